#include "disp_curve.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

typedef struct curve_ctx {
    const float *depth, *disp;
    float inv_lo, inv_hi;
    int bins;
    const int *count, *left, *right; /* pass 2 inputs */
    double *partial;                 /* per block: pass 1 counts, or pass 2 (w, w s, w value) */
    double *range;                   /* per block: min and max depth */
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
            lo = fmin(lo, x->depth[i]);
            hi = fmax(hi, x->depth[i]);
        }
    x->range[2 * block] = lo;
    x->range[2 * block + 1] = hi;
}

static int bin_of(const curve_ctx *x, float s)
{
    int b = (int)floorf(s + 0.5f);
    return b < 0 ? 0 : (b >= x->bins ? x->bins - 1 : b);
}

/* Pass 1: the histogram of depth. */
static void count_block(void *c, int block, int begin, int end)
{
    curve_ctx *x = c;
    double *h = x->partial + (size_t)block * 3 * x->bins;
    memset(h, 0, 3 * (size_t)x->bins * sizeof(double));
    for (int i = begin; i < end; i++)
        if (pair_ok(x->depth[i], x->disp[i]))
            h[bin_of(x, disp_curve_coord(x->depth[i], x->inv_lo, x->inv_hi, (uint)x->bins))] += 1.0;
}

/* Pass 2: hat kernels reaching the next populated bin on each side. */
static void splat_block(void *c, int block, int begin, int end)
{
    curve_ctx *x = c;
    double *acc = x->partial + (size_t)block * 3 * x->bins;
    memset(acc, 0, 3 * (size_t)x->bins * sizeof(double));
    for (int i = begin; i < end; i++) {
        if (!pair_ok(x->depth[i], x->disp[i]))
            continue;
        float s = disp_curve_coord(x->depth[i], x->inv_lo, x->inv_hi, (uint)x->bins);
        int b = bin_of(x, s);
        /* A side without a populated neighbour keeps a one-bin tent. */
        int lsup = x->left[b] > 0 ? x->left[b] : 1, rsup = x->right[b] > 0 ? x->right[b] : 1;
        double unit = 1.0 / x->count[b];
        int j0 = (int)floorf(s) - lsup + 1, j1 = (int)ceilf(s) + rsup - 1;
        for (int j = j0 < 0 ? 0 : j0; j <= j1 && j < x->bins; j++) {
            double d = (double)j - s;
            double w = d >= 0 ? 1.0 - d / rsup : 1.0 + d / lsup;
            if (w <= 0)
                continue;
            acc[3 * j] += w * unit;
            acc[3 * j + 1] += w * unit * s;
            acc[3 * j + 2] += w * unit * x->disp[i];
        }
    }
}

vg_status disp_curve_build(const disp_curve_desc *desc, const float *depth, const float *disparity,
                           int n, disp_curve *out, vg_pool *pool)
{
    memset(out, 0, sizeof *out);
    int bins = desc && desc->bins > 0 ? desc->bins : DISP_CURVE_BINS;
    if (bins > DISP_CURVE_BINS || bins < 2) {
        vg_error("curve: %d bins (2..%d)", bins, DISP_CURVE_BINS);
        return VG_ERR_ARG;
    }
    int blocks = vg_block_count(n, MID_BLOCK);
    curve_ctx x = {.depth = depth, .disp = disparity, .bins = bins};
    x.partial = malloc((size_t)(blocks ? blocks : 1) * 3 * bins * sizeof(double));
    x.range = malloc((size_t)(blocks ? blocks : 1) * 2 * sizeof(double));
    int *count = calloc((size_t)bins, sizeof(int)), *left = calloc((size_t)bins, sizeof(int));
    int *right = calloc((size_t)bins, sizeof(int));
    vg_status st = VG_OK;
    if (!x.partial || !x.range || !count || !left || !right) {
        st = VG_ERR_NOMEM;
        goto done;
    }
    /* Domain in inverse depth. */
    double zlo = desc ? desc->depth_min : 0, zhi = desc ? desc->depth_max : 0;
    if (!(zhi > zlo && zlo > 0)) {
        vg_parallel_for(pool, n, MID_BLOCK, range_block, &x);
        zlo = DBL_MAX;
        zhi = -DBL_MAX;
        for (int b = 0; b < blocks; b++) {
            zlo = fmin(zlo, x.range[2 * b]);
            zhi = fmax(zhi, x.range[2 * b + 1]);
        }
    }
    if (!(zhi >= zlo && zlo > 0)) {
        vg_error("curve: no valid (depth, disparity) pair among %d", n);
        st = VG_ERR_ARG;
        goto done;
    }
    if (zhi < zlo * (1 + 1e-6))
        zhi = zlo * (1 + 1e-6); /* one depth: a flat curve */
    x.inv_lo = (float)(1.0 / zhi);
    x.inv_hi = (float)(1.0 / zlo);
    /* Pass 1: bandwidth from the histogram (integer counts: order-free). */
    vg_parallel_for(pool, n, MID_BLOCK, count_block, &x);
    for (int b = 0; b < blocks; b++)
        for (int j = 0; j < bins; j++)
            count[j] += (int)x.partial[(size_t)b * 3 * bins + j];
    for (int j = 0, last = -1; j < bins; j++) {
        left[j] = last >= 0 ? j - last : 0;
        if (count[j])
            last = j;
    }
    for (int j = bins - 1, next = -1; j >= 0; j--) {
        right[j] = next >= 0 ? next - j : 0;
        if (count[j])
            next = j;
    }
    /* Pass 2: reconstruction, block sums added in block order. */
    x.count = count;
    x.left = left;
    x.right = right;
    vg_parallel_for(pool, n, MID_BLOCK, splat_block, &x);
    double *sum = calloc(3 * (size_t)bins, sizeof(double));
    if (!sum) {
        st = VG_ERR_NOMEM;
        goto done;
    }
    for (int b = 0; b < blocks; b++)
        for (int j = 0; j < 3 * bins; j++)
            sum[j] += x.partial[(size_t)b * 3 * bins + j];
    /* Each bin's weighted mean (s, disparity) is a node; near the ends of the
     * data the kernels are one-sided and the node is off the bin centre, so
     * the node polyline is resampled at the centres (exact for a mapping
     * linear in inverse depth). Nodes are in increasing s. */
    int first = -1, last = -1, seg = -1;
    for (int j = 0; j < bins; j++) {
        out->header.populated += count[j] > 0;
        if (sum[3 * j] <= 0)
            continue;
        if (first < 0)
            first = j;
        last = j;
    }
    for (int j = first; j >= 0 && j <= last; j++) {
        /* Advance seg to the last node whose s is <= j (or the first node). */
        if (seg < 0)
            seg = first;
        while (true) {
            int nx = seg + 1;
            while (nx <= last && sum[3 * nx] <= 0)
                nx++;
            if (nx > last || sum[3 * nx + 1] / sum[3 * nx] > j)
                break;
            seg = nx;
        }
        int a = seg, nx = seg + 1;
        while (nx <= last && sum[3 * nx] <= 0)
            nx++;
        if (nx > last) { /* past the last node: extend the last segment */
            nx = seg;
            a = seg - 1;
            while (a >= first && sum[3 * a] <= 0)
                a--;
            if (a < first) {
                out->value[j] = (float)(sum[3 * seg + 2] / sum[3 * seg]);
                continue;
            }
        }
        double s0 = sum[3 * a + 1] / sum[3 * a], v0 = sum[3 * a + 2] / sum[3 * a];
        double s1 = sum[3 * nx + 1] / sum[3 * nx], v1 = sum[3 * nx + 2] / sum[3 * nx];
        out->value[j] = (float)(s1 > s0 ? v0 + (v1 - v0) * ((double)j - s0) / (s1 - s0) : v0);
    }
    /* Beyond the data, the curve holds its end values. */
    for (int j = 0; j < first; j++)
        out->value[j] = out->value[first];
    for (int j = last + 1; j < bins; j++)
        out->value[j] = out->value[last];
    free(sum);
    out->header.inv_depth_lo = x.inv_lo;
    out->header.inv_depth_hi = x.inv_hi;
    out->header.bins = (uint)bins;
done:
    free(x.partial);
    free(x.range);
    free(count);
    free(left);
    free(right);
    return st;
}

float disp_curve_eval(const disp_curve *c, float depth)
{
    int bins = (int)c->header.bins;
    float s = disp_curve_coord(depth, c->header.inv_depth_lo, c->header.inv_depth_hi, c->header.bins);
    /* The domain reaches half a bin past the first and last centres: the end
     * segments extend linearly there, and the curve is held beyond. */
    float lo = floorf(s);
    int i = isnan(s) ? 0 : (lo < 0.0f ? 0 : (lo > (float)(bins - 2) ? bins - 2 : (int)lo));
    float t = s - (float)i;
    t = isnan(t) ? 0.0f : fminf(fmaxf(t, -0.5f), 1.5f);
    return c->value[i] + t * (c->value[i + 1] - c->value[i]);
}
