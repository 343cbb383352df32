/* vergence — the scene pass of the centre eye: the G-buffer (DESIGN.md
 * step 2), shaded with the sun's shadow map (res->shadow, shadow_gpu.h).
 * Adds `gbuffer`; fills res->color, depth, ids, motion, zbuffer. */
#pragma once
#include "pass/frame_ctx.h"

typedef struct gbuffer_gpu gbuffer_gpu;

typedef struct gbuffer_gpu_desc {
    bool lit;                    /* the centre colour shaded (else only what the disparity passes read) */
} gbuffer_gpu_desc;

vg_status gbuffer_gpu_create(frame_ctx *fc, const gbuffer_gpu_desc *desc, gbuffer_gpu **out);
void gbuffer_gpu_destroy(gbuffer_gpu *p);
void gbuffer_gpu_add(gbuffer_gpu *p, rg_graph *g, frame_resources *res);

/* The G-buffer's attachments: colour (sRGB, saliency in alpha), linear
 * depth, instance ids, motion to the neighbouring keyframes, z-buffer. */
typedef struct gbuffer_targets {
    rg_res color, depth, ids, motion, zbuffer;
} gbuffer_targets;
/* Declares them as transient images "<prefix>.color", ... of w x h. */
gbuffer_targets gbuffer_gpu_targets(rg_graph *g, const char *prefix, uint32_t w, uint32_t h);
/* Pass p writes them (in shader output order; the z-buffer cleared). */
void gbuffer_gpu_targets_write(rg_graph *g, rg_pass p, const gbuffer_targets *t);
/* The sky and scene pipelines that fill them (lit: shaded colour, else
 * only what the disparity passes read), for the scene layout of fc. */
vg_status gbuffer_gpu_pipelines_create(frame_ctx *fc, const char *name, bool lit, VkPipeline *sky, VkPipeline *scene);

/* Formats of the G-buffer colour attachments, in shader output order. */
extern const VkFormat gbuffer_formats[4];
#define GBUFFER_DEPTH_FORMAT VK_FORMAT_D32_SFLOAT
