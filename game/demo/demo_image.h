/* vergence demo — the pictures of the report, from a frame's readback. */
#pragma once
#include <stdint.h>

#include "core/status.h"
#include "pass/frame_types.h"

/* RGBA8 -> RGB8 PNG at DIR/NAME. */
vg_status demo_png_rgba(const char *dir, const char *name, const uint8_t *rgba, uint32_t w, uint32_t h);
/* The two eyes side by side (left | right, a 4 px gap) as an RGB PNG. */
vg_status demo_png_sbs(const char *dir, const char *name, const uint8_t *left, const uint8_t *right,
                       uint32_t w, uint32_t h);
/* The cascade debug view (paper Fig. 5): the left eye tinted by the stage
 * that gave each pixel's vertices their disparity. */
vg_status demo_png_cascade(const char *dir, const char *name, const frame_outputs *fo, uint32_t w, uint32_t h);
/* An eye with its holes (nothing rendered there: alpha 0) in magenta;
 * returns the fraction of such pixels in *holes when not NULL. */
vg_status demo_png_holes(const char *dir, const char *name, const uint8_t *eye, uint32_t w, uint32_t h,
                         double *holes);
/* An x-t slice: rows samples, columns w, values in [lo, hi] through the
 * colour map (figure/figure.h), each sample repeated `repeat` times
 * vertically. NAN is grey. */
vg_status demo_png_xt(const char *dir, const char *name, const float *v, int w, int rows, int repeat,
                      float lo, float hi);
