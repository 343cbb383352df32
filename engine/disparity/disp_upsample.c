#include "disp_upsample.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "mid_shared.h"

/* Rows of full-resolution pixels per block of the spatial pass. */
#define ROWS_PER_BLOCK 8

/* ------------------------------------------------------------------------- */
/* Grid and flow                                                             */
/* ------------------------------------------------------------------------- */

void disp_grid_init(disp_grid *g, int full_w, int full_h, int stride)
{
    g->full_w = full_w;
    g->full_h = full_h;
    g->stride = stride > 0 ? stride : 5;
    g->nx = (full_w + g->stride - 1) / g->stride;
    g->ny = (full_h + g->stride - 1) / g->stride;
}

void disp_grid_sample(const disp_grid *g, const float *full, int channels, float *coarse)
{
    for (int qy = 0; qy < g->ny; qy++)
        for (int qx = 0; qx < g->nx; qx++) {
            size_t src = ((size_t)disp_grid_py(g, qy) * g->full_w + disp_grid_px(g, qx)) * channels;
            size_t dst = ((size_t)qy * g->nx + qx) * channels;
            for (int c = 0; c < channels; c++)
                coarse[dst + c] = full[src + c];
        }
}

void disp_grid_positions(const disp_grid *g, float *pos)
{
    for (int qy = 0; qy < g->ny; qy++)
        for (int qx = 0; qx < g->nx; qx++) {
            pos[2 * (qy * g->nx + qx)] = (float)disp_grid_px(g, qx);
            pos[2 * (qy * g->nx + qx) + 1] = (float)disp_grid_py(g, qy);
        }
}

void disp_flow_advect(const float *flow, int w, int h, float *pos, int count)
{
    for (int i = 0; i < count; i++) {
        float x = pos[2 * i], y = pos[2 * i + 1];
        if (!(x >= 0.0f && x <= (float)(w - 1) && y >= 0.0f && y <= (float)(h - 1))) {
            pos[2 * i] = pos[2 * i + 1] = NAN;
            continue;
        }
        int x0 = (int)x, y0 = (int)y;
        int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
        float fx = x - (float)x0, fy = y - (float)y0;
        for (int c = 0; c < 2; c++) {
            float a = flow[((size_t)y0 * w + x0) * 2 + c], b = flow[((size_t)y0 * w + x1) * 2 + c];
            float e = flow[((size_t)y1 * w + x0) * 2 + c], d = flow[((size_t)y1 * w + x1) * 2 + c];
            float v = (1 - fy) * ((1 - fx) * a + fx * b) + fy * ((1 - fx) * e + fx * d);
            pos[2 * i + c] += v;
        }
        x = pos[2 * i];
        y = pos[2 * i + 1];
        /* Half a pixel of slack at the border, as for the window's links. */
        if (!(x >= -0.5f && x <= (float)w - 0.5f && y >= -0.5f && y <= (float)h - 0.5f))
            pos[2 * i] = pos[2 * i + 1] = NAN;
        else {
            pos[2 * i] = fminf(fmaxf(x, 0.0f), (float)(w - 1));
            pos[2 * i + 1] = fminf(fmaxf(y, 0.0f), (float)(h - 1));
        }
    }
}

/* ------------------------------------------------------------------------- */
/* Time                                                                      */
/* ------------------------------------------------------------------------- */

typedef struct keyframe_sample {
    float ratio, slope; /* the correction f / g and its slope */
    float ratio_h;      /* f / h (the view's g and h; without them, f / g) */
    float weight; /* bilinear weight of the taps on the sample's surface */
} keyframe_sample;

/* The keyframe's ratio and slope at a full-resolution position: bilinear
 * over the coarse samples, keeping only taps on the sample's surface (with
 * `test`): its instance id, and its depth or its trajectory (the position
 * `other` of the sample in the interval's other keyframe, full-resolution
 * px, NaN when lost or none). */
static keyframe_sample sample_keyframe(const disp_grid *g, float px, float py, float z, float id,
                                       const float *other, const disp_keyframe_view *k, float log_tol, bool test,
                                       bool depth_only)
{
    keyframe_sample s = {1.0f, 0.0f, 1.0f, 0.0f};
    if (isnan(px) || isnan(py))
        return s;
    float s2 = (float)(g->stride / 2);
    float cx = fminf(fmaxf((px - s2) / (float)g->stride, 0.0f), (float)(g->nx - 1));
    float cy = fminf(fmaxf((py - s2) / (float)g->stride, 0.0f), (float)(g->ny - 1));
    int x0 = (int)cx, y0 = (int)cy;
    float fx = cx - (float)x0, fy = cy - (float)y0;
    float acc = 0.0f, sacc = 0.0f, racc = 0.0f, wsum = 0.0f;
    for (int t = 0; t < 4; t++) {
        int x = x0 + (t & 1), y = y0 + (t >> 1);
        float w = ((t & 1) ? fx : 1 - fx) * ((t >> 1) ? fy : 1 - fy);
        if (w <= 0.0f || x >= g->nx || y >= g->ny)
            continue;
        int q = y * g->nx + x;
        if (test) {
            bool same_depth = z > 0.0f && k->depth[q] > 0.0f && fabsf(logf(k->depth[q] / z)) <= log_tol;
            bool on_path = k->flow && other && !isnan(other[0]) &&
                           mid_on_trajectory((float)x, (float)y, k->flow[2 * q], k->flow[2 * q + 1],
                                             (other[0] - s2) / (float)g->stride, (other[1] - s2) / (float)g->stride);
            bool keep = depth_only ? same_depth : (k->id ? k->id[q] : 0.0f) == id && (same_depth || on_path);
            if (!keep)
                continue;
        }
        acc += w * k->ratio[q];
        sacc += w * (k->slope ? k->slope[q] : 0.0f);
        racc += w * (k->g && k->h ? mid_ratio_to_h(k->ratio[q], k->g[q], k->h[q]) : k->ratio[q]);
        wsum += w;
    }
    if (wsum > 0.0f) {
        s.ratio = acc / wsum;
        s.slope = sacc / wsum;
        s.ratio_h = racc / wsum;
    }
    s.weight = wsum;
    return s;
}

typedef struct time_ctx {
    const disp_upsample_desc *d;
    float tau, span, log_tol;
    const float *depth_t, *id_t, *g_t, *h_t;
    const disp_keyframe_view *k0, *k1;
    float *out;
} time_ctx;

/* The ratio f / h of frame t at sample q from the correction m. */
static float to_h(const time_ctx *x, int q, float m)
{
    return x->g_t && x->h_t ? mid_ratio_to_h(m, x->g_t[q], x->h_t[q]) : m;
}

static void temporal_block(void *c, int block, int begin, int end)
{
    (void)block;
    time_ctx *x = c;
    const disp_grid *g = &x->d->grid;
    const disp_keyframe_view *k0 = x->k0, *k1 = x->k1;
    for (int q = begin; q < end; q++) {
        float z = x->depth_t[q], id = x->id_t ? x->id_t[q] : 0.0f;
        /* At a keyframe (no k1) the sample itself: depth and id alone. */
        const float *at0 = k0->pos + 2 * q, *at1 = k1 && x->tau > 0.0f ? k1->pos + 2 * q : NULL;
        keyframe_sample a = sample_keyframe(g, at0[0], at0[1], z, id, at1, k0, x->log_tol, true, x->d->depth_only);
        keyframe_sample b = {1.0f, 0.0f, 1.0f, 0.0f};
        if (at1)
            b = sample_keyframe(g, at1[0], at1[1], z, id, at0, k1, x->log_tol, true, x->d->depth_only);
        /* Fig. 4: interpolate f / g along the flow in time, by cubic Hermite
         * with the keyframes' slopes (C1 at keyframes), or linearly without
         * them, and apply it to frame t's g; a keyframe none of whose taps
         * is the sample's surface (occluded), or out of frame, drops out.
         * One tap of the surface is enough: with the links' ½ of the
         * weight, the edge of a ball that shrinks between keyframes lost
         * the later keyframe and followed h (docs/method.md §8). */
        bool ok0 = a.weight > 0.0f && x->tau < 1.0f;
        bool ok1 = b.weight > 0.0f && x->tau > 0.0f;
        if (ok0 && ok1) {
            float m = k0->slope && k1->slope ? mid_hermite(a.ratio, a.slope, b.ratio, b.slope, x->tau, x->span)
                                             : (1.0f - x->tau) * a.ratio + x->tau * b.ratio;
            x->out[q] = to_h(x, q, m);
            continue;
        }
        if (ok0 && x->tau == 0.0f) { /* at the keyframe itself: its f / g on this frame's g, as either side */
            x->out[q] = to_h(x, q, a.ratio);
            continue;
        }
        /* One keyframe alone: its f / h (a constant f / g would hold the
         * manipulation's change over the interval). */
        if (ok0 || ok1) {
            x->out[q] = ok0 ? a.ratio_h : b.ratio_h;
            continue;
        }
        /* Both lost (disocclusion, or out of frame for both): the temporally
         * nearer keyframe's ratio f / h at the tracked position, else at the
         * sample itself, whatever surface it shows there. */
        bool near0 = x->tau < 0.5f || !k1;
        const disp_keyframe_view *k = near0 ? k0 : k1;
        float px = k->pos[2 * q], py = k->pos[2 * q + 1];
        if (isnan(px) || isnan(py)) {
            px = (float)disp_grid_px(g, q % g->nx);
            py = (float)disp_grid_py(g, q / g->nx);
        }
        x->out[q] = sample_keyframe(g, px, py, z, id, NULL, k, x->log_tol, false, false).ratio_h;
    }
}

void disp_upsample_temporal(const disp_upsample_desc *d, float tau, float span, const float *depth_t,
                            const float *id_t, const float *g_t, const float *h_t, const disp_keyframe_view *k0,
                            const disp_keyframe_view *k1, float *ratio_t, vg_pool *pool)
{
    float tol = d->occlusion_tolerance > 0 ? d->occlusion_tolerance : MID_OCCLUSION_TOLERANCE;
    time_ctx c = {.d = d, .tau = tau, .span = span, .log_tol = logf(1.0f + tol), .depth_t = depth_t, .id_t = id_t,
                  .g_t = g_t, .h_t = h_t, .k0 = k0, .k1 = k1, .out = ratio_t};
    vg_parallel_for(pool, d->grid.nx * d->grid.ny, MID_BLOCK, temporal_block, &c);
}

/* ------------------------------------------------------------------------- */
/* Space: joint bilateral upsampling                                         */
/* ------------------------------------------------------------------------- */

typedef struct space_ctx {
    const disp_upsample_desc *d;
    const float *h, *ratio;
    float *f;
    float inv_2ss, inv_2sr;
} space_ctx;

static void spatial_block(void *c, int block, int begin, int end)
{
    (void)block;
    space_ctx *x = c;
    const disp_grid *g = &x->d->grid;
    const float s2 = (float)(g->stride / 2), inv_s = 1.0f / (float)g->stride;
    bool clamp = x->d->range_hi > x->d->range_lo;
    for (int y = begin; y < end; y++)
        for (int px = 0; px < g->full_w; px++) {
            size_t i = (size_t)y * g->full_w + px;
            float hv = x->h[i];
            float cx = ((float)px - s2) * inv_s, cy = ((float)y - s2) * inv_s;
            /* The 2 x 2 coarse samples around the pixel: bilinear (tent)
             * weights times the range Gaussian on the guide, where the guide
             * of a coarse sample is h at its full-resolution pixel. The tent
             * makes the upsampling exact at the samples, where the solver
             * put its values (a Gaussian kernel blends a sample with its
             * neighbours: +0.05 of h's MID distortion on balloon). */
            float tx = fminf(fmaxf(cx, 0.0f), (float)(g->nx - 1)), ty = fminf(fmaxf(cy, 0.0f), (float)(g->ny - 1));
            int x0 = (int)floorf(tx), y0 = (int)floorf(ty);
            int x1 = x0 + 1 < g->nx ? x0 + 1 : x0, y1 = y0 + 1 < g->ny ? y0 + 1 : y0;
            float fx = tx - (float)x0, fy = ty - (float)y0, tacc = 0.0f, tsum = 0.0f;
            for (int t = 0; t < 4; t++) {
                int qx = t & 1 ? x1 : x0, qy = t & 2 ? y1 : y0;
                float b = (t & 1 ? fx : 1.0f - fx) * (t & 2 ? fy : 1.0f - fy);
                float dr = hv - x->h[(size_t)disp_grid_py(g, qy) * g->full_w + disp_grid_px(g, qx)];
                float w = b * expf(-dr * dr * x->inv_2sr);
                tacc += w * x->ratio[qy * g->nx + qx];
                tsum += w;
            }
            int bx = (int)floorf(cx) - 1, by = (int)floorf(cy) - 1;
            float acc = 0.0f, wsum = 0.0f, best_d = 1e30f, best_r = 1.0f;
            /* None of the four on this pixel's surface: the 4 x 4 coarse
             * neighbours, Kopf et al.'s spatial Gaussian on the coarse
             * distance times the range Gaussian. */
            for (int j = 0; j < 4 && tsum < MID_TENT_MIN_WEIGHT; j++) {
                int qy = by + j;
                if (qy < 0 || qy >= g->ny)
                    continue;
                for (int k = 0; k < 4; k++) {
                    int qx = bx + k;
                    if (qx < 0 || qx >= g->nx)
                        continue;
                    float dx = cx - (float)qx, dy = cy - (float)qy, d2 = dx * dx + dy * dy;
                    float gq = x->h[(size_t)disp_grid_py(g, qy) * g->full_w + disp_grid_px(g, qx)];
                    float dr = hv - gq;
                    float w = expf(-d2 * x->inv_2ss - dr * dr * x->inv_2sr);
                    float r = x->ratio[qy * g->nx + qx];
                    acc += w * r;
                    wsum += w;
                    if (d2 < best_d) {
                        best_d = d2;
                        best_r = r;
                    }
                }
            }
            /* No neighbour on this surface (a structure thinner than the
             * grid): the nearest sample's correction. */
            float ratio = tsum >= MID_TENT_MIN_WEIGHT ? tacc / tsum : wsum > 1e-20f ? acc / wsum : best_r;
            float f = hv * ratio;
            if (clamp)
                f = fminf(fmaxf(f, x->d->range_lo), x->d->range_hi);
            x->f[i] = f;
        }
}

void disp_upsample_spatial(const disp_upsample_desc *d, const float *h_full,
                           const float *ratio_coarse, float *f_full, vg_pool *pool)
{
    float ss = d->sigma_spatial > 0 ? d->sigma_spatial : MID_SIGMA_SPATIAL;
    float sr = d->sigma_range > 0 ? d->sigma_range : MID_SIGMA_RANGE;
    space_ctx c = {.d = d, .h = h_full, .ratio = ratio_coarse, .f = f_full,
                   .inv_2ss = 1.0f / (2.0f * ss * ss), .inv_2sr = 1.0f / (2.0f * sr * sr)};
    vg_parallel_for(pool, d->grid.full_h, ROWS_PER_BLOCK, spatial_block, &c);
}
