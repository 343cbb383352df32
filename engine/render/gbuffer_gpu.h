/* vergence — the scene passes of the centre eye: sun shadow map and G-buffer
 * (DESIGN.md step 2). Adds `shadow` and `gbuffer`; fills res->shadow,
 * color, depth, ids, motion, zbuffer. */
#pragma once
#include "frame_ctx.h"

typedef struct gbuffer_gpu gbuffer_gpu;

vg_status gbuffer_gpu_create(frame_ctx *fc, gbuffer_gpu **out);
void gbuffer_gpu_destroy(gbuffer_gpu *p);
void gbuffer_gpu_add(gbuffer_gpu *p, rg_graph *g, frame_resources *res);

/* Formats of the G-buffer colour attachments, in shader output order. */
extern const VkFormat gbuffer_formats[4];
#define GBUFFER_DEPTH_FORMAT VK_FORMAT_D32_SFLOAT
