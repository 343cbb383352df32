/* vergence — PNG files through stb (io.h): 8-bit images for people and
 * tests, and the 16-bit and 8-bit disparity PNGs of KITTI and Sintel. A file
 * of its own so that what links io.c for PFM and .flo (the SDK's library
 * among them) does not link stb. */
#include "io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>
#include <setjmp.h>
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

/* libpng writes into memory through this, then core/io renames it into place. */
static void png_sink_write_png(png_structp png, png_bytep data, size_t size)
{
    png_sink_write(png_get_io_ptr(png), data, (int)size);
}

static void png_sink_flush(png_structp png)
{
    (void)png;
}

vg_status vg_png_write_grey16(const char *path, int width, int height, const uint16_t *grey)
{
    png_sink sink = {0};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *volatile row = NULL;
    vg_status st = VG_ERR_NOMEM;
    if (!info || width <= 0 || height <= 0 || (size_t)width * height > VG_MAX_PIXELS)
        goto done;
    if (setjmp(png_jmpbuf(png)))
        goto done;
    png_set_write_fn(png, &sink, png_sink_write_png, png_sink_flush);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 16, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    if (!(row = malloc((size_t)width * 2)))
        goto done;
    for (int y = 0; y < height; y++) {
        for (int x = 0; x < width; x++) { /* PNG samples are big-endian */
            uint16_t v = grey[(size_t)y * width + x];
            row[2 * x] = (uint8_t)(v >> 8), row[2 * x + 1] = (uint8_t)v;
        }
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    st = sink.failed ? VG_ERR_NOMEM : VG_OK;
done:
    free(row);
    png_destroy_write_struct(&png, &info);
    if (st == VG_OK)
        st = vg_file_write_atomic(path, sink.data, sink.size);
    else
        vg_error("%s: PNG encoding of a %dx%d 16-bit image failed; not written", path, width, height);
    free(sink.data);
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

/* ------------------------------------------------------------------------- */
/* Decoding through libpng                                                    */
/* ------------------------------------------------------------------------- */

/* libpng, not stb, decodes: stb 2.27 (Debian 12) reads zero bits past the end
 * of a truncated IDAT stream and inflates them until its buffer reaches 2 GiB
 * (a 200-byte file found by fuzz.disparity_png); libpng stops at the data's
 * end with an error, checks each chunk's CRC, and bounds what a header may
 * claim (png_set_user_limits). */
typedef struct png_job {
    const uint8_t *next;
    size_t left;
    char why[160];
} png_job;

static void png_job_read(png_structp png, png_bytep out, size_t n)
{
    png_job *job = png_get_io_ptr(png);
    if (n > job->left)
        png_error(png, "the file ends inside a chunk");
    memcpy(out, job->next, n);
    job->next += n;
    job->left -= n;
}

static void png_job_error(png_structp png, png_const_charp msg)
{
    png_job *job = png_get_error_ptr(png);
    snprintf(job->why, sizeof job->why, "%s", msg);
    png_longjmp(png, 1);
}

static void png_job_warning(png_structp png, png_const_charp msg)
{
    (void)png, (void)msg; /* ancillary trouble (a bad sRGB chunk) does not stop a decode */
}

bool vg_png_decode(const uint8_t *data, size_t size, vg_png_image *img, char *why, size_t cap)
{
    /* img->comp and img->bits are the request; 0 asks for the header only. */
    int comp = img->comp, bits = img->bits;
    png_job job = {.next = data, .left = size};
    img->pixels = NULL;
    if (size < 8 || png_sig_cmp(data, 0, 8)) {
        snprintf(why, cap, "not a PNG file (its first 8 bytes are not PNG's signature)");
        return false;
    }
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &job, png_job_error, png_job_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info) {
        png_destroy_read_struct(&png, NULL, NULL);
        snprintf(why, cap, "out of memory");
        return false;
    }
    uint8_t *volatile pixels = NULL;
    png_bytep *volatile rows = NULL;
    if (setjmp(png_jmpbuf(png))) {
        free(pixels);
        free(rows);
        png_destroy_read_struct(&png, &info, NULL);
        snprintf(why, cap, "%s", job.why);
        return false;
    }
    png_set_read_fn(png, &job, png_job_read);
    png_set_user_limits(png, 1u << 20, 1u << 20);
    png_set_chunk_malloc_max(png, 1u << 24);
    png_read_info(png, info);
    int type = png_get_color_type(png, info), depth = png_get_bit_depth(png, info);
    img->width = (int)png_get_image_width(png, info);
    img->height = (int)png_get_image_height(png, info);
    img->file_bits = depth;
    img->file_comp = png_get_channels(png, info);
    if (type == PNG_COLOR_TYPE_PALETTE)
        img->file_comp = png_get_valid(png, info, PNG_INFO_tRNS) ? 4 : 3;
    if ((double)img->width * img->height > VG_MAX_PIXELS)
        png_error(png, "more pixels than vergence reads (2^28)");
    if (comp == 0) {
        png_destroy_read_struct(&png, &info, NULL);
        return true;
    }
    /* To `comp` channels of `bits`: palette and low-bit grey expanded,
     * colour made grey (libpng's Rec. 709 weights) or grey made colour,
     * alpha dropped or added opaque, as stb's req_comp did. */
    png_set_expand(png);
    if (depth == 16 && bits == 8)
        png_set_strip_16(png);
    if (depth < 16 && bits == 16)
        png_set_expand_16(png);
    if (bits == 16)
        png_set_swap(png);
    bool colour = type & PNG_COLOR_MASK_COLOR;
    bool alpha = (type & PNG_COLOR_MASK_ALPHA) || png_get_valid(png, info, PNG_INFO_tRNS);
    if (colour && comp <= 2)
        png_set_rgb_to_gray_fixed(png, 1, -1, -1);
    if (!colour && comp >= 3)
        png_set_gray_to_rgb(png);
    if (alpha && (comp == 1 || comp == 3))
        png_set_strip_alpha(png);
    if (!alpha && (comp == 2 || comp == 4))
        png_set_add_alpha(png, bits == 16 ? 0xffff : 0xff, PNG_FILLER_AFTER);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    size_t row = (size_t)img->width * (size_t)comp * (size_t)(bits / 8);
    if (png_get_rowbytes(png, info) != row)
        png_error(png, "libpng's rows are not the size asked for");
    pixels = malloc(row * (size_t)img->height);
    rows = malloc(sizeof(png_bytep) * (size_t)img->height);
    if (!pixels || !rows)
        png_error(png, "out of memory");
    for (int y = 0; y < img->height; y++)
        rows[y] = pixels + row * (size_t)y;
    png_read_image(png, rows);
    free(rows);
    png_destroy_read_struct(&png, &info, NULL);
    img->pixels = pixels;
    return true;
}

/* vg_png_decode with its failure said in one line naming the file. */
static bool decode_named(const char *path, const uint8_t *buf, size_t size, vg_png_image *img)
{
    char why[200];
    if (vg_png_decode(buf, size, img, why, sizeof why))
        return true;
    vg_error("%s: cannot decode PNG: %s", path, why);
    return false;
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
    vg_png_image img = {0};
    if (!decode_named(path, buf, size, &img))
        return VG_ERR_FORMAT;
    bool deep = img.file_bits == 16;
    if (!(deep && img.file_comp == 1) && !(!deep && img.file_comp >= 3)) {
        vg_error("%s: a disparity PNG is KITTI's 16-bit grey or Sintel's 8-bit RGB; this one is %d-bit with %d "
                 "channel(s)", path, img.file_bits, img.file_comp);
        return VG_ERR_FORMAT;
    }
    img.comp = deep ? 1 : 3;
    img.bits = deep ? 16 : 8;
    if (!decode_named(path, buf, size, &img))
        return VG_ERR_FORMAT;
    int w = img.width, h = img.height;
    void *px = img.pixels;
    if ((st = vg_imagef_alloc(out, w, h, 1)) != VG_OK) {
        free(px);
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
            free(px);
            vg_imagef_free(out);
            return VG_ERR_FORMAT;
        }
        for (size_t i = 0; i < count; i++)
            out->data[i] = 4.0f * c[3 * i] + c[3 * i + 1] / 64.0f + c[3 * i + 2] / 16384.0f;
        *encoding = "Sintel";
    }
    free(px);
    return VG_OK;
}

vg_status vg_grey16_png_read(const char *path, vg_imagef *out)
{
    uint8_t *buf;
    size_t size;
    *out = (vg_imagef){0};
    vg_status st = vg_file_read(path, &buf, &size);
    if (st != VG_OK)
        return st;
    vg_png_image img = {0}; /* the header first: the file must be 16-bit grey */
    bool ok = decode_named(path, buf, size, &img);
    if (ok && (img.file_comp != 1 || img.file_bits != 16)) {
        vg_error("%s: a 16-bit grey PNG is needed; this one is %d-bit with %d channel(s)", path, img.file_bits,
                 img.file_comp);
        ok = false;
    }
    img.comp = 1;
    img.bits = 16;
    ok = ok && decode_named(path, buf, size, &img);
    free(buf);
    if (!ok)
        return VG_ERR_FORMAT;
    if ((st = vg_imagef_alloc(out, img.width, img.height, 1)) == VG_OK) {
        const uint16_t *v = img.pixels;
        for (size_t i = 0; i < (size_t)img.width * img.height; i++)
            out->data[i] = (float)v[i];
    }
    free(img.pixels);
    return st;
}

vg_status vg_png_read(const char *path, int *width, int *height, int comp, uint8_t **pixels)
{
    uint8_t *buf;
    size_t size;
    *pixels = NULL;
    vg_status st = vg_file_read(path, &buf, &size);
    if (st != VG_OK)
        return st;
    vg_png_image img = {.comp = comp, .bits = 8};
    bool ok = decode_named(path, buf, size, &img);
    free(buf);
    if (!ok)
        return VG_ERR_FORMAT;
    *width = img.width;
    *height = img.height;
    *pixels = img.pixels;
    return VG_OK;
}
