/* vergence — the warp's global depth -> vergence curve on the CPU: the same
 * algorithm as the warp.curve passes (shaders/curve*.comp), for the offline
 * baker and as their oracle, and the curve file format.
 *
 * Bins uniform in inverse depth over the pairs' range; each populated bin
 * holds the centroid of its pairs (mean inverse depth, mean vergence); an
 * empty bin takes its centre and the value linear between the nearest
 * populated centroids (constant past the ends). The warp reads it linearly
 * between consecutive centroids (cascade.glsl).
 *
 * File (little-endian): "VGCV", uint32 version 1, uint32 bins, then the
 * vg_curve struct of shared.h as stored on the GPU. */
#pragma once
#include <stddef.h>

#include "core/status.h"
#include "shared.h"

/* Builds a curve from n pairs; pairs with non-positive or non-finite depth
 * or vergence are skipped. */
vg_status curve_cpu_build(const float *depth, const float *vergence, size_t n, vg_curve *out);
/* The curve at depth z, linear between centroids, extended linearly past the
 * ends like the shader (CURVE_REACH bins apart). */
float curve_cpu_eval(const vg_curve *c, float z);

vg_status curve_file_write(const char *path, const vg_curve *c);
vg_status curve_file_read(const char *path, vg_curve *c);
