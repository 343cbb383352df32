/* vergence — the global depth -> vergence curve (paper Sec. 4.6), the last
 * resort of the 3D warp for vertices no disparity sample covers: on the CPU,
 * in the layout the warp.curve passes write on the GPU (vgx_curve_data,
 * vergence/warp_shared.h), so it is their reference (tests/gpu), the
 * offline baker's (`vergence bake-curve`), and its file.
 *
 * Bins uniform in inverse depth over the pairs' range (vergence is nearly
 * linear in 1/z); every populated bin is a node at the centroid of its pairs
 * (mean inverse depth, mean vergence); an empty bin is a node at its centre
 * with the value linear in inverse depth between the nearest populated
 * nodes (the paper's "linear interpolation for empty intervals"), constant
 * past the ends. The curve is linear between consecutive nodes and
 * continues linearly past the first and last node with the slope over
 * VGX_CURVE_REACH bins: vergence/curve.h evaluates it, for the warp's
 * shaders and the CPU alike (vgx_curve_vergence).
 *
 * File (little-endian): "VGCV", uint32 version 1, uint32 bins, then the
 * vgx_curve_data struct as stored on the GPU. */
#pragma once
#include <stddef.h>

#include "core/status.h"
#include "vergence/warp_shared.h"

/* Vergence is an angle below 180 degrees: a curve beyond is not of a scene. */
#define DISP_CURVE_MAX_ARCMIN 10800.0

/* Builds a curve from n (depth, vergence) pairs; pairs with a non-positive
 * or non-finite depth or vergence are skipped (no pair: valid = 0). */
vg_status disp_curve_build(const float *depth, const float *vergence, size_t n, vgx_curve_data *out);

vg_status disp_curve_write(const char *path, const vgx_curve_data *c);
/* Reads and checks a curve file (one error line naming the file). */
vg_status disp_curve_read(const char *path, vgx_curve_data *c);
