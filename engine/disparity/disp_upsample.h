/* vergence — from the coarse keyframe solution to full-resolution frames
 * (paper Sec. 4.4, Fig. 4). Only the correction is upsampled: the ratio
 * r = f / h (vergence is never 0, DESIGN.md), so f = h * r keeps every fine
 * detail of the full-resolution h.
 *   Time:  r at the coarse samples of frame t from the two nearest keyframes,
 *          along the flow, by cubic Hermite on their ratios and slopes; a
 *          keyframe whose sample fails the depth test (occlusion) or left
 *          the frame drops out.
 *   Space: joint bilateral upsampling (Kopf et al. 2007) of r, guided by the
 *          full-resolution h of frame t; then f = clamp(h r, target range).
 * Equations: docs/method.md "Upsampling". */
#pragma once
#include <stdbool.h>

#include "core/parallel.h"

/* The coarse grid of a full-resolution frame: sample (qx, qy) is the
 * full-resolution pixel (min(qx s + s/2, W - 1), min(qy s + s/2, H - 1)), a
 * point sample at the block centre (no blending across depth edges). */
typedef struct disp_grid {
    int full_w, full_h, stride, nx, ny;
} disp_grid;

void disp_grid_init(disp_grid *g, int full_w, int full_h, int stride);
static inline int disp_grid_px(const disp_grid *g, int qx)
{
    int x = qx * g->stride + g->stride / 2;
    return x < g->full_w ? x : g->full_w - 1;
}
static inline int disp_grid_py(const disp_grid *g, int qy)
{
    int y = qy * g->stride + g->stride / 2;
    return y < g->full_h ? y : g->full_h - 1;
}
/* Point samples of a full-resolution field (channels interleaved). */
void disp_grid_sample(const disp_grid *g, const float *full, int channels, float *coarse);
/* Full-resolution positions of the coarse samples (2 floats each). */
void disp_grid_positions(const disp_grid *g, float *pos);

/* Moves positions (full-resolution pixels, 2 floats each) along one
 * per-frame flow field (bilinear); a position that leaves the frame, or is
 * NaN, becomes NaN. Composes per-frame flows into keyframe flows. */
void disp_flow_advect(const float *flow, int w, int h, float *pos, int count);

typedef struct disp_upsample_desc {
    disp_grid grid;
    float occlusion_tolerance; /* relative depth, 0 = MID_OCCLUSION_TOLERANCE */
    float sigma_spatial;       /* coarse pixels, 0 = 0.5 */
    float sigma_range;         /* arcmin, 0 = 4 */
    float range_lo, range_hi;  /* clamp of f; both 0 = none */
    bool depth_only;           /* occlusion in time by depth alone (paper 4.4), not the links' test */
} disp_upsample_desc;

/* One keyframe as frame t sees it (coarse arrays of the keyframe). */
typedef struct disp_keyframe_view {
    const float *pos;   /* where frame t's coarse samples are in it (full-resolution px, 2 floats; NaN lost) */
    const float *ratio; /* the correction m = f / g (f / h: pass no g, h, g_t, h_t) */
    const float *slope; /* dm/dt along the motion, per second (mid_window_ratio_slopes); NULL: linear */
    const float *depth;
    const float *id;    /* instance ids (0: sky); NULL: all 0 (sequences from files without ids) */
    const float *flow;  /* coarse px to the interval's other keyframe (k0: forward, k1: backward); NULL: none */
    const float *g, *h; /* the keyframe's g and h: its ratio f / h where no tap is the sample's surface; NULL: m */
} disp_keyframe_view;

/* Time. tau = (t - t0) / (t1 - t0), span = t1 - t0 in seconds; depth_t,
 * id_t: coarse depth and instance ids of frame t (id_t NULL: all 0); k1 may
 * be NULL (no later keyframe, or tau = 0). A keyframe tap counts when it is
 * the sample's surface as the solver's links decide it: the same instance,
 * and the depth test or the trajectory test (mid_on_trajectory: the tap's
 * flow to the other keyframe lands where the sample is there). The keyframes'
 * corrections m = f / g by cubic Hermite in time when both have slopes (C1
 * at keyframes), else linearly; applied to frame t's coarse g_t and h_t,
 * ratio_t = m g_t / h_t (mid_ratio_to_h: f follows the original's motion
 * between keyframes). g_t and h_t NULL: ratio_t is m. Where only one
 * keyframe has taps on the sample's surface, that keyframe's own f / h (the
 * views' g and h); where neither has, the nearer one's f / h whatever surface
 * it shows. */
void disp_upsample_temporal(const disp_upsample_desc *d, float tau, float span, const float *depth_t,
                            const float *id_t, const float *g_t, const float *h_t, const disp_keyframe_view *k0,
                            const disp_keyframe_view *k1, float *ratio_t, vg_pool *pool);

/* Space. f_full = clamp(h_full * JBU(ratio_coarse; guide h_full)). */
void disp_upsample_spatial(const disp_upsample_desc *d, const float *h_full,
                           const float *ratio_coarse, float *f_full, vg_pool *pool);
