/* vergence — compose: the two eyes into one output image (DESIGN.md step 10). */
#pragma once
#include "pass/frame_ctx.h"

typedef struct compose_gpu compose_gpu;

typedef struct compose_gpu_desc {
    frame_compose compose;       /* the layout (FRAME_COMPOSE_DEFAULT: side by side) */
    bool swap_eyes;
} compose_gpu_desc;

vg_status compose_gpu_create(frame_ctx *fc, const compose_gpu_desc *desc, compose_gpu **out);
void compose_gpu_destroy(compose_gpu *c);
/* Reads res->left and res->right; fills res->stereo. */
void compose_gpu_add(compose_gpu *c, rg_graph *g, frame_resources *res);
