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

/* The centre-view pixel column of an eye pixel's surface point. */
static long centre_column(const float *aux, size_t i)
{
    return lroundf(aux[4 * i] - 0.5f);
}

/* Whether the centre view shows one object, unbroken and at the sides'
 * depths (zmin .. zmax, within WARP_SAME_SURFACE), on row y from where eye
 * pixel l's surface point lies (on its own row) to where eye pixel r's
 * does, two pixels beyond, and on the rows above and below: between the
 * two sides of a crack the surface is whole (a gap narrower than a pixel,
 * which the centre view's samples miss and an eye's may hit, is not). */
static bool centre_unbroken(const frame_outputs *o, const float *aux, uint32_t width, uint32_t height, size_t l,
                            size_t r, uint32_t y, float zmin, float zmax, float *deepest)
{
    long xl = centre_column(aux, l), xr = centre_column(aux, r);
    if (xl < 2 || xr < 2 || xl + 2 >= (long)width || xr + 2 >= (long)width || y < 1 || y + 1 >= height)
        return false;
    uint32_t id = o->ids[(l / width) * width + (size_t)xl];
    if (id == 0 || o->ids[(r / width) * width + (size_t)xr] != id)
        return false;
    /* Two pixels of margin: where the object ends or has a notch within a
     * pixel or two, an eye may rightly show what lies beside it (the eye
     * and the centre view round an edge's sub-pixel place differently). */
    for (uint32_t row = y - 1; row <= y + 1; row++)
        for (long x = (xl < xr ? xl : xr) - 2; x <= (xl < xr ? xr : xl) + 2; x++) {
            size_t k = (size_t)row * width + (size_t)x;
            if (o->ids[k] != id || o->depth[k] < (1.0f - WARP_SAME_SURFACE) * zmin ||
                o->depth[k] > (1.0f + WARP_SAME_SURFACE) * zmax)
                return false;
            *deepest = fmaxf(*deepest, o->depth[k]);
        }
    return true;
}

/* A crack: pixel i shows something farther than the surface on both sides
 * of it (horizontally or vertically, one or two pixels wide), one object at
 * one depth (within WARP_SAME_SURFACE) that the centre view shows unbroken
 * from where one side comes from to where the other does. Sky or a farther
 * surface seen through an object the centre view shows whole is the warp's
 * own doing: the speckles of a crack between patches. (Two objects may
 * rightly part in an eye: parallax opens gaps between them.) */
static bool crack(const uint8_t *eye, const float *aux, const frame_outputs *o, uint32_t width, uint32_t height,
                  size_t i)
{
    uint32_t x = (uint32_t)(i % width), y = (uint32_t)(i / width);
    bool geometry = is_geometry(eye + 4 * i);
    float z = aux[4 * i + 1];
    static const int spans[3][2] = {{1, 1}, {1, 2}, {2, 1}};
    for (int dir = 0; dir < 2; dir++) {
        uint32_t at = dir ? y : x, size = dir ? height : width;
        size_t k = dir ? width : 1;
        for (int s = 0; s < 3; s++) {
            uint32_t a = (uint32_t)spans[s][0], b = (uint32_t)spans[s][1];
            if (at < a || at + b >= size)
                continue;
            size_t l = i - a * k, r = i + b * k;
            if (!is_geometry(eye + 4 * l) || !is_geometry(eye + 4 * r))
                continue;
            float zl = aux[4 * l + 1], zr = aux[4 * r + 1], zs = fmaxf(zl, zr);
            if (fabsf(zl - zr) > WARP_SAME_SURFACE * zs)
                continue;
            /* What the eye shows there lies behind the surface, deeper than
             * the centre view shows it anywhere between (a crevice the eye
             * sees into is no crack). */
            float deepest = zs;
            if ((geometry && z <= (1.0f + WARP_SAME_SURFACE) * zs) ||
                !centre_unbroken(o, aux, width, height, l, r, y, fminf(zl, zr), zs, &deepest))
                continue;
            if (!geometry || z > (1.0f + WARP_SAME_SURFACE) * deepest)
                return true;
        }
    }
    return false;
}

static int luma(const uint8_t *p)
{
    return (2 * p[0] + 5 * p[1] + p[2]) / 8;
}

/* How far an eye pixel's colour is from the centre view's at its surface
 * point (luma, 0..255; the centre colour interpolated along the row), or -1
 * where the centre view shows another surface there (occluded, or off). */
static int deviation(const uint8_t *eye, const float *aux, const frame_outputs *o, uint32_t width, size_t i)
{
    if (!is_geometry(eye + 4 * i))
        return -1;
    float cx = aux[4 * i] - 0.5f, z = aux[4 * i + 1];
    long x0 = (long)floorf(cx);
    if (x0 < 0 || x0 + 1 >= (long)width)
        return -1;
    size_t row = (i / width) * width, k0 = row + (size_t)x0, k1 = k0 + 1;
    if (fabsf(o->depth[k0] - z) > WARP_SAME_SURFACE * z || fabsf(o->depth[k1] - z) > WARP_SAME_SURFACE * z)
        return -1;
    float t = cx - (float)x0, c = (1.0f - t) * (float)luma(o->color + 4 * k0) + t * (float)luma(o->color + 4 * k1);
    return (int)fabsf((float)luma(eye + 4 * i) - c);
}

/* A speckle: an eye pixel whose colour is WARP_SPECKLE_LUMA away from the
 * centre view's at its own surface point while its 8 neighbours match
 * theirs (within a third of that): the isolated red or green dot an
 * anaglyph shows where one eye is wrong, whatever made it wrong (a crack's
 * neighbour, a torn texture, a noisy target). Shading that depends on the
 * eye (highlights) changes whole areas, not single pixels. */
static bool speckle(const uint8_t *eye, const float *aux, const frame_outputs *o, uint32_t width, uint32_t height,
                    size_t i)
{
    uint32_t x = (uint32_t)(i % width), y = (uint32_t)(i / width);
    if (x == 0 || y == 0 || x + 1 >= width || y + 1 >= height || deviation(eye, aux, o, width, i) < WARP_SPECKLE_LUMA)
        return false;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            if (!dx && !dy)
                continue;
            int d = deviation(eye, aux, o, width, i + (size_t)((long)dy * width + dx));
            if (d < 0 || d > WARP_SPECKLE_LUMA / 3)
                return false;
        }
    return true;
}

/* A silhouette pixel of the reference: geometry next to sky or the reverse. */
static bool silhouette(const uint8_t *ref, uint32_t width, uint32_t height, size_t i)
{
    uint32_t x = (uint32_t)(i % width), y = (uint32_t)(i / width);
    int g = is_geometry(ref + 4 * i);
    return (x > 0 && is_geometry(ref + 4 * (i - 1)) != g) || (x + 1 < width && is_geometry(ref + 4 * (i + 1)) != g) ||
           (y > 0 && is_geometry(ref + 4 * (i - width)) != g) ||
           (y + 1 < height && is_geometry(ref + 4 * (i + width)) != g);
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
            if (stage < 0 || stage > VGX_STAGE_CURVE)
                stage = VGX_STAGE_NONE;
            m->stage_pixels[stage]++;
            float err = fabsf(a[2]);
            vg_status st = stage == VGX_STAGE_CURVE ? push(&m->errors_curve, &m->curve_count, &m->curve_cap, err)
                                                   : push(&m->errors, &m->error_count, &m->error_cap, err);
            if (st != VG_OK)
                return st;
        }
        uint64_t cracks = 0;
        for (size_t i = 0; o->ids && o->depth && i < n; i++)
            cracks += crack(eyes[e], aux[e], o, width, height, i);
        for (size_t i = 0; o->color && o->depth && i < n; i++)
            m->speckle_pixels += speckle(eyes[e], aux[e], o, width, height, i);
        m->crack_pixels += cracks;
        m->crack_frame_max = cracks > m->crack_frame_max ? cracks : m->crack_frame_max;
        if (!refs[e])
            continue;
        for (size_t i = 0; i < n; i++) {
            if (interior(refs[e], width, height, i)) {
                m->reference_geometry++;
                m->holes += hole(eyes[e], aux[e], o->ids, width, height, i);
            }
            if (silhouette(refs[e], width, height, i)) {
                m->silhouette_pixels++;
                m->silhouette_flips += is_geometry(eyes[e] + 4 * i) != is_geometry(refs[e] + 4 * i);
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
    for (int s = 0; s <= VGX_STAGE_CURVE; s++)
        total += m->stage_pixels[s];
    for (int s = 0; s <= VGX_STAGE_CURVE; s++)
        m->stage_fraction[s] = total ? (double)m->stage_pixels[s] / (double)total : 0.0;
    m->error_median = percentile(m->errors, m->error_count, 0.5);
    m->error_p99 = percentile(m->errors, m->error_count, 0.99);
    m->error_p99_curve = percentile(m->errors_curve, m->curve_count, 0.99);
    m->hole_fraction = m->reference_geometry ? (double)m->holes / (double)m->reference_geometry : NAN;
    m->crack_fraction = total ? (double)m->crack_pixels / (double)total : 0.0;
    m->speckle_fraction = total ? (double)m->speckle_pixels / (double)total : 0.0;
    m->silhouette_mismatch = m->silhouette_pixels ? (double)m->silhouette_flips / (double)m->silhouette_pixels : NAN;
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
