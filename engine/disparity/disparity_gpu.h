/* vergence — the disparity passes of the frame on the GPU (DESIGN.md steps
 * 3-8), beside their CPU reference in this folder.
 *
 *   disparity.original  g from the G-buffer's linear depth (stereo rig + display)
 *
 * Reads res->depth; fills res->g (R32F, arcmin). */
#pragma once
#include "render/frame_ctx.h"

typedef struct disparity_gpu disparity_gpu;

vg_status disparity_gpu_create(frame_ctx *fc, disparity_gpu **out);
void disparity_gpu_destroy(disparity_gpu *d);
void disparity_gpu_add(disparity_gpu *d, rg_graph *g, frame_resources *res);
/* Per-frame CPU work before the frame is recorded (frame_ctx holds the
 * slot, times and cameras of this frame). */
vg_status disparity_gpu_prepare(disparity_gpu *d);
