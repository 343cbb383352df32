/* vergence — what the engine's own frame asks of the SDK beyond the public
 * API (include/vergence/vergence.h): the tuning its command line exposes
 * (grid stride, solver, the temporal occlusion test, keyframe readback),
 * the frame-in-flight slot of its timestamps, and its science metrics'
 * view of the solve's keyframes. Hosts never see it. */
#pragma once
#include "disparity/gpu/disparity_gpu.h"
#include "vergence/vergence.h"

/* vgx_context_create with the disparity pipeline's fields the public desc
 * does not name taken from tuning (coarse_stride, window_future, solver,
 * solver_iterations, temporal_depth_only, readback; zero = the SDK's). */
vgx_result vgx_engine_context_create(const vgx_context_desc *desc, const disparity_gpu_desc *tuning,
                                     vgx_context **out);
/* vgx_begin_frame with the engine's slot (RG_MAX_SLOTS) for the solve's timestamps. */
vgx_result vgx_engine_begin_frame(vgx_context *c, int64_t frame_index, int slot, vgx_frame_plan *plan);
/* The engine's status of a result (the inverse of the SDK's own mapping). */
vg_status vgx_engine_status(vgx_result r);
/* The pipeline behind the context (keyframe readback, its info). */
disparity_gpu *vgx_engine_disparity(const vgx_context *c);
