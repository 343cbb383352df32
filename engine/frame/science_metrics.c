/* vergence — science metrics over the GPU pipeline's frames. */
#include "science_metrics.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "frame.h"
#include "disparity/disp_upsample.h"
#include "disparity/mid_window.h"

struct science_metrics {
    science_metrics_desc d;
    disp_grid grid;
    int ns, nt, cap;                   /* keyframes k0 .. k0 + nt - 1 of at most cap */
    long k0;                           /* the first keyframe's number (-1: none yet) */
    float *g, *h, *f, *z, *id, *ffw, *fbw;  /* keyframe samples (cap keyframes) */
    uint8_t *have;                     /* which keyframes of the span were added */
    long last_index;
    double g_lo, g_hi;                 /* the range the frames were measured in */
    double h_out, f_out, pixels;
    /* the two frames before, for second differences */
    float *f1, *f2, *h1, *h2;
    uint32_t *id1, *id2;
    int held;
    science_second_difference f_d2, h_d2, c_d2;
};

vg_status science_metrics_create(const science_metrics_desc *desc, science_metrics **out)
{
    *out = NULL;
    science_metrics *m = calloc(1, sizeof *m);
    if (!m)
        return VG_ERR_NOMEM;
    m->d = *desc;
    disp_grid_init(&m->grid, (int)desc->width, (int)desc->height, (int)desc->stride);
    m->ns = m->grid.nx * m->grid.ny;
    m->cap = desc->max_keyframes > 0 ? desc->max_keyframes : 256;
    size_t nk = (size_t)m->ns * m->cap, np = (size_t)desc->width * desc->height;
    m->g = malloc(nk * sizeof(float));
    m->h = malloc(nk * sizeof(float));
    m->f = malloc(nk * sizeof(float));
    m->z = malloc(nk * sizeof(float));
    m->id = malloc(nk * sizeof(float));
    m->ffw = calloc(2 * nk, sizeof(float));
    m->fbw = calloc(2 * nk, sizeof(float));
    m->f1 = malloc(np * sizeof(float));
    m->f2 = malloc(np * sizeof(float));
    m->h1 = malloc(np * sizeof(float));
    m->h2 = malloc(np * sizeof(float));
    m->id1 = malloc(np * sizeof(uint32_t));
    m->id2 = malloc(np * sizeof(uint32_t));
    m->have = calloc((size_t)m->cap, 1);
    m->last_index = -1;
    m->k0 = -1;
    m->g_lo = desc->range_lo;
    m->g_hi = desc->range_hi;
    if (!m->g || !m->h || !m->f || !m->z || !m->id || !m->ffw || !m->fbw || !m->f1 || !m->f2 || !m->h1 || !m->h2 || !m->id1 ||
        !m->id2 || !m->have) {
        science_metrics_destroy(m);
        return VG_ERR_NOMEM;
    }
    *out = m;
    return VG_OK;
}

vg_status science_metrics_create_for(const frame *f, science_metrics **out)
{
    const frame_desc *d = frame_get_desc(f);
    frame_info info;
    frame_get_info(f, &info);
    if (!info.disparity) {
        *out = NULL;
        vg_error("the science metrics need a frame with the disparity pipeline (a stereo frame)");
        return VG_ERR_ARG;
    }
    return science_metrics_create(&(science_metrics_desc){
        .width = d->width, .height = d->height, .keyframe_stride = d->keyframe_stride, .fps = d->fps,
        .stride = info.grid_stride, .range_lo = info.range_lo, .range_hi = info.range_hi,
        .hull = d->op == DISP_OPERATOR_NONE}, out);
}

void science_metrics_destroy(science_metrics *m)
{
    if (!m)
        return;
    free(m->g); free(m->h); free(m->f); free(m->z); free(m->id); free(m->ffw); free(m->fbw);
    free(m->f1); free(m->f2); free(m->h1); free(m->h2); free(m->id1); free(m->id2); free(m->have);
    free(m);
}

static long outside(const float *x, size_t n, double lo, double hi)
{
    long c = 0;
    for (size_t i = 0; i < n; i++)
        c += !(x[i] >= lo - 1e-3 && x[i] <= hi + 1e-3);
    return c;
}

static void d2_add(science_second_difference *acc, double mean, long ph, int s)
{
    if (ph == 0 || ph == s - 1) { /* f(t_mid + 1) or f(t_mid) starts an interval */
        acc->boundary += mean;
        acc->boundary_frames++;
    } else {
        acc->between += mean;
        acc->between_frames++;
    }
    if (ph == 0) {
        acc->at_key += mean;
        acc->key_frames++;
    } else if (ph == 1 || ph == s - 1) {
        acc->next_to_key += mean;
        acc->next_frames++;
    }
}

/* Second differences at frame t_mid = t - 1 of f, h and f - h, from frames
 * t - 2 (held f2, h2), t - 1 (f1, h1) and t (f, h), in one walk over the
 * pixels that show the same instance in all three. */
static void second_differences(science_metrics *m, const float *f, const float *h, const uint32_t *ids, long t_mid)
{
    size_t np = (size_t)m->d.width * m->d.height, n = 0;
    double sf = 0, sh = 0, sc = 0;
    for (size_t i = 0; i < np; i++) {
        if (!ids[i] || ids[i] != m->id1[i] || ids[i] != m->id2[i])
            continue;
        double df = (double)f[i] - 2.0 * m->f1[i] + m->f2[i];
        double dh = (double)h[i] - 2.0 * m->h1[i] + m->h2[i];
        sf += fabs(df);
        sh += fabs(dh);
        sc += fabs(df - dh);
        n++;
    }
    if (!n)
        return;
    int s = m->d.keyframe_stride;
    long ph = ((t_mid % s) + s) % s;
    d2_add(&m->f_d2, sf / (double)n, ph, s);
    d2_add(&m->h_d2, sh / (double)n, ph, s);
    d2_add(&m->c_d2, sc / (double)n, ph, s);
}

/* The offset of keyframe `key` in the arrays, -1 when it cannot be held
 * (before the first, past the capacity, or already there). */
static long keyframe_slot(science_metrics *m, long key)
{
    if (m->k0 < 0)
        m->k0 = key;
    long j = key - m->k0;
    if (j < 0 || j >= m->cap || m->have[j])
        return -1;
    m->have[j] = 1;
    m->nt = j + 1 > m->nt ? (int)(j + 1) : m->nt;
    return j * m->ns;
}

void science_metrics_add(science_metrics *m, long index, const float *g, const float *h, const float *f, const float *depth,
                     const float *motion, const uint32_t *ids)
{
    /* The same frame again (a redraw) shows the same maps: counted once. */
    if (index == m->last_index)
        return;
    size_t np = (size_t)m->d.width * m->d.height;
    double lo = m->d.range_lo, hi = m->d.range_hi;
    for (size_t i = 0; m->d.hull && i < np; i++) {
        lo = g[i] < lo ? g[i] : lo;
        hi = g[i] > hi ? g[i] : hi;
    }
    m->h_out += (double)outside(h, np, lo, hi);
    m->f_out += (double)outside(f, np, lo, hi);
    m->g_lo = lo < m->g_lo ? lo : m->g_lo;
    m->g_hi = hi > m->g_hi ? hi : m->g_hi;
    m->pixels += (double)np;
    if (m->held >= 2 && index == m->last_index + 1) {
        second_differences(m, f, h, ids, index - 1);
    }
    if (index != m->last_index + 1)
        m->held = 0;
    /* Shift the history: t-1 becomes t-2. */
    float *tf = m->f2, *th = m->h2;
    uint32_t *ti = m->id2;
    m->f2 = m->f1; m->h2 = m->h1; m->id2 = m->id1;
    m->f1 = tf; m->h1 = th; m->id1 = ti;
    memcpy(m->f1, f, np * sizeof(float));
    memcpy(m->h1, h, np * sizeof(float));
    memcpy(m->id1, ids, np * sizeof(uint32_t));
    m->held = m->held < 2 ? m->held + 1 : 2;
    m->last_index = index;
    long j = index % m->d.keyframe_stride == 0 ? keyframe_slot(m, index / m->d.keyframe_stride) : -1;
    if (j < 0)
        return;
    /* A keyframe: coarse samples and the motion to its neighbours as the
     * window's flows (coarse pixels). */
    size_t o = (size_t)j;
    disp_grid_sample(&m->grid, g, 1, m->g + o);
    disp_grid_sample(&m->grid, h, 1, m->h + o);
    disp_grid_sample(&m->grid, f, 1, m->f + o);
    disp_grid_sample(&m->grid, depth, 1, m->z + o);
    /* The instance at each sample: links stay on their instance (mid_window.c). */
    for (int q = 0; q < m->ns; q++)
        m->id[o + q] = (float)ids[(size_t)disp_grid_py(&m->grid, q / m->grid.nx) * m->d.width +
                                  disp_grid_px(&m->grid, q % m->grid.nx)];
    float inv = 1.0f / (float)m->grid.stride;
    for (int q = 0; q < m->ns; q++) {
        const float *mv = motion + 4 * ((size_t)disp_grid_py(&m->grid, q / m->grid.nx) * m->d.width +
                                        disp_grid_px(&m->grid, q % m->grid.nx));
        m->fbw[2 * (o + q)] = mv[0] * inv;
        m->fbw[2 * (o + q) + 1] = mv[1] * inv;
        m->ffw[2 * (o + q)] = mv[2] * inv;
        m->ffw[2 * (o + q) + 1] = mv[3] * inv;
    }
}

void science_metrics_add_keyframe(science_metrics *m, long keyframe, const disparity_gpu_keyframe *k)
{
    long j = k->ns == m->ns ? keyframe_slot(m, keyframe) : -1;
    if (j < 0)
        return;
    size_t o = (size_t)j, n = (size_t)m->ns;
    memcpy(m->g + o, k->g, n * sizeof(float));
    memcpy(m->h + o, k->h, n * sizeof(float));
    memcpy(m->f + o, k->f, n * sizeof(float));
    memcpy(m->z + o, k->depth, n * sizeof(float));
    memcpy(m->id + o, k->id, n * sizeof(float));
    memcpy(m->ffw + 2 * o, k->flow_fwd, 2 * n * sizeof(float));
    memcpy(m->fbw + 2 * o, k->flow_bwd, 2 * n * sizeof(float));
}

vg_status science_metrics_finish(science_metrics *m, science_metrics_result *out)
{
    memset(out, 0, sizeof *out);
    for (int j = 0; j < m->nt; j++)
        out->keyframes_missing += !m->have[j];
    out->keyframes = out->keyframes_missing ? 0 : m->nt;
    out->h_range_violation = m->pixels > 0 ? m->h_out / m->pixels : 0;
    out->f_range_violation = m->pixels > 0 ? m->f_out / m->pixels : 0;
    out->f_d2 = m->f_d2;
    out->h_d2 = m->h_d2;
    out->c_d2 = m->c_d2;
    science_second_difference *d2[3] = {&out->f_d2, &out->h_d2, &out->c_d2};
    for (int i = 0; i < 3; i++) {
        d2[i]->boundary = d2[i]->boundary_frames ? d2[i]->boundary / d2[i]->boundary_frames : 0;
        d2[i]->between = d2[i]->between_frames ? d2[i]->between / d2[i]->between_frames : 0;
        d2[i]->at_key = d2[i]->key_frames ? d2[i]->at_key / d2[i]->key_frames : 0;
        d2[i]->next_to_key = d2[i]->next_frames ? d2[i]->next_to_key / d2[i]->next_frames : 0;
    }
    out->range_lo = m->g_lo;
    out->range_hi = m->g_hi;
    if (out->keyframes < 3)
        return VG_OK; /* no acceleration to measure (or keyframes between were not rendered) */
    mid_window *w;
    vg_status st = mid_window_create(&(mid_window_desc){.width = m->grid.nx, .height = m->grid.ny, .keyframes = m->nt,
                                                        .range_lo = (float)m->g_lo, .range_hi = (float)m->g_hi,
                                                        .keyframe_seconds = (float)(m->d.keyframe_stride / m->d.fps)},
                                     &w);
    if (st != VG_OK)
        return st;
    size_t n = (size_t)w->n;
    memcpy(w->g, m->g, n * sizeof(float));
    memcpy(w->h, m->h, n * sizeof(float));
    memcpy(w->depth, m->z, n * sizeof(float));
    memcpy(w->id, m->id, n * sizeof(float));
    memcpy(w->flow_fwd, m->ffw, 2 * n * sizeof(float));
    memcpy(w->flow_bwd, m->fbw, 2 * n * sizeof(float));
    st = mid_window_build(w, NULL);
    if (st == VG_OK) {
        disp_metrics_window(w, w->h, NULL, &out->h);
        disp_metrics_window(w, m->f, NULL, &out->f);
    }
    mid_window_destroy(w);
    return st;
}
