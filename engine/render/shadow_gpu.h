/* vergence — the sun and its shadow map, one module: the cascades set up on
 * the CPU each frame (shadow_gpu_setup: the sun, two cascades in one atlas,
 * docs/architecture.md "Lighting"; shade.glsl reads them) and the passes
 * `shadow.static`, `shadow.copy` and `shadow` that draw them into
 * res->shadow. */
#pragma once
#include "frame_ctx.h"

struct vg_frame_ubo;
typedef struct shadow_gpu shadow_gpu;

vg_status shadow_gpu_create(frame_ctx *fc, shadow_gpu **out);
void shadow_gpu_destroy(shadow_gpu *p);
/* The sun, the sky's colours and the cascades of this frame into the frame
 * constants; sets fc->shadow_cascades. */
void shadow_gpu_setup(frame_ctx *fc, struct vg_frame_ubo *u);
/* Declares res->shadow and the passes that draw it. */
void shadow_gpu_add(shadow_gpu *p, rg_graph *g, frame_resources *res);
/* Binds the cache (imported) to the compiled graph g. */
void shadow_gpu_bind(shadow_gpu *p, rg_graph *g);
