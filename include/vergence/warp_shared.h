/* vergence — what the warp's C and GLSL sides share (vergence/lang.h's
 * subset of both): the cascade's stage ids and the global curve's layout.
 * include/vergence/warp.glsl and the engine's shaders include it, the
 * engine's C code too (the CPU curve, captures, warp metrics). */
#ifndef VERGENCE_WARP_SHARED_H
#define VERGENCE_WARP_SHARED_H

#include "lang.h"

/* The cascade's stages (paper 4.6, Fig. 5): vgx_cascade's y,
 * vgx_warp_vertex's one-hot, the captures' stage image. */
#define VGX_STAGE_NONE 0
#define VGX_STAGE_DIRECT 1
#define VGX_STAGE_NEIGHBORHOOD 2
#define VGX_STAGE_HALTON 3
#define VGX_STAGE_CURVE 4

/* The global depth -> vergence curve (paper 4.6): bins uniform in inverse
 * depth; each holds the centroid of its pairs (mean inverse depth, mean
 * vergence), and the curve is linear in inverse depth between consecutive
 * centroids (vergence/curve.h evaluates it). The warp's storage buffer
 * holds one, std430 or scalar alike. */
#define VGX_CURVE_BINS 256
/* Bins between the two nodes of an end slope: the curve continues linearly
 * past its covered range with the slope over this many bins. */
#define VGX_CURVE_REACH 16
VGX_STRUCT(vgx_curve_data) {
    float inv_depth_near;            /* 1 / the smallest depth covered */
    float inv_depth_far;             /* 1 / the largest */
    uint valid;                      /* 0: no pairs were seen, the curve is unusable */
    uint pad;
    float inv_depth[VGX_CURVE_BINS]; /* the nodes: centroids, 1/m (bin centre for empty bins) */
    float vergence[VGX_CURVE_BINS];  /* arcmin at each node */
};

#endif /* VERGENCE_WARP_SHARED_H */
