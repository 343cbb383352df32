/* vergence — forward image warping with a z-buffer, on the CPU. */
#include "image_warp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

long image_warp(const uint8_t *src, int w, int h, int channels, const float *shift, const float *z, uint8_t *dst,
                float *z_out, uint8_t *hole)
{
    float *zb = z_out ? z_out : malloc((size_t)w * sizeof(float));
    long holes = 0;
    if (!zb)
        return -1;
    for (int y = 0; y < h; y++) {
        size_t row = (size_t)y * w;
        float *zr = z_out ? zb + row : zb;
        for (int x = 0; x < w; x++)
            zr[x] = INFINITY;
        memset(dst + row * channels, 0, (size_t)w * channels);
        for (int x = 0; x < w; x++) {
            float to = floorf((float)x + 0.5f + shift[row + x]);
            if (!(to >= 0.0f && to < (float)w))
                continue; /* off the image, or NaN */
            int t = (int)to;
            if (!(z[row + x] < zr[t]))
                continue;
            zr[t] = z[row + x];
            memcpy(dst + (row + t) * channels, src + (row + x) * channels, (size_t)channels);
        }
        for (int x = 0; x < w; x++) {
            bool empty = isinf(zr[x]) && zr[x] > 0;
            holes += empty;
            if (hole)
                hole[row + x] = empty;
        }
    }
    if (!z_out)
        free(zb);
    return holes;
}

void image_warp_fill(uint8_t *dst, int w, int h, int channels, const float *z_out, const uint8_t *hole)
{
    for (int y = 0; y < h; y++) {
        size_t row = (size_t)y * w;
        for (int x = 0; x < w;) {
            if (!hole[row + x]) {
                x++;
                continue;
            }
            int a = x;
            while (x < w && hole[row + x])
                x++;
            int left = a - 1, right = x; /* the run's neighbours, -1 or w at the border */
            int from = left < 0 ? right : right >= w ? left : z_out[row + left] >= z_out[row + right] ? left : right;
            if (from < 0 || from >= w)
                continue; /* an empty row */
            for (int k = a; k < x; k++)
                memcpy(dst + (row + k) * channels, dst + (row + from) * channels, (size_t)channels);
        }
    }
}
