#include "disp_operator.h"

#include <float.h>
#include <stdbool.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "mid_shared.h"

struct disp_operator {
    disp_operator_desc d; /* defaults resolved */
    double lo, hi;        /* target range */
    double *knots;        /* bins + 1: normalised cumulative mapping in [0, 1] */
    double *hist;         /* bins: importance after the blur */
    double *kernel;       /* blur taps, 2 * radius + 1 */
    int radius;
    double dom_lo, dom_hi, out_lo, out_hi, scale;
    int has_prev;
    double *partial;      /* per-block histograms */
    int partial_blocks;
};

const char *const disp_operator_names[] = {"lang", "none", "linear", "lang", "lang-smoothed", NULL};
_Static_assert(DISP_OPERATOR_NONE == DISP_OP_NONE && DISP_OPERATOR_LINEAR == DISP_OP_LINEAR &&
                   DISP_OPERATOR_LANG == DISP_OP_LANG && DISP_OPERATOR_LANG_SMOOTHED == DISP_OP_LANG_SMOOTHED,
               "operator kinds shared with the GPU passes");

disp_operator_kind disp_operator_kind_parse(const char *name)
{
    for (int k = DISP_OPERATOR_NONE; k <= DISP_OPERATOR_LANG_SMOOTHED; k++)
        if (!strcmp(name, disp_operator_names[k]))
            return (disp_operator_kind)k;
    return DISP_OPERATOR_DEFAULT;
}

const char *disp_operator_kind_name(disp_operator_kind kind)
{
    return kind >= DISP_OPERATOR_DEFAULT && kind <= DISP_OPERATOR_LANG_SMOOTHED ? disp_operator_names[kind] : "?";
}

disp_operator_desc disp_operator_desc_defaults(const disp_operator_desc *desc)
{
    disp_operator_desc d = *desc;
    bool study = d.preset == DISP_PRESET_STUDY;
    if (d.kind == DISP_OPERATOR_DEFAULT)
        d.kind = DISP_OPERATOR_LANG;
    /* The constants the GPU pass's shader shares (mid_shared.h). */
    if (!(d.range > 0))
        d.range = study ? DISP_OP_RANGE_STUDY : DISP_OP_RANGE_COMFORT;
    if (!(d.floor > 0))
        d.floor = study ? DISP_OP_FLOOR_STUDY : DISP_OP_FLOOR_COMFORT;
    if (d.bins <= 0)
        d.bins = DISP_OP_BINS;
    if (!(d.blur_bins > 0))
        d.blur_bins = DISP_OP_BLUR_BINS;
    if (!(d.saliency_floor > 0))
        d.saliency_floor = DISP_OP_SALIENCY_FLOOR;
    if (!(d.smooth_seconds > 0))
        d.smooth_seconds = DISP_OP_SMOOTH_SECONDS;
    if (!(d.frame_seconds > 0))
        d.frame_seconds = 1.0 / MID_FPS;
    return d;
}

vg_status disp_operator_create(const disp_operator_desc *desc, disp_operator **out)
{
    *out = NULL;
    if (!(desc->screen_vergence > 0)) {
        vg_error("operator: screen vergence %g arcmin must be positive", desc->screen_vergence);
        return VG_ERR_ARG;
    }
    disp_operator *op = calloc(1, sizeof *op);
    if (!op)
        return VG_ERR_NOMEM;
    disp_operator_desc d = disp_operator_desc_defaults(desc);
    op->d = d;
    op->lo = d.screen_vergence - d.range;
    op->hi = d.screen_vergence + d.range;
    if (!(op->lo > 0)) {
        vg_error("operator: target range %g +- %g arcmin reaches non-positive vergence",
                 d.screen_vergence, d.range);
        free(op);
        return VG_ERR_ARG;
    }
    op->radius = (int)ceil(3.0 * d.blur_bins);
    op->knots = calloc((size_t)d.bins + 1, sizeof(double));
    op->hist = calloc((size_t)d.bins, sizeof(double));
    op->kernel = calloc(2 * (size_t)op->radius + 1, sizeof(double));
    if (!op->knots || !op->hist || !op->kernel) {
        disp_operator_destroy(op);
        return VG_ERR_NOMEM;
    }
    for (int i = -op->radius; i <= op->radius; i++)
        op->kernel[i + op->radius] = exp(-0.5 * i * i / (d.blur_bins * d.blur_bins));
    for (int b = 0; b <= d.bins; b++)
        op->knots[b] = (double)b / d.bins;
    op->dom_lo = op->out_lo = op->lo;
    op->dom_hi = op->out_hi = op->hi;
    op->scale = 1.0;
    *out = op;
    return VG_OK;
}

void disp_operator_destroy(disp_operator *op)
{
    if (!op)
        return;
    free(op->knots);
    free(op->hist);
    free(op->kernel);
    free(op->partial);
    free(op);
}

void disp_operator_reset(disp_operator *op)
{
    op->has_prev = 0;
}

void disp_operator_range(const disp_operator *op, double *lo, double *hi)
{
    *lo = op->lo;
    *hi = op->hi;
    /* `none` keeps g as it is: its range is wherever g is (with a fixed
     * domain), so the optimiser's box never forces a change h did not make. */
    if (op->d.kind == DISP_OPERATOR_NONE && op->d.in_max > op->d.in_min) {
        *lo = op->d.in_min < *lo ? op->d.in_min : *lo;
        *hi = op->d.in_max > *hi ? op->d.in_max : *hi;
    }
}

/* ------------------------------------------------------------------------- */
/* Per-frame statistics (block partials, summed in block order)              */
/* ------------------------------------------------------------------------- */

typedef struct stat_ctx {
    disp_operator *op;
    const float *g, *sal;
    int minmax; /* 1: min/max pass, 0: histogram pass */
} stat_ctx;

static void stat_block(void *c, int block, int begin, int end)
{
    stat_ctx *x = c;
    disp_operator *op = x->op;
    int bins = op->d.bins;
    double *out = op->partial + (size_t)block * (size_t)(bins > 2 ? bins : 2);
    if (x->minmax) {
        double mn = DBL_MAX, mx = -DBL_MAX;
        for (int i = begin; i < end; i++) {
            mn = fmin(mn, x->g[i]);
            mx = fmax(mx, x->g[i]);
        }
        out[0] = mn;
        out[1] = mx;
        return;
    }
    memset(out, 0, (size_t)bins * sizeof(double));
    double inv = bins / (op->dom_hi - op->dom_lo);
    for (int i = begin; i < end; i++) {
        int b = (int)((x->g[i] - op->dom_lo) * inv);
        b = b < 0 ? 0 : (b >= bins ? bins - 1 : b);
        /* Lang et al.: pixels count by their visual importance. */
        out[b] += x->sal ? op->d.saliency_floor + x->sal[i] : 1.0;
    }
}

static vg_status ensure_partial(disp_operator *op, int blocks)
{
    if (blocks <= op->partial_blocks)
        return VG_OK;
    int width = op->d.bins > 2 ? op->d.bins : 2;
    double *p = realloc(op->partial, (size_t)blocks * (size_t)width * sizeof(double));
    if (!p)
        return VG_ERR_NOMEM;
    op->partial = p;
    op->partial_blocks = blocks;
    return VG_OK;
}

/* The mapping's slope per bin follows importance with a floor (Lang et al.
 * 2010, "nonlinear disparity mapping"): blur, integrate, normalise. */
static void lang_knots(disp_operator *op, const double *hist_raw)
{
    int bins = op->d.bins;
    double total = 0;
    for (int b = 0; b < bins; b++) {
        double s = 0, wsum = 0;
        for (int i = -op->radius; i <= op->radius; i++) {
            int j = b + i;
            if (j < 0 || j >= bins)
                continue;
            s += op->kernel[i + op->radius] * hist_raw[j];
            wsum += op->kernel[i + op->radius];
        }
        op->hist[b] = s / wsum;
        total += op->hist[b];
    }
    double smooth = op->d.kind == DISP_OPERATOR_LANG_SMOOTHED && op->has_prev
                        ? exp(-op->d.frame_seconds / op->d.smooth_seconds) : 0.0;
    /* Slopes: 1 per bin for a uniform histogram, the floor for an empty bin. */
    double sum = 0;
    for (int b = 0; b < bins; b++)
        sum += op->d.floor + (total > 0 ? op->hist[b] / total : 1.0 / bins) * bins;
    double k = 0;
    for (int b = 0; b <= bins; b++) {
        double now = k / sum;
        /* First-order temporal smoothing of the mapping (lang-smoothed only). */
        op->knots[b] = smooth * op->knots[b] + (1.0 - smooth) * now;
        if (b < bins)
            k += op->d.floor + (total > 0 ? op->hist[b] / total : 1.0 / bins) * bins;
    }
    op->knots[0] = 0.0;
    op->knots[bins] = 1.0;
    op->has_prev = 1;
}

double disp_operator_map(const disp_operator *op, double x)
{
    switch (op->d.kind) {
    case DISP_OPERATOR_NONE:
        return x;
    case DISP_OPERATOR_LINEAR:
        return op->d.screen_vergence + op->scale * (x - op->d.screen_vergence);
    default:
        break;
    }
    double span = op->dom_hi - op->dom_lo;
    if (!(span > 1e-6))
        return op->d.screen_vergence + op->scale * (x - op->d.screen_vergence);
    double u = (x - op->dom_lo) / span * op->d.bins;
    u = u < 0 ? 0 : (u > op->d.bins ? op->d.bins : u);
    int b = (int)u;
    if (b >= op->d.bins)
        b = op->d.bins - 1;
    double k = op->knots[b] + (u - b) * (op->knots[b + 1] - op->knots[b]);
    return op->out_lo + (op->out_hi - op->out_lo) * k;
}

typedef struct map_ctx {
    const disp_operator *op;
    const float *g;
    float *h;
} map_ctx;

static void map_block(void *c, int block, int begin, int end)
{
    (void)block;
    map_ctx *x = c;
    for (int i = begin; i < end; i++)
        x->h[i] = (float)disp_operator_map(x->op, x->g[i]);
}

void disp_operator_apply(disp_operator *op, const float *g, const float *saliency, int n, float *h,
                         vg_pool *pool)
{
    int blocks = vg_block_count(n, MID_BLOCK);
    if (n <= 0 || ensure_partial(op, blocks) != VG_OK) {
        if (n > 0)
            memcpy(h, g, (size_t)n * sizeof(float));
        return;
    }
    int width = op->d.bins > 2 ? op->d.bins : 2;
    stat_ctx sc = {.op = op, .g = g, .sal = saliency, .minmax = 1};
    /* Domain of the mapping: fixed, or this frame's range of g. */
    if (op->d.in_max > op->d.in_min) {
        op->dom_lo = op->d.in_min;
        op->dom_hi = op->d.in_max;
    } else {
        vg_parallel_for(pool, n, MID_BLOCK, stat_block, &sc);
        op->dom_lo = DBL_MAX;
        op->dom_hi = -DBL_MAX;
        for (int b = 0; b < blocks; b++) {
            op->dom_lo = fmin(op->dom_lo, op->partial[(size_t)b * width]);
            op->dom_hi = fmax(op->dom_hi, op->partial[(size_t)b * width + 1]);
        }
    }
    /* linear: the largest scale about a_s <= 1 that fits the domain in range. */
    double as = op->d.screen_vergence, s = 1.0;
    if (op->dom_hi > op->hi)
        s = fmin(s, (op->hi - as) / (op->dom_hi - as));
    if (op->dom_lo < op->lo)
        s = fmin(s, (as - op->lo) / (as - op->dom_lo));
    op->scale = s;
    op->out_lo = as + s * (op->dom_lo - as);
    op->out_hi = as + s * (op->dom_hi - as);
    if ((op->d.kind == DISP_OPERATOR_LANG || op->d.kind == DISP_OPERATOR_LANG_SMOOTHED) &&
        op->dom_hi - op->dom_lo > 1e-6) {
        sc.minmax = 0;
        vg_parallel_for(pool, n, MID_BLOCK, stat_block, &sc);
        /* Fixed-order sum of the block histograms into block 0. */
        for (int b = 1; b < blocks; b++)
            for (int j = 0; j < op->d.bins; j++)
                op->partial[j] += op->partial[(size_t)b * width + j];
        lang_knots(op, op->partial);
    }
    map_ctx mc = {.op = op, .g = g, .h = h};
    vg_parallel_for(pool, n, MID_BLOCK, map_block, &mc);
}
