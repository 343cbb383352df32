/* vergence — stereo capture metrics. */
#include "warp_metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "shared.h"

static vg_status push(float **v, size_t *n, size_t *cap, float x)
{
    if (*n == *cap) {
        size_t c = *cap ? 2 * *cap : 1 << 16;
        float *p = realloc(*v, c * sizeof *p);
        if (!p)
            return VG_ERR_NOMEM;
        *v = p;
        *cap = c;
    }
    (*v)[(*n)++] = x;
    return VG_OK;
}

/* Eye colour alpha: 255 geometry, 128 sky, 0 nothing. */
static int is_geometry(const uint8_t *rgba)
{
    return rgba[3] > 192;
}

/* Geometry with geometry all around in the reference: silhouette pixels,
 * covered or not by a sub-pixel margin, are not holes. */
static int interior(const uint8_t *ref, uint32_t width, uint32_t height, size_t i)
{
    uint32_t x = (uint32_t)(i % width), y = (uint32_t)(i / width);
    if (x == 0 || y == 0 || x + 1 >= width || y + 1 >= height)
        return 0;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++)
            if (!is_geometry(ref + 4 * (i + (size_t)((long)dy * width + dx))))
                return 0;
    return 1;
}

/* A sky pixel between geometry of one surface (offset k on both sides, the
 * same depth) that the centre view, at the place the two sides come from,
 * covers with geometry: the warp tore the surface open. Sky the centre view
 * itself shows there (a gap, a notch) is rightly sky in the eye too. */
static bool torn(const uint8_t *eye, const float *aux, const uint32_t *centre_ids, uint32_t width, size_t i,
                 size_t k)
{
    if (!is_geometry(eye + 4 * (i - k)) || !is_geometry(eye + 4 * (i + k)))
        return false;
    float a = aux[4 * (i - k) + 1], b = aux[4 * (i + k) + 1];
    if (fabsf(a - b) >= 0.02f * fmaxf(a, b))
        return false;
    /* Where the two sides come from in the centre view, give or take a pixel:
     * a silhouette there (sky nearby) makes the gap the object's own edge. */
    long xc = lroundf(0.5f * (aux[4 * (i - k)] + aux[4 * (i + k)]) - 0.5f);
    const uint32_t *row = centre_ids + (i / width) * width;
    if (xc < 1 || xc + 1 >= (long)width)
        return false;
    return row[xc - 1] != 0 && row[xc] != 0 && row[xc + 1] != 0;
}

/* A pixel the method left empty (nothing drawn: the disocclusions of image
 * warping), or a crack (torn above). */
static int hole(const uint8_t *eye, const float *aux, const uint32_t *centre_ids, uint32_t width, uint32_t height,
                size_t i)
{
    const uint8_t *p = eye + 4 * i;
    if (p[3] < 64)
        return 1;
    if (is_geometry(p))
        return 0;
    uint32_t x = (uint32_t)(i % width), y = (uint32_t)(i / width);
    bool lr = x > 0 && x + 1 < width && torn(eye, aux, centre_ids, width, i, 1);
    bool ud = y > 0 && y + 1 < height && torn(eye, aux, centre_ids, width, i, width);
    return lr || ud;
}

vg_status warp_metrics_add(warp_metrics *m, const frame_outputs *o, uint32_t width, uint32_t height)
{
    size_t n = (size_t)width * height;
    const uint8_t *eyes[2] = {o->left, o->right};
    const float *aux[2] = {o->left_aux, o->right_aux};
    const uint8_t *refs[2] = {o->ref_left, o->ref_right};
    for (int e = 0; e < 2; e++) {
        for (size_t i = 0; i < n; i++) {
            if (!is_geometry(eyes[e] + 4 * i))
                continue;
            const float *a = aux[e] + 4 * i;
            int stage = (int)a[3];
            if (stage < 0 || stage > VG_STAGE_CURVE)
                stage = VG_STAGE_NONE;
            m->stage_pixels[stage]++;
            float err = fabsf(a[2]);
            vg_status st = stage == VG_STAGE_CURVE ? push(&m->errors_curve, &m->curve_count, &m->curve_cap, err)
                                                   : push(&m->errors, &m->error_count, &m->error_cap, err);
            if (st != VG_OK)
                return st;
        }
        if (!refs[e])
            continue;
        for (size_t i = 0; i < n; i++) {
            if (interior(refs[e], width, height, i)) {
                m->reference_geometry++;
                m->holes += hole(eyes[e], aux[e], o->ids, width, height, i);
            }
            for (int c = 0; c < 3; c++) {
                double d = (double)eyes[e][4 * i + c] - (double)refs[e][4 * i + c];
                m->sq_error[e] += d * d;
            }
        }
        m->samples[e] += 3 * n;
    }
    return VG_OK;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static double percentile(float *v, size_t n, double q)
{
    if (!n)
        return NAN;
    qsort(v, n, sizeof *v, cmp_float);
    size_t k = (size_t)(q * (double)(n - 1) + 0.5);
    return v[k < n ? k : n - 1];
}

void warp_metrics_finish(warp_metrics *m)
{
    uint64_t total = 0;
    for (int s = 0; s <= VG_STAGE_CURVE; s++)
        total += m->stage_pixels[s];
    for (int s = 0; s <= VG_STAGE_CURVE; s++)
        m->stage_fraction[s] = total ? (double)m->stage_pixels[s] / (double)total : 0.0;
    m->error_median = percentile(m->errors, m->error_count, 0.5);
    m->error_p99 = percentile(m->errors, m->error_count, 0.99);
    m->error_p99_curve = percentile(m->errors_curve, m->curve_count, 0.99);
    m->hole_fraction = m->reference_geometry ? (double)m->holes / (double)m->reference_geometry : NAN;
    for (int e = 0; e < 2; e++) {
        double mse = m->samples[e] ? m->sq_error[e] / (double)m->samples[e] : NAN;
        m->psnr[e] = mse > 0 ? 10.0 * log10(255.0 * 255.0 / mse) : mse == 0 ? INFINITY : NAN;
    }
}

void warp_metrics_free(warp_metrics *m)
{
    if (!m)
        return;
    free(m->errors);
    free(m->errors_curve);
    memset(m, 0, sizeof *m);
}

double warp_psnr(const uint8_t *a, const uint8_t *b, size_t pixels)
{
    double sq = 0;
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++) {
            double d = (double)a[4 * i + c] - (double)b[4 * i + c];
            sq += d * d;
        }
    double mse = sq / (3.0 * (double)pixels);
    return mse > 0 ? 10.0 * log10(255.0 * 255.0 / mse) : INFINITY;
}
