/* vergence — the frame loop of `vergence capture` and of each run of
 * `vergence demo`, and what it records: every pass's ms (matched by name:
 * the list can change between frames), the CPU ms of each frame, its camera
 * and times, the stereo pair's accuracy against the reference (warp_metrics)
 * and the science metrics of h and f (science_metrics). capture_json.h
 * writes the record. */
#pragma once
#include <stdbool.h>

#include "frame/frame.h"
#include "frame/science_metrics.h"
#include "frame/warp_metrics.h"

#define CAPTURE_PASS_NAME 64

typedef struct capture_log_desc {
    int frames;                  /* at most this many are recorded */
    bool science;                /* the MID metrics of h and f (stereo frames only) */
    bool warp;                   /* the pair against the two-camera reference, every frame */
} capture_log_desc;

typedef struct capture_log {
    int capacity, frames;
    uint32_t pass_count;
    char pass_names[RG_MAX_PASSES][CAPTURE_PASS_NAME];
    double *pass_ms;             /* frames x RG_MAX_PASSES, NAN where a pass did not run */
    double *cpu_ms;              /* frames: frame_render's wall time */
    vg_camera *cameras;          /* frames */
    frame_times *times;          /* frames */
    uint32_t shadow_map_px;      /* the shadow map's size (the frame's, resolved) */
    double *shadow_m;            /* frames x 3: the shadow cascades' texels in metres (whole scene, near) and
                                    the split depth (0: one cascade) */
    double *shadow_px;           /* frames: the shadow texel in screen pixels where it lands (median over the
                                    geometry's pixels; NAN without the depth read back) */
    bool warp_every_frame;
    warp_metrics warp;
    science_metrics *science;    /* NULL unless asked for and the frame has the disparity pipeline */
    science_metrics_result result;
    frame_info info;
} capture_log;

vg_status capture_log_begin(capture_log *log, const frame *f, const capture_log_desc *desc);
/* Renders frame `index` of f (timed) and records it; the outputs are the frame's. */
vg_status capture_log_render(capture_log *log, frame *f, long index);
/* After the last frame: the warp's and the science figures. */
vg_status capture_log_finish(capture_log *log);
void capture_log_free(capture_log *log);

/* Medians over the recorded frames (NAN when a pass never ran). */
double capture_log_pass_median(const capture_log *log, uint32_t pass);
double capture_log_frame_median(const capture_log *log);
/* The shadow over the frames (medians): each cascade's texel in metres, the split depth, screen pixels. */
void capture_log_shadow(const capture_log *log, double texel_m[2], double *split_m, double *texel_px);
