#include "disp_curve.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

typedef struct curve_ctx {
    const float *depth, *disp;
    double inv_lo, span;
    int bins;
    double *partial; /* per block: count, sum of disparity, sum of position in the bin (3 per bin) */
    double *range;   /* per block: min and max inverse depth */
} curve_ctx;

static bool pair_ok(float z, float d)
{
    return z > 0.0f && isfinite(z) && isfinite(d) && d > 0.0f;
}

static void range_block(void *c, int block, int begin, int end)
{
    curve_ctx *x = c;
    double lo = DBL_MAX, hi = -DBL_MAX;
    for (int i = begin; i < end; i++)
        if (pair_ok(x->depth[i], x->disp[i])) {
            double q = 1.0 / x->depth[i];
            lo = fmin(lo, q);
            hi = fmax(hi, q);
        }
    x->range[2 * block] = lo;
    x->range[2 * block + 1] = hi;
}

/* Per bin: how many pairs, their disparities and where they sit in the bin. */
static void bins_block(void *c, int block, int begin, int end)
{
    curve_ctx *x = c;
    double *acc = x->partial + (size_t)block * 3 * x->bins;
    memset(acc, 0, 3 * (size_t)x->bins * sizeof(double));
    for (int i = begin; i < end; i++) {
        if (!pair_ok(x->depth[i], x->disp[i]))
            continue;
        double pos = (1.0 / x->depth[i] - x->inv_lo) / x->span * x->bins;
        pos = pos < 0 ? 0 : (pos > x->bins - 1e-3 ? x->bins - 1e-3 : pos);
        int b = (int)pos;
        acc[3 * b] += 1.0;
        acc[3 * b + 1] += x->disp[i];
        acc[3 * b + 2] += pos - b;
    }
}

vg_status disp_curve_build(const disp_curve_desc *desc, const float *depth, const float *disparity,
                           int n, disp_curve *out, vg_pool *pool)
{
    memset(out, 0, sizeof *out);
    int bins = desc && desc->bins > 0 ? desc->bins : DISP_CURVE_BINS;
    if (bins > DISP_CURVE_BINS || bins < DISP_CURVE_REACH + 2) {
        vg_error("curve: %d bins (%d..%d)", bins, DISP_CURVE_REACH + 2, DISP_CURVE_BINS);
        return VG_ERR_ARG;
    }
    int blocks = vg_block_count(n, MID_BLOCK);
    curve_ctx x = {.depth = depth, .disp = disparity, .bins = bins};
    x.partial = malloc((size_t)(blocks ? blocks : 1) * 3 * bins * sizeof(double));
    x.range = malloc((size_t)(blocks ? blocks : 1) * 2 * sizeof(double));
    double *sum = calloc(3 * (size_t)bins, sizeof(double));
    vg_status st = VG_OK;
    if (!x.partial || !x.range || !sum) {
        st = VG_ERR_NOMEM;
        goto done;
    }
    /* Domain in inverse depth: given, or the pairs' range. */
    double lo = 0, hi = 0;
    if (desc && desc->depth_max > desc->depth_min && desc->depth_min > 0) {
        lo = 1.0 / desc->depth_max;
        hi = 1.0 / desc->depth_min;
    } else {
        vg_parallel_for(pool, n, MID_BLOCK, range_block, &x);
        lo = DBL_MAX;
        hi = -DBL_MAX;
        for (int b = 0; b < blocks; b++) {
            lo = fmin(lo, x.range[2 * b]);
            hi = fmax(hi, x.range[2 * b + 1]);
        }
    }
    if (!(hi >= lo && lo > 0)) {
        vg_error("curve: no valid (depth, disparity) pair among %d", n);
        st = VG_ERR_ARG;
        goto done;
    }
    /* As the GPU: float bounds; a single depth still needs a span to index bins. */
    float inv_far = (float)lo, inv_near = hi > lo ? (float)hi : (float)(lo * 1.001 + 1e-6);
    x.inv_lo = inv_far;
    x.span = (double)inv_near - inv_far;
    vg_parallel_for(pool, n, MID_BLOCK, bins_block, &x);
    /* Block sums added in block order (deterministic). */
    for (int b = 0; b < blocks; b++)
        for (int j = 0; j < 3 * bins; j++)
            sum[j] += x.partial[(size_t)b * 3 * bins + j];
    /* Nodes: the centroid of a populated bin, the centre of an empty one. */
    for (int b = 0; b < bins; b++) {
        double count = sum[3 * b];
        double inside = count > 0 ? sum[3 * b + 2] / count : 0.5;
        out->inv_depth[b] = (float)(x.inv_lo + (b + inside) / bins * x.span);
        out->value[b] = count > 0 ? (float)(sum[3 * b + 1] / count) : 0.0f;
        out->header.populated += count > 0;
    }
    /* Empty bins: linear in inverse depth between the nearest populated
     * nodes (the paper's linear interpolation for empty intervals). */
    for (int b = 0; b < bins; b++) {
        if (sum[3 * b] > 0)
            continue;
        int l = b, r = b;
        while (l >= 0 && sum[3 * l] == 0)
            l--;
        while (r < bins && sum[3 * r] == 0)
            r++;
        if (l >= 0 && r < bins) {
            double ql = out->inv_depth[l], qr = out->inv_depth[r];
            out->value[b] = (float)(out->value[l] + (out->value[r] - out->value[l]) * (out->inv_depth[b] - ql) / (qr - ql));
        } else {
            out->value[b] = l >= 0 ? out->value[l] : out->value[r];
        }
    }
    out->header.inv_depth_lo = inv_far;
    out->header.inv_depth_hi = inv_near;
    out->header.bins = (uint)bins;
done:
    free(x.partial);
    free(x.range);
    free(sum);
    return st;
}

static float between(const disp_curve *c, int a, int b, float q)
{
    float dq = c->inv_depth[b] - c->inv_depth[a];
    float t = fabsf(dq) > 1e-12f ? (q - c->inv_depth[a]) / dq : 0.0f;
    return c->value[a] + t * (c->value[b] - c->value[a]);
}

float disp_curve_eval(const disp_curve *c, float depth)
{
    int last = (int)c->header.bins - 1;
    float q = 1.0f / (depth > 1e-6f ? depth : 1e-6f);
    if (last < DISP_CURVE_REACH)
        return 0.0f;
    if (q <= c->inv_depth[0])
        return between(c, 0, DISP_CURVE_REACH, q);
    if (q >= c->inv_depth[last])
        return between(c, last - DISP_CURVE_REACH, last, q);
    /* The node segment that holds q (nodes increase in inverse depth). */
    float span = c->header.inv_depth_hi - c->header.inv_depth_lo;
    int i = (int)((q - c->header.inv_depth_lo) / (span > 1e-12f ? span : 1e-12f) * (float)(last + 1));
    i = i < 0 ? 0 : (i > last ? last : i);
    if (q < c->inv_depth[i])
        i = i > 0 ? i - 1 : 0;
    while (i < last - 1 && q > c->inv_depth[i + 1])
        i++;
    while (i > 0 && q < c->inv_depth[i])
        i--;
    return between(c, i, i + 1, q);
}
