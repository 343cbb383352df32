/* vergence — warp.curve on the GPU (paper 4.6): the global depth ->
 * vergence curve of a target map, the last stage of the warp's cascade
 * (include/vergence/warp.glsl). Three passes in a fixed order, so the curve
 * is the same on every run and device (shaders/curve.glsl):
 *   warp.curve.range    the inverse-depth range, per 64x64 tile then over them
 *   warp.curve.bins     per tile and bin: counts and fixed-point sums
 *   warp.curve.resolve  per bin: the centroid; empty bins interpolated.
 * The frame's warp (warp_gpu) and the SDK add them alike. */
#pragma once
#include <stdint.h>

#include "gpu/pipeline.h"
#include "graph/graph.h"

typedef struct curve_gpu curve_gpu;

vg_status curve_gpu_create(gpu *g, uint32_t width, uint32_t height, curve_gpu **out);
void curve_gpu_destroy(curve_gpu *c);
/* Adds the passes: the curve (a vgx_curve_data buffer) of the (depth, target)
 * pairs of the pixels nearer than the background depth (depth and target
 * R32F storage images, width x height). */
void curve_gpu_add(curve_gpu *c, rg_graph *g, rg_res depth, rg_res target, rg_res curve);
/* This frame's background depth (the camera's far plane): pixels at or
 * beyond 0.999 of it are not geometry. */
void curve_gpu_set_background(curve_gpu *c, float depth);
