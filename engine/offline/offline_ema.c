/* vergence — `optimize --operator ema`: the baseline the stereo converters
 * use against flicker (nunif's iw3, depth_scaler.py, EMAMinMaxScaler with
 * WindowEMAScaler's settings). Each frame's range of known g is recorded in
 * pass A; the ranges are smoothed once every frame was read; h maps g
 * linearly from its frame's smoothed range onto the target range. */
#include "offline_internal.h"

#include <math.h>
#include <stdlib.h>

vg_status offline_ema_record(offline_seq *s, int t, double lo, double hi)
{
    int k = t - s->desc->first;
    if (!s->ema && !(s->ema = malloc((size_t)s->frames * sizeof *s->ema)))
        return VG_ERR_NOMEM;
    /* A frame without known g keeps its neighbour's range (set when smoothed). */
    s->ema[k] = (struct offline_range){isfinite(lo) ? (float)lo : NAN, isfinite(hi) ? (float)hi : NAN};
    return VG_OK;
}

/* nunif's iw3 (depth_scaler.py, EMAMinMaxScaler): frame t's range is the
 * min and max over frames t .. t + window - 1 (its look-ahead queue; here
 * within the shot), then v_t = decay v_(t-1) + (1 - decay) window_t, from
 * the first frame's window at each shot's start (iw3 resets at scene cuts). */
vg_status offline_ema_ranges(offline_seq *s)
{
    const offline_desc *d = s->desc;
    int n = s->frames, window = d->ema_window > 0 ? d->ema_window : 30;
    double decay = d->ema_decay > 0 ? d->ema_decay : 0.9;
    float *lo = malloc((size_t)n * sizeof *lo), *hi = malloc((size_t)n * sizeof *hi);
    if (!lo || !hi) {
        free(lo);
        free(hi);
        return VG_ERR_NOMEM;
    }
    for (int k = 0; k < n; k++) { /* unknown frames: the nearest known before */
        if (isnan(s->ema[k].lo))
            s->ema[k].lo = k ? s->ema[k - 1].lo : (float)s->g_min;
        if (isnan(s->ema[k].hi))
            s->ema[k].hi = k ? s->ema[k - 1].hi : (float)s->g_max;
    }
    int shot_end = n; /* exclusive, of the shot frame k is in */
    for (int k = n - 1; k >= 0; k--) {
        if (k + 1 < n && offline_is_cut(s, d->first + k + 1))
            shot_end = k + 1;
        lo[k] = s->ema[k].lo, hi[k] = s->ema[k].hi;
        for (int j = k + 1; j < k + window && j < shot_end; j++)
            lo[k] = fminf(lo[k], s->ema[j].lo), hi[k] = fmaxf(hi[k], s->ema[j].hi);
    }
    for (int k = 0; k < n; k++) {
        bool start = k == 0 || offline_is_cut(s, d->first + k);
        s->ema[k].lo = start ? lo[k] : (float)(decay * s->ema[k - 1].lo + (1 - decay) * lo[k]);
        s->ema[k].hi = start ? hi[k] : (float)(decay * s->ema[k - 1].hi + (1 - decay) * hi[k]);
    }
    free(lo);
    free(hi);
    return VG_OK;
}

/* h of frame t: g from its smoothed range onto the target range, clamped. */
void offline_ema_apply(const offline_seq *s, int t, const float *g, float *h)
{
    int k = t - s->desc->first;
    float lo = s->ema[k].lo, span = s->ema[k].hi - lo, out_lo = (float)s->range_lo;
    float out_span = (float)(s->range_hi - s->range_lo);
    for (int i = 0; i < s->width * s->height; i++) {
        float u = span > 0 ? (g[i] - lo) / span : 0.5f;
        h[i] = out_lo + out_span * fminf(fmaxf(u, 0.0f), 1.0f);
    }
}
