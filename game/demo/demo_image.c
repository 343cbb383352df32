/* vergence demo — pictures: eyes, side-by-side pairs, the cascade view,
 * holes of the image-warping baseline, x-t slices through a colour map. */
#include "demo_image.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "capture/capture_image.h"
#include "core/io.h"
#include "figure/figure.h"
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

vg_status demo_png_xt(const char *dir, const char *name, const float *v, int w, int rows, int repeat,
                      float lo, float hi)
{
    char path[4096];
    vg_status st = vg_path_join(path, sizeof path, dir, name);
    return st == VG_OK ? figure_map_png(path, v, w, rows, repeat, lo, hi, NULL) : st;
}
