/* vergence — the science metrics (disp_metrics.c) over frames the GPU
 * pipeline produced: `vergence capture` adds them to capture.json, the tests
 * and the bench read them. Like `vergence optimize` (docs/method.md Sec. 11):
 * a MID window over the captured keyframes (coarse samples of g, h, depth
 * and the G-buffer's exact motion to the neighbouring keyframes), h and f
 * point-sampled at the keyframes (so upsampling errors count), range
 * violations over every full-resolution pixel of every frame. Also the
 * temporal second difference of f at keyframe boundaries and between them
 * (a pop at a boundary shows there). */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "core/status.h"
#include "disparity/disp_metrics.h"
#include "disparity/gpu/disparity_gpu.h"

typedef struct science_metrics_desc {
    uint32_t width, height, stride;  /* frames and the solver's coarse stride */
    int keyframe_stride;
    double fps;
    double range_lo, range_hi;       /* target range (arcmin) */
    bool hull;                       /* operator none: the range also holds each frame's g */
    int max_keyframes;               /* window capacity, 0 = 256 */
} science_metrics_desc;

/* Mean |f(t+1) - 2 f(t) + f(t-1)| over pixels that show the same instance in
 * all three frames, at frames next to a keyframe boundary (t or t + 1 a
 * keyframe) and at the others; and, to see a kink of the interpolation in
 * time, at keyframes (t a keyframe) and at the frames either side of them. */
typedef struct science_second_difference {
    double boundary, between, at_key, next_to_key;
    int boundary_frames, between_frames, key_frames, next_frames;
} science_second_difference;

typedef struct science_metrics_result {
    disp_metrics h, f;
    double h_range_violation, f_range_violation; /* over every pixel of every frame */
    science_second_difference f_d2, h_d2;
    science_second_difference c_d2; /* of the correction f - h: what the pipeline adds to h */
    int keyframes;              /* of the MID window; 0 when keyframes_missing */
    int keyframes_missing;      /* keyframes between the first and the last that were not added: no MID */
    double range_lo, range_hi;
} science_metrics_result;

typedef struct science_metrics science_metrics;

vg_status science_metrics_create(const science_metrics_desc *desc, science_metrics **out);
/* The metrics of a frame's outputs: its size, keyframes, grid and target
 * range (for `none`, which keeps g, the range also holds each frame's g).
 * VG_ERR_ARG for a frame without the disparity pipeline. */
struct frame;
vg_status science_metrics_create_for(const struct frame *f, science_metrics **out);
void science_metrics_destroy(science_metrics *m);
/* One frame (absolute index). motion: 4 floats per pixel (px to the previous
 * keyframe, to the next). Frames may skip indices: second differences come
 * from consecutive frames only, and MID needs every keyframe between the
 * first and the last; an index added again is ignored. */
void science_metrics_add(science_metrics *m, long index, const float *g, const float *h, const float *f, const float *depth,
                     const float *motion, const uint32_t *ids);
/* One keyframe as the solve saw it (disparity_gpu_keyframe_read): the MID
 * window's samples from the store and the published f instead of from a
 * rendered frame (a metrics object takes keyframes from one source). */
void science_metrics_add_keyframe(science_metrics *m, long keyframe, const disparity_gpu_keyframe *k);
/* The metrics over the frames added (needs at least 3 keyframes for MID). */
vg_status science_metrics_finish(science_metrics *m, science_metrics_result *out);
