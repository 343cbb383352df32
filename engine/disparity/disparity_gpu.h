/* vergence — the disparity passes of the frame on the GPU (DESIGN.md steps
 * 3-7), beside their CPU reference in this folder:
 *
 *   disparity.original      g from the G-buffer's linear depth (stereo rig + display)
 *   disparity.operator.fit  the operator's mapping from the frame's coarse samples
 *   disparity.operator      h = M(g, saliency) per pixel
 *   mid.keyframes           the keyframe entering the window, rendered at coarse
 *                           resolution at its (future) time
 *   mid.keyframes.fit/store its own mapping; g, h, depth, flows into the store
 *   mid.window              when the window moves: links, CSR, targets, chains
 *   mid.solve               this frame's share of the window's solve (warm start,
 *                           amortised over the keyframe interval), then publish
 *   mid.upsample.time/space f for this frame from the published keyframe ratios
 *
 * Reads res->depth, color (saliency), motion; fills res->g, h, f (R32F, arcmin).
 * The window (paper 4.5: "previous frames combined with a prediction of future
 * frames") holds keyframes from history and predicted ones; docs/method.md
 * "GPU passes" has the timeline. */
#pragma once
#include "render/frame_ctx.h"

typedef struct disparity_gpu disparity_gpu;

/* Resolves the frame_desc fields of the disparity pipeline in fc->desc. */
vg_status disparity_gpu_create(frame_ctx *fc, disparity_gpu **out);
void disparity_gpu_destroy(disparity_gpu *d);
void disparity_gpu_add(disparity_gpu *d, rg_graph *g, frame_resources *res);
/* Per-frame CPU work before the frame is recorded (frame_ctx holds the
 * slot, times and cameras of this frame): which keyframes to render, which
 * part of the solve runs, where the frame is between its keyframes. */
vg_status disparity_gpu_prepare(disparity_gpu *d);

/* The stride of the solver's grid for a frame size: coarse_stride (0 = 5),
 * widened until the grid is at most 192 x 108 (paper 4.5: the solve's
 * resolution is chosen by content, so its time does not grow with the
 * output's). */
uint32_t disparity_gpu_grid_stride(uint32_t width, uint32_t height, int coarse_stride);

/* The solver's grid and window, as resolved (for reports). */
typedef struct disparity_gpu_info {
    uint32_t stride, nx, ny;      /* coarse grid */
    int past, future;             /* keyframes of the window behind and ahead of the frame */
    double range_lo, range_hi;    /* target range, arcmin */
    int items;                    /* steps of the current window's solve */
} disparity_gpu_info;
void disparity_gpu_get_info(const disparity_gpu *d, disparity_gpu_info *info);
