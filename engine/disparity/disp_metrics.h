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

/* In the target range [lo, hi] up to 1e-3 arcmin (float rounding of the clamp). */
static inline bool disp_metrics_in_range(float x, float lo, float hi)
{
    return x >= lo - 1e-3f && x <= hi + 1e-3f;
}
