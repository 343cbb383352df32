/* vergence — the global depth -> disparity curve (paper Sec. 4.6), the last
 * resort of the 3D warp for vertices no disparity sample covers.
 *
 * From (depth, disparity) pairs of a frame, in two passes:
 *   1. bandwidth: a histogram of depth; for every bin the distance (in bins)
 *      to the nearest populated bin on each side;
 *   2. reconstruction: each pair spreads its disparity with a hat kernel
 *      whose support on each side reaches the next populated bin, weighted by
 *      1 / (pairs in its bin) so that every populated bin carries unit mass.
 * In populated runs this is a tent filter over +-1 bin; across empty bins it
 * is exactly linear between the bracketing bins (docs/method.md "Curve").
 * Bins are uniform in inverse depth. Layout shared with GLSL: mid_shared.h. */
#pragma once
#include "core/parallel.h"
#include "core/status.h"
#include "mid_shared.h"

typedef struct disp_curve {
    disp_curve_header header;
    float value[DISP_CURVE_BINS]; /* disparity at each bin centre, arcmin */
} disp_curve;

typedef struct disp_curve_desc {
    int bins;                    /* 0 = DISP_CURVE_BINS (at most that) */
    float depth_min, depth_max;  /* domain; both 0 = the pairs' range */
} disp_curve_desc;

/* Pairs with a non-positive or non-finite depth or disparity are skipped. */
vg_status disp_curve_build(const disp_curve_desc *desc, const float *depth, const float *disparity,
                           int n, disp_curve *out, vg_pool *pool);
/* Linear interpolation between bin centres; the end segments extend half a
 * bin to the domain ends, and the curve is held beyond the domain. */
float disp_curve_eval(const disp_curve *c, float depth);
