/* vergence — the global depth -> disparity curve (paper Sec. 4.6), the last
 * resort of the 3D warp for vertices no disparity sample covers.
 *
 * The same definition as the warp.curve passes on the GPU (shaders/curve*.comp,
 * engine/warp), so this is their reference: bins uniform in inverse depth over
 * the pairs' range (vergence is nearly linear in 1/z); every populated bin is
 * a node at the centroid of its pairs (mean inverse depth, mean disparity); an
 * empty bin gets the value linear in inverse depth between the nearest
 * populated nodes (the paper's bandwidth adapted to the gap: "linear
 * interpolation for empty intervals"), constant past the ends. The curve is
 * linear between consecutive nodes and continues linearly past the first and
 * last node (the slope over DISP_CURVE_REACH bins), as the warp's cascade
 * evaluates it. Layout shared with GLSL: mid_shared.h. */
#pragma once
#include "core/parallel.h"
#include "core/status.h"
#include "mid_shared.h"

/* Bins between the two nodes of an end slope (= cascade.glsl CURVE_REACH). */
#define DISP_CURVE_REACH 16

typedef struct disp_curve {
    disp_curve_header header;
    float value[DISP_CURVE_BINS];     /* disparity at each node, arcmin */
    float inv_depth[DISP_CURVE_BINS]; /* inverse depth of each node (bin centre when empty), 1/m */
} disp_curve;

typedef struct disp_curve_desc {
    int bins;                    /* 0 = DISP_CURVE_BINS (at most that) */
    float depth_min, depth_max;  /* domain; both 0 = the pairs' range */
} disp_curve_desc;

/* Pairs with a non-positive or non-finite depth or disparity are skipped. */
vg_status disp_curve_build(const disp_curve_desc *desc, const float *depth, const float *disparity,
                           int n, disp_curve *out, vg_pool *pool);
/* Linear between consecutive nodes; linear continuation past the end nodes. */
float disp_curve_eval(const disp_curve *c, float depth);
