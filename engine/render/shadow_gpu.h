/* vergence — the sun and its shadow map, one module: the cascades set up on
 * the CPU each frame (shadow_gpu_setup: the sun, two cascades in one atlas,
 * docs/architecture.md "Lighting"; shade.glsl reads them) and the passes
 * `shadow.static`, `shadow.copy` and `shadow` that draw them into
 * res->shadow. */
#pragma once
#include "pass/frame_ctx.h"

struct vg_frame_ubo;
typedef struct shadow_gpu shadow_gpu;

typedef struct shadow_gpu_desc {
    uint32_t size;               /* a cascade's side in texels (the atlas is VG_SHADOW_CASCADES wide) */
} shadow_gpu_desc;

vg_status shadow_gpu_create(frame_ctx *fc, const shadow_gpu_desc *desc, shadow_gpu **out);
void shadow_gpu_destroy(shadow_gpu *p);
/* The sun, the sky's colours and the cascades of this frame into the frame
 * constants; sets fc->shadow_cascades. */
void shadow_gpu_setup(shadow_gpu *p, struct vg_frame_ubo *u);
/* Declares res->shadow and the passes that draw it. */
void shadow_gpu_add(shadow_gpu *p, rg_graph *g, frame_resources *res);
/* Binds the cache (imported) to the compiled graph g. */
void shadow_gpu_bind(shadow_gpu *p, rg_graph *g);
