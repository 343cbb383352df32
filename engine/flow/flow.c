/* vergence — what the flow module does in C (flow.h): the forward-backward
 * consistency check (Sundaram, Brox, Keutzer 2010) and the end-point error
 * the tests and docs/formats.md measure the flow by. */
#include "flow.h"

#include <math.h>
#include <stddef.h>

/* Bilinear sample of a 2-channel flow at (x, y), inside [0, w-1] x [0, h-1]. */
static void sample(const float *flow, int w, int h, float x, float y, float *u, float *v)
{
    int x0 = (int)x, y0 = (int)y;
    int x1 = x0 + 1 < w ? x0 + 1 : x0, y1 = y0 + 1 < h ? y0 + 1 : y0;
    float fx = x - (float)x0, fy = y - (float)y0;
    const float *a = flow + ((size_t)y0 * w + x0) * 2, *b = flow + ((size_t)y0 * w + x1) * 2;
    const float *c = flow + ((size_t)y1 * w + x0) * 2, *d = flow + ((size_t)y1 * w + x1) * 2;
    *u = (1 - fy) * ((1 - fx) * a[0] + fx * b[0]) + fy * ((1 - fx) * c[0] + fx * d[0]);
    *v = (1 - fy) * ((1 - fx) * a[1] + fx * b[1]) + fy * ((1 - fx) * c[1] + fx * d[1]);
}

long flow_occlusions(const float *fwd, const float *bwd, int width, int height, uint8_t *occluded)
{
    if (!fwd || !bwd || width < 1 || height < 1)
        return 0;
    long count = 0;
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            size_t i = (size_t)y * width + x;
            float u = fwd[2 * i], v = fwd[2 * i + 1];
            float tx = (float)x + u, ty = (float)y + v;
            bool occ = !(tx >= 0.0f && tx <= (float)(width - 1) && ty >= 0.0f && ty <= (float)(height - 1));
            if (!occ) {
                float bu, bv;
                sample(bwd, width, height, tx, ty, &bu, &bv);
                float du = u + bu, dv = v + bv;
                float lhs = du * du + dv * dv;
                float rhs = FLOW_CHECK_REL * (u * u + v * v + bu * bu + bv * bv) + FLOW_CHECK_ABS;
                occ = !(lhs <= rhs); /* NaN: occluded */
            }
            if (occluded)
                occluded[i] = occ;
            count += occ;
        }
    return count;
}

void flow_fill_occluded(float *flow, const uint8_t *occluded, int width, int height)
{
    for (int y = 0; y < height; y++) {
        float *row = flow + (size_t)y * width * 2;
        const uint8_t *o = occluded + (size_t)y * width;
        int last = -1;
        for (int x = 0; x <= width; x++) {
            if (x < width && o[x])
                continue;
            /* a run of occluded pixels in (last, x): each takes its nearer kept end */
            for (int k = last + 1; k < x; k++) {
                int from = last < 0 ? x : x >= width ? last : (x - k <= k - last ? x : last);
                if (from < 0 || from >= width) {
                    row[2 * k] = row[2 * k + 1] = NAN;
                    continue;
                }
                row[2 * k] = row[2 * from];
                row[2 * k + 1] = row[2 * from + 1];
            }
            last = x;
        }
    }
}

double flow_epe(const float *a, const float *b, int width, int height, const uint8_t *mask, long *count)
{
    double sum = 0;
    long n = 0;
    for (size_t i = 0; a && b && width > 0 && height > 0 && i < (size_t)width * height; i++) {
        if (mask && mask[i])
            continue;
        double du = (double)a[2 * i] - b[2 * i], dv = (double)a[2 * i + 1] - b[2 * i + 1];
        sum += sqrt(du * du + dv * dv);
        n++;
    }
    if (count)
        *count = n;
    return n ? sum / (double)n : NAN;
}
