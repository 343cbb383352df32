/* vergence — files: whole-file reads, atomic writes, PFM, Middlebury .flo, PNG.
 *
 * Every reader checks sizes before it touches memory and logs one error line
 * that names the file and the problem. Every writer writes to a temporary
 * file and renames it into place, so a crash never leaves a half-written file
 * under the final name. Images are row-major with the top row first. */
#pragma once
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

/* Images larger than this are rejected as garbled headers, not allocated. */
#define VG_MAX_PIXELS (1 << 28)

typedef struct vg_imagef {
    int width, height, channels; /* channels: 1 or 3 (PFM), 2 (flow) */
    float *data;                 /* width * height * channels floats, top row first */
} vg_imagef;

vg_status vg_imagef_alloc(vg_imagef *img, int width, int height, int channels);
void vg_imagef_free(vg_imagef *img);

/* Reads a whole file; *data is NUL-terminated (not counted in *size). */
vg_status vg_file_read(const char *path, uint8_t **data, size_t *size);
/* Writes data to path.tmp then renames it to path. */
vg_status vg_file_write_atomic(const char *path, const void *data, size_t size);
/* write(2) of every byte (one error line naming path); honours the injected
 * "disk full" (core/fault.h). */
vg_status vg_write_all(int fd, const void *data, size_t size, const char *path);

/* A watched folder records every file vg_file_write_atomic finishes under
 * it (and vg_write_watch_add for files written by other means): the
 * manifest of a result lists exactly those (core/manifest.h). Watches nest;
 * a file is recorded by every watch of a folder that holds it. */
typedef struct vg_written {
    char *name;                  /* relative to the watched folder */
    uint64_t bytes;
} vg_written;
typedef struct vg_write_watch {
    char dir[1024];
    vg_written *files;
    int count, cap;
    bool failed;                 /* out of memory: a file went unrecorded */
    struct vg_write_watch *next;
} vg_write_watch;
void vg_write_watch_begin(vg_write_watch *w, const char *dir);
void vg_write_watch_end(vg_write_watch *w);
vg_status vg_write_watch_add(const char *path);
/* mkdir -p, then proves the folder is writable by creating a probe file. */
vg_status vg_dir_prepare(const char *path);
/* Joins dir and name into out (size cap); returns VG_ERR_ARG when too long. */
vg_status vg_path_join(char *out, size_t cap, const char *dir, const char *name);

/* Portable Float Map: "Pf" (1 channel) or "PF" (3 channels), either endianness. */
vg_status vg_pfm_read(const char *path, vg_imagef *out);
/* The same from memory; `path` only names the data in errors. */
vg_status vg_pfm_parse(const char *path, const uint8_t *data, size_t size, vg_imagef *out);
vg_status vg_pfm_write(const char *path, const vg_imagef *img);

/* A disparity PNG of a stereo dataset, in pixels (x_left - x_right):
 * KITTI's 16-bit grey (d = v / 256, v = 0: unknown) or Sintel's 8-bit RGB
 * (d = 4 R + G / 64 + B / 16384). Unknown pixels are +inf (as Middlebury's
 * PFM). `*encoding` names which ("KITTI" or "Sintel"). */
vg_status vg_disparity_png_read(const char *path, vg_imagef *out, const char **encoding);
/* The same from memory; `path` only names the data in errors. A colour
 * picture (R, G and B that rise together) is refused: it is not Sintel's. */
vg_status vg_disparity_png_parse(const char *path, const uint8_t *data, size_t size, vg_imagef *out,
                                 const char **encoding);

/* Middlebury .flo: magic 202021.25, int32 width, int32 height, (u, v) floats. */
vg_status vg_flo_read(const char *path, vg_imagef *out);
vg_status vg_flo_parse(const char *path, const uint8_t *data, size_t size, vg_imagef *out);
vg_status vg_flo_write(const char *path, const vg_imagef *img);

/* 8-bit PNG (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA). The pixel buffer from
 * vg_png_read is freed with free(). */
vg_status vg_png_write(const char *path, int width, int height, int comp, const uint8_t *pixels);
/* The same into memory (*png freed with free()), with stb's defaults pinned. */
vg_status vg_png_encode(int width, int height, int comp, const uint8_t *pixels, uint8_t **png, size_t *size);
vg_status vg_png_read(const char *path, int *width, int *height, int comp, uint8_t **pixels);
/* A 16-bit grey PNG (depth as monocular estimators and depth cameras write
 * it) as its values 0..65535; any other PNG is refused with one line. */
vg_status vg_grey16_png_read(const char *path, vg_imagef *out);
/* The same written, through libpng. */
vg_status vg_png_write_grey16(const char *path, int width, int height, const uint16_t *grey);

/* A PNG decoded from memory by libpng. Set comp (1 to 4 channels) and bits (8
 * or 16, host byte order) to what you want; comp 0 reads the header only.
 * The file's own channels and bits are reported beside. */
typedef struct vg_png_image {
    int comp, bits;          /* asked for */
    int width, height;       /* read */
    int file_comp, file_bits; /* the file's channels (palette: 3, or 4 with tRNS) and bit depth */
    void *pixels;            /* width * height * comp samples, freed with free() */
} vg_png_image;
/* false with the reason in why (no log line: the caller names the file). */
bool vg_png_decode(const uint8_t *data, size_t size, vg_png_image *img, char *why, size_t cap);
