/* vergence — PNG files through stb (io.h): 8-bit images for people and
 * tests, and the 16-bit and 8-bit disparity PNGs of KITTI and Sintel. A file
 * of its own so that what links io.c for PFM and .flo (the SDK's library
 * among them) does not link stb. */
#include "io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>
#include <stb_image_write.h>

#include "log.h"

/* ------------------------------------------------------------------------- */
/* PNG                                                                       */
/* ------------------------------------------------------------------------- */

typedef struct png_sink {
    uint8_t *data;
    size_t size, cap;
    int failed;
} png_sink;

static void png_sink_write(void *ctx, void *data, int size)
{
    png_sink *s = ctx;
    if (s->failed || size <= 0)
        return;
    if (s->size + (size_t)size > s->cap) {
        size_t cap = s->cap ? s->cap * 2 : 65536;
        while (cap < s->size + (size_t)size)
            cap *= 2;
        uint8_t *p = realloc(s->data, cap);
        if (!p) {
            s->failed = 1;
            return;
        }
        s->data = p;
        s->cap = cap;
    }
    memcpy(s->data + s->size, data, (size_t)size);
    s->size += (size_t)size;
}

vg_status vg_png_encode(int width, int height, int comp, const uint8_t *pixels, uint8_t **png, size_t *size)
{
    /* stb's defaults, pinned here: other code in the process must not be able
     * to change the bytes (committed textures, captures) through these globals. */
    stbi_write_png_compression_level = 8;
    stbi_write_force_png_filter = -1;
    png_sink sink = {0};
    int ok = stbi_write_png_to_func(png_sink_write, &sink, width, height, comp, pixels, width * comp);
    *png = NULL;
    *size = 0;
    if (!ok || sink.failed) {
        free(sink.data);
        vg_error("PNG encoding of a %dx%d image failed", width, height);
        return VG_ERR_NOMEM;
    }
    *png = sink.data;
    *size = sink.size;
    return VG_OK;
}

vg_status vg_png_write(const char *path, int width, int height, int comp, const uint8_t *pixels)
{
    uint8_t *png;
    size_t size;
    vg_status st = vg_png_encode(width, height, comp, pixels, &png, &size);
    if (st == VG_OK)
        st = vg_file_write_atomic(path, png, size);
    else
        vg_error("%s: not written", path);
    free(png);
    return st;
}

/* Pearson correlation of two channels of 8-bit RGB pixels (0 when one is constant). */
static double channel_correlation(const uint8_t *c, size_t count, int a, int b)
{
    double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
    for (size_t i = 0; i < count; i++) {
        double x = c[3 * i + (size_t)a], y = c[3 * i + (size_t)b];
        sa += x, sb += y, saa += x * x, sbb += y * y, sab += x * y;
    }
    double va = saa - sa * sa / (double)count, vb = sbb - sb * sb / (double)count;
    return va > 0 && vb > 0 ? (sab - sa * sb / (double)count) / sqrt(va * vb) : 0.0;
}

vg_status vg_disparity_png_read(const char *path, vg_imagef *out, const char **encoding)
{
    uint8_t *buf;
    size_t size;
    *out = (vg_imagef){0};
    vg_status st = vg_file_read(path, &buf, &size);
    if (st != VG_OK)
        return st;
    st = vg_disparity_png_parse(path, buf, size, out, encoding);
    free(buf);
    return st;
}

vg_status vg_disparity_png_parse(const char *path, const uint8_t *buf, size_t size, vg_imagef *out,
                                 const char **encoding)
{
    vg_status st;
    *out = (vg_imagef){0};
    int w = 0, h = 0, n = 0;
    bool ok = size <= 0x7fffffff && stbi_info_from_memory(buf, (int)size, &w, &h, &n);
    bool deep = ok && stbi_is_16_bit_from_memory(buf, (int)size);
    void *px = NULL;
    if (ok && deep && n == 1)
        px = stbi_load_16_from_memory(buf, (int)size, &w, &h, &n, 1);
    else if (ok && !deep && n >= 3)
        px = stbi_load_from_memory(buf, (int)size, &w, &h, &n, 3);
    if (!px) {
        if (ok)
            vg_error("%s: a disparity PNG is KITTI's 16-bit grey or Sintel's 8-bit RGB; this one is %d-bit with %d "
                     "channel(s)", path, deep ? 16 : 8, n);
        else
            vg_error("%s: cannot decode image: %s", path, stbi_failure_reason());
        return VG_ERR_FORMAT;
    }
    if ((st = vg_imagef_alloc(out, w, h, 1)) != VG_OK) {
        stbi_image_free(px);
        return st;
    }
    size_t count = (size_t)w * h;
    if (deep) {
        const uint16_t *v = px;
        for (size_t i = 0; i < count; i++)
            out->data[i] = v[i] ? (float)v[i] / 256.0f : INFINITY;
        *encoding = "KITTI";
    } else {
        /* Sintel's G and B hold the fraction bits of the disparity R counts
         * in steps of 4 px: they do not rise with R or with each other, as
         * the channels of a colour picture do. */
        const uint8_t *c = px;
        double rg = channel_correlation(c, count, 0, 1), gb = channel_correlation(c, count, 1, 2);
        if (rg > 0.5 && gb > 0.5) {
            vg_error("%s: looks like a colour picture, not a Sintel disparity PNG: its R, G and B rise together "
                     "(correlation R-G %.2f, G-B %.2f) where Sintel's G and B hold the fraction bits of the disparity",
                     path, rg, gb);
            stbi_image_free(px);
            vg_imagef_free(out);
            return VG_ERR_FORMAT;
        }
        for (size_t i = 0; i < count; i++)
            out->data[i] = 4.0f * c[3 * i] + c[3 * i + 1] / 64.0f + c[3 * i + 2] / 16384.0f;
        *encoding = "Sintel";
    }
    stbi_image_free(px);
    return VG_OK;
}

vg_status vg_png_read(const char *path, int *width, int *height, int comp, uint8_t **pixels)
{
    uint8_t *buf;
    size_t size;
    *pixels = NULL;
    vg_status st = vg_file_read(path, &buf, &size);
    if (st != VG_OK)
        return st;
    int n;
    *pixels = size <= 0x7fffffff ? stbi_load_from_memory(buf, (int)size, width, height, &n, comp) : NULL;
    free(buf);
    if (!*pixels) {
        vg_error("%s: cannot decode image: %s", path, stbi_failure_reason());
        return VG_ERR_FORMAT;
    }
    return VG_OK;
}
