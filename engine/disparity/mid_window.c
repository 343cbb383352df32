#include "mid_window.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

/* ------------------------------------------------------------------------- */
/* Create / destroy                                                          */
/* ------------------------------------------------------------------------- */

vg_status mid_window_create(const mid_window_desc *desc, mid_window **out)
{
    *out = NULL;
    if (desc->width < 2 || desc->height < 2 || desc->keyframes < 1) {
        vg_error("MID window: %dx%d x %d keyframes is too small (at least 2x2 x 1)", desc->width,
                 desc->height, desc->keyframes);
        return VG_ERR_ARG;
    }
    if (!(desc->range_hi > desc->range_lo) || !(desc->range_lo > 0)) {
        vg_error("MID window: target range [%g, %g] arcmin is empty or not positive",
                 desc->range_lo, desc->range_hi);
        return VG_ERR_ARG;
    }
    long long n = (long long)desc->width * desc->height * desc->keyframes;
    if (n > (1LL << 28)) {
        vg_error("MID window: %lld unknowns is too many", n);
        return VG_ERR_ARG;
    }
    mid_window *w = calloc(1, sizeof *w);
    if (!w)
        return VG_ERR_NOMEM;
    w->nx = desc->width;
    w->ny = desc->height;
    w->nt = desc->keyframes;
    w->ns = w->nx * w->ny;
    w->n = (int)n;
    w->range_lo = desc->range_lo;
    w->range_hi = desc->range_hi;
    w->occlusion_tolerance =
        desc->occlusion_tolerance > 0 ? desc->occlusion_tolerance : MID_OCCLUSION_TOLERANCE;
    w->flow_tolerance = desc->flow_tolerance > 0 ? desc->flow_tolerance : MID_FLOW_TOLERANCE;
    w->edge_scale = desc->edge_scale > 0 ? desc->edge_scale : 1.0f / (desc->range_hi - desc->range_lo);
    w->time_unit = desc->time_unit > 0 ? desc->time_unit : 1.0f;
    size_t nf = (size_t)n * sizeof(float);
    w->g = calloc(1, nf);
    w->h = calloc(1, nf);
    w->depth = calloc(1, nf);
    w->id = calloc(1, nf);
    w->unknown = calloc((size_t)n, 1);
    w->flow_fwd = calloc(2, nf);
    w->flow_bwd = calloc(2, nf);
    w->dt = calloc((size_t)w->nt, sizeof(float));
    w->fwd = calloc((size_t)n, sizeof(mid_link));
    w->bwd = calloc((size_t)n, sizeof(mid_link));
    w->fwd_adj.offset = calloc((size_t)n + 1, sizeof(uint32_t));
    w->bwd_adj.offset = calloc((size_t)n + 1, sizeof(uint32_t));
    w->edge_x = calloc(1, nf);
    w->edge_y = calloc(1, nf);
    w->ph = calloc(1, nf);
    w->pg_acc = calloc(1, nf);
    w->inv_dt_f = calloc((size_t)w->nt, sizeof(float));
    w->inv_dt_b = calloc((size_t)w->nt, sizeof(float));
    w->chain_next = calloc((size_t)n, sizeof(int32_t));
    w->chain_prev = calloc((size_t)n, sizeof(int32_t));
    w->chain_head = calloc((size_t)n, sizeof(int32_t));
    w->chain_order = calloc((size_t)n, sizeof(int32_t));
    w->chain_group = calloc((size_t)n / MID_CHAIN_GROUP + 2, sizeof(int32_t));
    if (!w->chain_next || !w->chain_prev || !w->chain_head || !w->chain_order || !w->chain_group ||
        !w->g || !w->h || !w->depth || !w->id || !w->unknown || !w->flow_fwd || !w->flow_bwd || !w->dt || !w->fwd ||
        !w->bwd || !w->fwd_adj.offset || !w->bwd_adj.offset || !w->edge_x || !w->edge_y ||
        !w->ph || !w->pg_acc || !w->inv_dt_f || !w->inv_dt_b) {
        mid_window_destroy(w);
        return VG_ERR_NOMEM;
    }
    float dt = desc->keyframe_seconds > 0 ? desc->keyframe_seconds : (float)MID_KEYFRAME_SECONDS;
    for (int k = 0; k + 1 < w->nt; k++)
        w->dt[k] = dt;
    for (int i = 0; i < w->n; i++)
        w->depth[i] = 1.0f;
    *out = w;
    return VG_OK;
}

void mid_window_destroy(mid_window *w)
{
    if (!w)
        return;
    free(w->g);
    free(w->h);
    free(w->depth);
    free(w->id);
    free(w->unknown);
    free(w->flow_fwd);
    free(w->flow_bwd);
    free(w->dt);
    free(w->fwd);
    free(w->bwd);
    free(w->fwd_adj.offset);
    free(w->fwd_adj.entry);
    free(w->bwd_adj.offset);
    free(w->bwd_adj.entry);
    free(w->edge_x);
    free(w->edge_y);
    free(w->ph);
    free(w->pg_acc);
    free(w->inv_dt_f);
    free(w->inv_dt_b);
    free(w->chain_next);
    free(w->chain_prev);
    free(w->chain_head);
    free(w->chain_order);
    free(w->chain_group);
    free(w);
}

/* ------------------------------------------------------------------------- */
/* Links (A_f, A_b) with occlusion masks                                     */
/* ------------------------------------------------------------------------- */

/* A tap is the same surface when the depths differ by less than the relative
 * tolerance (paper Sec. 4.4: "comparing the depth value of the current pixel
 * and the corresponding pixel along the motion flow"). */
static bool same_surface(float z0, float z1, float log_tol)
{
    if (!(z0 > 0.0f) || !(z1 > 0.0f) || !isfinite(z0) || !isfinite(z1))
        return false;
    return fabsf(logf(z1 / z0)) <= log_tol;
}

/* The tap moves back the way we came: the forward flow of i and the
 * backward flow of the tap (or the reverse for A_b) cancel. This keeps
 * points that move fast in depth linked (their depth ratio between keyframes
 * can exceed any fixed tolerance) while a tap on an occluder, which moves
 * differently, fails. */
static bool round_trip(const float *there, const float *back, int i, int j, float tol)
{
    float dx = there[2 * i] + back[2 * j], dy = there[2 * i + 1] + back[2 * j + 1];
    float mag = fabsf(there[2 * i]) + fabsf(there[2 * i + 1]);
    float lim = tol + 0.1f * mag;
    return dx * dx + dy * dy <= lim * lim;
}

/* Row i of A_f (dir = +1) or A_b (dir = -1). Out of frame when the target
 * lies more than half a pixel outside the grid. A tap is kept when it lies
 * on the sample's instance and passes the depth test or the round-trip flow
 * test. Without the instance test a slowly moving object's silhouette links
 * to the background behind it, whose flow back is zero, so the round trip
 * passes: on balloon such links carried 90 % of h's MID distortion (the
 * object's and the background's motion mixed). Sequences from files have no
 * ids (all 0): the depth and round-trip tests decide alone. A sample of
 * unknown g has no links and is no tap (its g is made up). */
static mid_link link_make(const mid_window *w, int i, int dir, float log_tol)
{
    mid_link l = {0};
    int k = i / w->ns, p = i % w->ns, x = p % w->nx, y = p / w->nx;
    int kk = k + dir;
    if (kk < 0 || kk >= w->nt || w->unknown[i])
        return l;
    const float *flow = dir > 0 ? w->flow_fwd : w->flow_bwd;
    const float *back = dir > 0 ? w->flow_bwd : w->flow_fwd;
    float tx = (float)x + flow[2 * i], ty = (float)y + flow[2 * i + 1];
    if (!(tx >= -0.5f && tx <= (float)w->nx - 0.5f && ty >= -0.5f && ty <= (float)w->ny - 0.5f))
        return l; /* out of frame, or NaN */
    tx = fminf(fmaxf(tx, 0.0f), (float)(w->nx - 1));
    ty = fminf(fmaxf(ty, 0.0f), (float)(w->ny - 1));
    int x0 = (int)floorf(tx), y0 = (int)floorf(ty);
    if (x0 > w->nx - 2)
        x0 = w->nx - 2;
    if (y0 > w->ny - 2)
        y0 = w->ny - 2;
    l.fx = tx - (float)x0;
    l.fy = ty - (float)y0;
    l.base = (uint)(kk * w->ns + y0 * w->nx + x0);
    float raw[4] = {(1 - l.fx) * (1 - l.fy), l.fx * (1 - l.fy), (1 - l.fx) * l.fy, l.fx * l.fy};
    uint idx[4] = {l.base, l.base + 1, l.base + (uint)w->nx, l.base + (uint)w->nx + 1};
    float kept = 0.0f;
    float z0 = w->depth[i], id = w->id[i];
    for (int t = 0; t < 4; t++)
        if (raw[t] > 0.0f && w->id[idx[t]] == id && !w->unknown[idx[t]] &&
            (same_surface(z0, w->depth[idx[t]], log_tol) || round_trip(flow, back, i, (int)idx[t], w->flow_tolerance))) {
            l.mask |= 1u << t;
            kept += raw[t];
        }
    if (kept < MID_LINK_MIN_WEIGHT)
        l.mask = 0; /* occluded or disoccluded */
    return l;
}

typedef struct build_ctx {
    mid_window *w;
    float log_tol, inv_range;
} build_ctx;

static void links_block(void *c, int block, int begin, int end)
{
    (void)block;
    build_ctx *b = c;
    for (int i = begin; i < end; i++) {
        b->w->fwd[i] = link_make(b->w, i, +1, b->log_tol);
        b->w->bwd[i] = link_make(b->w, i, -1, b->log_tol);
    }
}

/* The transpose of a link matrix as CSR. Built once per window, in source
 * order, so each row lists its sources sorted by index (a fixed summation
 * order for the adjoint gather). A GPU builds it the same way on the host or
 * with a counting sort. */
static vg_status adjoint_build(const mid_window *w, const mid_link *links, mid_adjoint *adj)
{
    uint32_t *off = adj->offset;
    memset(off, 0, ((size_t)w->n + 1) * sizeof *off);
    for (int i = 0; i < w->n; i++) {
        mid_link l = links[i];
        uint idx[4] = {l.base, l.base + 1, l.base + (uint)w->nx, l.base + (uint)w->nx + 1};
        for (int t = 0; t < 4; t++)
            if (l.mask & (1u << t))
                off[idx[t] + 1]++;
    }
    for (int j = 0; j < w->n; j++)
        off[j + 1] += off[j];
    free(adj->entry);
    adj->count = off[w->n];
    adj->entry = malloc((adj->count ? adj->count : 1) * sizeof *adj->entry);
    uint32_t *fill = malloc(((size_t)w->n + 1) * sizeof *fill);
    if (!adj->entry || !fill) {
        free(fill);
        return VG_ERR_NOMEM;
    }
    memcpy(fill, off, ((size_t)w->n + 1) * sizeof *fill);
    for (int i = 0; i < w->n; i++) {
        mid_link l = links[i];
        if (!l.mask)
            continue;
        mid_taps tw = mid_link_taps(l);
        float wt[4] = {tw.w00, tw.w10, tw.w01, tw.w11};
        uint idx[4] = {l.base, l.base + 1, l.base + (uint)w->nx, l.base + (uint)w->nx + 1};
        for (int t = 0; t < 4; t++)
            if (l.mask & (1u << t))
                adj->entry[fill[idx[t]]++] = (mid_adj_entry){.src = (uint)i, .w = wt[t]};
    }
    free(fill);
    return VG_OK;
}

/* The tap of a link with the largest weight (lowest index on ties), or -1. */
static int32_t heaviest_tap(const mid_window *w, mid_link l)
{
    if (!l.mask)
        return -1;
    mid_taps t = mid_link_taps(l);
    float wt[4] = {t.w00, t.w10, t.w01, t.w11};
    uint idx[4] = {l.base, l.base + 1, l.base + (uint)w->nx, l.base + (uint)w->nx + 1};
    int best = -1;
    for (int k = 0; k < 4; k++)
        if ((l.mask & (1u << k)) && (best < 0 || wt[k] > wt[best]))
            best = k;
    return (int32_t)idx[best];
}

/* Mutual heaviest taps make disjoint chains along the flow. */
static void chains_build(mid_window *w)
{
    for (int i = 0; i < w->n; i++)
        w->chain_next[i] = w->chain_prev[i] = -1;
    for (int i = 0; i < w->n; i++) {
        int32_t j = heaviest_tap(w, w->fwd[i]);
        if (j >= 0 && heaviest_tap(w, w->bwd[j]) == i) {
            w->chain_next[i] = j;
            w->chain_prev[j] = i;
        }
    }
    w->chain_count = 0;
    for (int i = 0; i < w->n; i++)
        if (w->chain_prev[i] < 0)
            w->chain_head[w->chain_count++] = i;
    /* Group the chains and list each group's nodes keyframe by keyframe. */
    int32_t cursor[MID_CHAIN_GROUP];
    int out = 0;
    w->chain_groups = (w->chain_count + MID_CHAIN_GROUP - 1) / MID_CHAIN_GROUP;
    for (int gi = 0; gi < w->chain_groups; gi++) {
        int c0 = gi * MID_CHAIN_GROUP, cn = w->chain_count - c0 < MID_CHAIN_GROUP ? w->chain_count - c0 : MID_CHAIN_GROUP;
        w->chain_group[gi] = out;
        for (int c = 0; c < cn; c++)
            cursor[c] = w->chain_head[c0 + c];
        for (int k = 0; k < w->nt; k++)
            for (int c = 0; c < cn; c++)
                if (cursor[c] >= 0 && cursor[c] / w->ns == k) {
                    w->chain_order[out++] = cursor[c];
                    cursor[c] = w->chain_next[cursor[c]];
                }
    }
    w->chain_group[w->chain_groups] = out;
}

/* ------------------------------------------------------------------------- */
/* Edge weights and targets                                                  */
/* ------------------------------------------------------------------------- */

static void targets_block(void *c, int block, int begin, int end)
{
    (void)block;
    build_ctx *b = c;
    mid_window *w = b->w;
    for (int i = begin; i < end; i++) {
        int k = i / w->ns, p = i % w->ns, x = p % w->nx, y = p / w->nx;
        /* Sec. 4.1: a_x = exp(-10 |dh/dx|), h normalised over the target range;
         * c_s uses a^2 per edge (the residual is a times the difference).
         * An edge to a sample of unknown g has none. */
        bool known = !w->unknown[i];
        float ax = x + 1 < w->nx && known && !w->unknown[i + 1]
                       ? mid_edge_weight((w->h[i + 1] - w->h[i]) * b->inv_range) : 0.0f;
        float ay = y + 1 < w->ny && known && !w->unknown[i + w->nx]
                       ? mid_edge_weight((w->h[i + w->nx] - w->h[i]) * b->inv_range) : 0.0f;
        w->edge_x[i] = ax * ax;
        w->edge_y[i] = ay * ay;
        /* Targets of c_t and c_a evaluated along the same links as f. */
        float mf = w->fwd[i].mask ? 1.0f : 0.0f, mb = w->bwd[i].mask ? 1.0f : 0.0f;
        float idf = w->inv_dt_f[k], idb = w->inv_dt_b[k];
        float ha = mid_link_gather(w->fwd, w->nx, i, w->h);
        float ga = mid_link_gather(w->fwd, w->nx, i, w->g);
        float gb = mid_link_gather(w->bwd, w->nx, i, w->g);
        w->ph[i] = mf * mid_p((ha - w->h[i]) * idf);
        w->pg_acc[i] = mf * mb * (mid_p((ga - w->g[i]) * idf) - mid_p((w->g[i] - gb) * idb));
    }
}

vg_status mid_window_build(mid_window *w, vg_pool *pool)
{
    for (int k = 0; k < w->nt; k++) {
        if (k + 1 < w->nt && !(w->dt[k] > 0.0f)) {
            vg_error("MID window: keyframe interval %d has dt %g s (must be > 0)", k, w->dt[k]);
            return VG_ERR_ARG;
        }
        w->inv_dt_f[k] = k + 1 < w->nt ? w->time_unit / w->dt[k] : 0.0f;
        w->inv_dt_b[k] = k > 0 ? w->time_unit / w->dt[k - 1] : 0.0f;
    }
    build_ctx b = {.w = w, .log_tol = logf(1.0f + w->occlusion_tolerance), .inv_range = w->edge_scale};
    vg_parallel_for(pool, w->n, MID_BLOCK, links_block, &b);
    vg_status st = adjoint_build(w, w->fwd, &w->fwd_adj);
    if (st == VG_OK)
        st = adjoint_build(w, w->bwd, &w->bwd_adj);
    if (st != VG_OK)
        return st;
    vg_parallel_for(pool, w->n, MID_BLOCK, targets_block, &b);
    chains_build(w);
    w->built = true;
    return VG_OK;
}

mid_params mid_window_params(const mid_window *w, float w_data, float w_spatial, float w_temporal,
                             float w_accel)
{
    return (mid_params){
        .nx = (uint)w->nx, .ny = (uint)w->ny, .nt = (uint)w->nt, .ns = (uint)w->ns,
        .w_data = w_data, .w_spatial = w_spatial, .w_temporal = w_temporal, .w_accel = w_accel,
        .range_lo = w->range_lo, .range_hi = w->range_hi,
        .grad_scale = 2.0f / (float)w->n, .inv_n = 1.0f / (float)w->n,
    };
}

void mid_window_split(double seconds, double keyframe_seconds, double future_share, int *past, int *future)
{
    int keys = (int)lround(seconds / keyframe_seconds);
    *future = (int)lround(keys * future_share);
    *future = *future < 2 ? 2 : *future;
    *past = keys - *future > 0 ? keys - *future : 0;
}

void mid_window_warm_start(const mid_window *w, const float *prev, int shift, float *out)
{
    for (int k = 0; k < w->nt; k++) {
        int src = k + shift;
        const float *from = src >= 0 && src < w->nt ? prev + (size_t)src * w->ns : w->h + (size_t)k * w->ns;
        memcpy(out + (size_t)k * w->ns, from, (size_t)w->ns * sizeof(float));
    }
}

void mid_window_ratio_slopes(const mid_window *w, const float *ratio, float *slope)
{
    for (int i = 0; i < w->n; i++) {
        int k = i / w->ns;
        float r = ratio[i];
        float rf = w->fwd[i].mask ? mid_link_gather(w->fwd, w->nx, i, ratio) : r;
        float rb = w->bwd[i].mask ? mid_link_gather(w->bwd, w->nx, i, ratio) : r;
        slope[i] = mid_ratio_slope(r, rf, rb, w->fwd[i].mask, w->bwd[i].mask, w->inv_dt_f[k], w->inv_dt_b[k]);
    }
}
