/* vergence — the scene passes of the centre eye: sun shadow map and G-buffer
 * (DESIGN.md step 2). Adds `shadow` and `gbuffer`; fills res->shadow,
 * color, depth, ids, motion, zbuffer. */
#pragma once
#include "frame_ctx.h"

typedef struct gbuffer_pass gbuffer_pass;

vg_status gbuffer_pass_create(frame_ctx *fc, gbuffer_pass **out);
void gbuffer_pass_destroy(gbuffer_pass *p);
void gbuffer_pass_add(gbuffer_pass *p, rg_graph *g, frame_resources *res);

/* Formats of the G-buffer colour attachments, in shader output order. */
extern const VkFormat gbuffer_formats[4];
#define GBUFFER_DEPTH_FORMAT VK_FORMAT_D32_SFLOAT
