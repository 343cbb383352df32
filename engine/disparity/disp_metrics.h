/* vergence — quality metrics of a disparity video on a MID window, used by
 * every later issue (docs/method.md "Metrics").
 *
 * For a field x (h or f) on the keyframe samples of the window:
 *   MID distortion   RMS over moving pixels of the perceptual acceleration
 *                    error  e_i = [p(v+_x) - p(v-_x)] - [p(v+_g) - p(v-_g)]  (JND),
 *                    velocities along the window's flow links; a pixel moves
 *                    when g's velocity on a valid link reaches moving_threshold;
 *                    e needs both links valid
 *   range violation  fraction of samples outside the target range (+- 1e-3 arcmin)
 *   static RMS       RMS of x - h over the static (not moving) pixels, arcmin
 *   static gradient  RMS over static pixels of |grad (x - h)| (forward differences), arcmin/px
 * Samples of unknown g (w->unknown) are left out of all four. */
#pragma once
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

#include "mid_window.h"

typedef struct disp_metrics {
    double mid_distortion_jnd;
    double range_violation;
    double static_rms;
    double static_grad_rms;
    int moving, moving_measured, static_count, samples;
} disp_metrics;

typedef struct disp_metrics_desc {
    float moving_threshold; /* arcmin/s, 0 = 1 */
} disp_metrics_desc;

void disp_metrics_window(const mid_window *w, const float *x, const disp_metrics_desc *desc,
                         disp_metrics *out);
/* The metrics of a field as the JSON files write them (metrics.json,
 * capture.json): the members of the object the caller opened. */
struct vg_json;
void disp_metrics_write_json(struct vg_json *j, const disp_metrics *m, double range_violation);

/* The temporal end-point error of a field x against g at full resolution
 * (TEPE, Karaev et al., "DynamicStereo", CVPR 2023): per pixel, how x's
 * error e = x - g changes from one frame to the next, |e_t - e_(t-1)|, and
 * its acceleration variant, |e_(t+1) - 2 e_t + e_(t-1)|, in arcmin,
 * averaged over the pixels visible in every frame involved: g known there
 * and the same surface (depths within `same_surface` of each other, as the
 * solver's occlusion test). x = g gives 0; an x that moves in depth as g
 * does, offset or not, gives 0 too. Fed frame by frame, in order. */
typedef struct disp_tepe {
    size_t n;                 /* pixels of a frame */
    float same_surface;       /* relative depth difference of one surface */
    float *e[2], *z[2];       /* the last two frames' error and depth (NaN where g is unknown) */
    int frames;               /* frames fed */
    double sum_v, sum_a;
    long count_v, count_a;
} disp_tepe;

vg_status disp_tepe_init(disp_tepe *t, size_t n, float same_surface);
/* Frame after frame: x, g and depth z (metres) of n pixels; unknown (NULL:
 * none) marks pixels of unknown g. */
void disp_tepe_frame(disp_tepe *t, const float *x, const float *g, const float *z, const uint8_t *unknown);
/* A new shot: the next frame has no earlier one to differ from. */
void disp_tepe_restart(disp_tepe *t);
/* The means so far (NAN before a pixel was measured), and its pixels. */
double disp_tepe_velocity(const disp_tepe *t);
double disp_tepe_accel(const disp_tepe *t);
void disp_tepe_free(disp_tepe *t);

/* In the target range [lo, hi] up to 1e-3 arcmin (float rounding of the clamp). */
static inline bool disp_metrics_in_range(float x, float lo, float hi)
{
    return x >= lo - 1e-3f && x <= hi + 1e-3f;
}
