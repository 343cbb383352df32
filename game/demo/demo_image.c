/* vergence demo — pictures: eyes, side-by-side pairs, the cascade view,
 * holes of the image-warping baseline, x-t slices through a colour map. */
#include "demo_image.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "capture/capture_image.h"
#include "core/io.h"
#include "shared.h"

/* ------------------------------------------------------------------------- */
/* Writing                                                                   */
/* ------------------------------------------------------------------------- */

static vg_status write_rgb(const char *dir, const char *name, const uint8_t *rgb, uint32_t w, uint32_t h)
{
    char path[4096];
    vg_status st = vg_path_join(path, sizeof path, dir, name);
    if (st == VG_OK)
        st = vg_png_write(path, (int)w, (int)h, 3, rgb);
    return st;
}

vg_status demo_png_rgba(const char *dir, const char *name, const uint8_t *rgba, uint32_t w, uint32_t h)
{
    size_t px = (size_t)w * h;
    uint8_t *rgb = malloc(px * 3);
    if (!rgb)
        return VG_ERR_NOMEM;
    for (size_t i = 0; i < px; i++)
        memcpy(rgb + 3 * i, rgba + 4 * i, 3);
    vg_status st = write_rgb(dir, name, rgb, w, h);
    free(rgb);
    return st;
}

#define SBS_GAP 4

vg_status demo_png_sbs(const char *dir, const char *name, const uint8_t *left, const uint8_t *right,
                       uint32_t w, uint32_t h)
{
    uint32_t ow = 2 * w + SBS_GAP;
    uint8_t *rgb = malloc((size_t)ow * h * 3);
    if (!rgb)
        return VG_ERR_NOMEM;
    memset(rgb, 255, (size_t)ow * h * 3);
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x, o = (size_t)y * ow + x;
            memcpy(rgb + 3 * o, left + 4 * i, 3);
            memcpy(rgb + 3 * (o + w + SBS_GAP), right + 4 * i, 3);
        }
    vg_status st = write_rgb(dir, name, rgb, ow, h);
    free(rgb);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Debug views                                                               */
/* ------------------------------------------------------------------------- */

vg_status demo_png_cascade(const char *dir, const char *name, const frame_outputs *fo, uint32_t w, uint32_t h)
{
    uint8_t *rgb = malloc((size_t)w * h * 3);
    if (!rgb)
        return VG_ERR_NOMEM;
    capture_image_cascade(fo, w, h, true, rgb);
    vg_status st = write_rgb(dir, name, rgb, w, h);
    free(rgb);
    return st;
}

vg_status demo_png_holes(const char *dir, const char *name, const uint8_t *eye, uint32_t w, uint32_t h,
                         double *holes)
{
    size_t px = (size_t)w * h, count = 0;
    uint8_t *rgb = malloc(px * 3);
    if (!rgb)
        return VG_ERR_NOMEM;
    for (size_t i = 0; i < px; i++) {
        bool hole = eye[4 * i + 3] == 0;
        count += hole;
        static const uint8_t magenta[3] = {255, 0, 200};
        memcpy(rgb + 3 * i, hole ? magenta : eye + 4 * i, 3);
    }
    if (holes)
        *holes = px ? (double)count / (double)px : 0.0;
    vg_status st = write_rgb(dir, name, rgb, w, h);
    free(rgb);
    return st;
}

/* ------------------------------------------------------------------------- */
/* x-t slices                                                                */
/* ------------------------------------------------------------------------- */

void demo_colormap(float t, uint8_t rgb[3])
{
    /* Eight stops of a viridis-like map: ordered in lightness, readable in grey. */
    static const float stops[8][3] = {
        {0.267f, 0.005f, 0.329f}, {0.275f, 0.194f, 0.496f}, {0.213f, 0.359f, 0.552f}, {0.153f, 0.497f, 0.558f},
        {0.122f, 0.633f, 0.531f}, {0.288f, 0.762f, 0.428f}, {0.626f, 0.854f, 0.224f}, {0.993f, 0.906f, 0.144f}};
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    float x = t * 7.0f;
    int i = x >= 7.0f ? 6 : (int)x;
    float u = x - (float)i;
    for (int k = 0; k < 3; k++)
        rgb[k] = (uint8_t)lrintf(255.0f * (stops[i][k] + u * (stops[i + 1][k] - stops[i][k])));
}

vg_status demo_png_xt(const char *dir, const char *name, const float *v, int w, int rows, int repeat,
                      float lo, float hi)
{
    int oh = rows * repeat;
    uint8_t *rgb = malloc((size_t)w * (size_t)oh * 3);
    if (!rgb)
        return VG_ERR_NOMEM;
    float span = hi > lo ? hi - lo : 1.0f;
    for (int r = 0; r < rows; r++)
        for (int x = 0; x < w; x++) {
            float a = v[(size_t)r * (size_t)w + (size_t)x];
            uint8_t c[3] = {128, 128, 128};
            if (isfinite(a))
                demo_colormap((a - lo) / span, c);
            for (int k = 0; k < repeat; k++)
                memcpy(rgb + 3 * ((size_t)(r * repeat + k) * (size_t)w + (size_t)x), c, 3);
        }
    vg_status st = write_rgb(dir, name, rgb, (uint32_t)w, (uint32_t)oh);
    free(rgb);
    return st;
}
