/* vergence — compose: the two eyes into one output image (DESIGN.md step 10). */
#pragma once
#include "render/frame_ctx.h"

typedef struct compose_gpu compose_gpu;

vg_status compose_gpu_create(frame_ctx *fc, compose_gpu **out);
void compose_gpu_destroy(compose_gpu *c);
/* Reads res->left and res->right; fills res->stereo. */
void compose_gpu_add(compose_gpu *c, rg_graph *g, frame_resources *res);
