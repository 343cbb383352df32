/* Upsampling of the keyframe correction (paper Sec. 4.4, Fig. 4).
 * Run one case: test_upsample NAME. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>

#include "../test.h"
#include "disparity/disp_upsample.h"
#include "disparity/mid_shared.h"

#define FW 160
#define FH 90
#define S 5

/* A full-resolution h with pixel-scale detail the coarse grid cannot hold. */
static void detailed_h(float *h)
{
    for (int y = 0; y < FH; y++)
        for (int x = 0; x < FW; x++)
            h[y * FW + x] = 260.0f + 10.0f * sinf(0.9f * x) * cosf(1.3f * y) + 0.1f * x;
}

static disp_upsample_desc desc_default(void)
{
    disp_upsample_desc d = {0};
    disp_grid_init(&d.grid, FW, FH, S);
    return d;
}

/* Ratio 1 is no correction: f is h bit for bit; a constant ratio scales h
 * and keeps all of its fine detail. */
static int detail_preserved(void)
{
    disp_upsample_desc d = desc_default();
    int nc = d.grid.nx * d.grid.ny;
    float *h = malloc(FW * FH * sizeof(float)), *f = malloc(FW * FH * sizeof(float));
    float *r = malloc(nc * sizeof(float));
    detailed_h(h);
    for (int q = 0; q < nc; q++)
        r[q] = 1.0f;
    disp_upsample_spatial(&d, h, r, f, NULL);
    int differ = 0;
    for (int i = 0; i < FW * FH; i++)
        differ += f[i] != h[i];
    printf("ratio 1: %d of %d pixels differ from h\n", differ, FW * FH);
    CHECK(differ == 0, "%d pixels differ", differ);
    for (int q = 0; q < nc; q++)
        r[q] = 1.05f;
    disp_upsample_spatial(&d, h, r, f, NULL);
    double worst = 0;
    for (int i = 0; i < FW * FH; i++)
        worst = fmax(worst, fabs(f[i] - 1.05 * h[i]));
    printf("ratio 1.05: max |f - 1.05 h| = %.3g arcmin\n", worst);
    CHECK(worst < 1e-3, "%.3g", worst);
    free(h);
    free(f);
    free(r);
    return 0;
}

/* The guide keeps a correction on its own side of a depth edge that does
 * not line up with the coarse grid; plain spatial interpolation would mix. */
static int bilateral_edge(void)
{
    disp_upsample_desc d = desc_default();
    int nc = d.grid.nx * d.grid.ny;
    float *h = malloc(FW * FH * sizeof(float)), *f = malloc(FW * FH * sizeof(float));
    float *r = malloc(nc * sizeof(float));
    const float edge = 0.37f * FW; /* a slanted edge, mostly between coarse samples */
    for (int y = 0; y < FH; y++)
        for (int x = 0; x < FW; x++)
            h[y * FW + x] = (x < edge + 0.15f * y) ? 300.0f : 240.0f;
    for (int q = 0; q < nc; q++) {
        int px = disp_grid_px(&d.grid, q % d.grid.nx), py = disp_grid_py(&d.grid, q / d.grid.nx);
        r[q] = h[py * FW + px] > 270.0f ? 1.08f : 1.0f;
    }
    disp_upsample_spatial(&d, h, r, f, NULL);
    double worst = 0;
    for (int i = 0; i < FW * FH; i++) {
        double want = h[i] > 270.0f ? 1.08 : 1.0;
        worst = fmax(worst, fabs(f[i] / h[i] - want));
    }
    d.sigma_range = 1e6f; /* no guide: spatial interpolation only */
    disp_upsample_spatial(&d, h, r, f, NULL);
    double worst_plain = 0;
    for (int i = 0; i < FW * FH; i++) {
        double want = h[i] > 270.0f ? 1.08 : 1.0;
        worst_plain = fmax(worst_plain, fabs(f[i] / h[i] - want));
    }
    printf("ratio error at the edge: joint bilateral %.3g, spatial only %.3g\n", worst, worst_plain);
    CHECK(worst < 1e-3, "the correction leaks across the edge: %.3g", worst);
    CHECK(worst_plain > 0.02, "the test edge must be hard for plain interpolation (%.3g)", worst_plain);
    free(h);
    free(f);
    free(r);
    return 0;
}

/* A square moves 40 px right between keyframes k0 and k1 over a static
 * background. Keyframe corrections: square 1.1, background 1.0 at k0 and
 * 0.98 at k1. At tau = 0.5 the square's samples follow the flow; background
 * samples that the square covered at k0 fail the depth test there and take
 * k1 alone. */
static int temporal_flow_and_occlusion(void)
{
    disp_upsample_desc d = desc_default();
    int nx = d.grid.nx, ny = d.grid.ny, nc = nx * ny;
    float *ratio0 = malloc(nc * sizeof(float)), *ratio1 = malloc(nc * sizeof(float));
    float *depth0 = malloc(nc * sizeof(float)), *depth1 = malloc(nc * sizeof(float)), *depth_t = malloc(nc * sizeof(float));
    float *pos0 = malloc(2 * nc * sizeof(float)), *pos1 = malloc(2 * nc * sizeof(float)), *out = malloc(nc * sizeof(float));
    int x0 = 30, x1 = 70, xt = 50, y_lo = 30, y_hi = 60, side = 25; /* square spans [x, x + side) */
#define IN_SQUARE(px, py, sx) ((px) >= (sx) && (px) < (sx) + side && (py) >= y_lo && (py) < y_hi)
    disp_grid_positions(&d.grid, pos0);
    for (int q = 0; q < nc; q++) {
        float px = pos0[2 * q], py = pos0[2 * q + 1];
        bool s0 = IN_SQUARE(px, py, x0), s1 = IN_SQUARE(px, py, x1), st = IN_SQUARE(px, py, xt);
        ratio0[q] = s0 ? 1.1f : 1.0f;
        ratio1[q] = s1 ? 1.1f : 0.98f;
        depth0[q] = s0 ? 2.0f : 8.0f;
        depth1[q] = s1 ? 2.0f : 8.0f;
        depth_t[q] = st ? 2.0f : 8.0f;
        /* Flow of frame t to the keyframes: the square moves, the rest stays. */
        pos1[2 * q] = px + (st ? (float)(x1 - xt) : 0.0f);
        pos1[2 * q + 1] = py;
        pos0[2 * q] = px + (st ? (float)(x0 - xt) : 0.0f);
    }
    disp_keyframe_view k0 = {pos0, ratio0, NULL, depth0, NULL, NULL, NULL, NULL};
    disp_keyframe_view k1 = {pos1, ratio1, NULL, depth1, NULL, NULL, NULL, NULL};
    disp_upsample_temporal(&d, 0.5f, 1.0f / 6.0f, depth_t, NULL, NULL, NULL, &k0, &k1, out, NULL);
    double err_square = 0, err_uncovered = 0, err_static = 0;
    int n_square = 0, n_uncovered = 0;
    for (int q = 0; q < nc; q++) {
        float px = (float)disp_grid_px(&d.grid, q % nx), py = (float)disp_grid_py(&d.grid, q / nx);
        bool st = IN_SQUARE(px, py, xt), s0 = IN_SQUARE(px, py, x0), s1 = IN_SQUARE(px, py, x1);
        if (st) {
            err_square = fmax(err_square, fabs(out[q] - 1.1));
            n_square++;
        } else if (s0 && !s1) {
            err_uncovered = fmax(err_uncovered, fabs(out[q] - 0.98)); /* k0 occluded: k1 only */
            n_uncovered++;
        } else if (!s1) {
            err_static = fmax(err_static, fabs(out[q] - 0.99)); /* both: the average */
        }
    }
    printf("tau 0.5: square (%d samples) error %.3g; uncovered background (%d) error %.3g; background %.3g\n",
           n_square, err_square, n_uncovered, err_uncovered, err_static);
    CHECK(n_square > 20 && n_uncovered > 20, "the scene must have both cases");
    CHECK(err_square < 1e-6, "the square must follow its flow: %.3g", err_square);
    CHECK(err_uncovered < 1e-6, "occluded keyframe samples must drop out: %.3g", err_uncovered);
    CHECK(err_static < 1e-6, "%.3g", err_static);
    /* At a keyframe (tau 0) the keyframe's own correction comes back exactly. */
    disp_grid_positions(&d.grid, pos0);
    disp_upsample_temporal(&d, 0.0f, 0.0f, depth0, NULL, NULL, NULL, &k0, NULL, out, NULL);
    for (int q = 0; q < nc; q++)
        CHECK(out[q] == ratio0[q], "tau 0, sample %d: %.7f vs %.7f", q, out[q], ratio0[q]);
#undef IN_SQUARE
    free(ratio0); free(ratio1); free(depth0); free(depth1); free(depth_t);
    free(pos0); free(pos1); free(out);
    return 0;
}

/* Hermite in time: three keyframes of a static scene whose correction is
 * quadratic in time, slopes from mid_ratio_slope (central at the middle
 * keyframe, the exact derivative at the ends). The frames' second
 * differences equal the quadratic's everywhere, keyframes included; linear
 * interpolation (no slopes) puts a whole interval's curvature into the
 * keyframe's frame: the kink this removes. */
static int temporal_hermite(void)
{
    disp_upsample_desc d = desc_default();
    int nc = d.grid.nx * d.grid.ny, frames = 10;
    const float span = 1.0f / 6.0f, b = 0.05f, c = 0.3f;
    float *r = malloc(3 * (size_t)nc * sizeof(float)), *sl = malloc(3 * (size_t)nc * sizeof(float));
    float *depth = malloc(nc * sizeof(float)), *pos = malloc(2 * (size_t)nc * sizeof(float));
    float *out = malloc((2 * (size_t)frames + 1) * nc * sizeof(float));
    CHECK(r && sl && depth && pos && out, "memory");
    disp_grid_positions(&d.grid, pos);
    for (int q = 0; q < nc; q++) {
        depth[q] = 5.0f;
        float a = 1.0f + 0.01f * (float)(q % 7);
        for (int k = 0; k < 3; k++) {
            float t = (float)k * span;
            r[k * nc + q] = a + b * t + c * t * t;
        }
        for (int k = 0; k < 3; k += 2)
            sl[k * nc + q] = b + 2.0f * c * (float)k * span;
        sl[nc + q] = mid_ratio_slope(r[nc + q], r[2 * nc + q], r[q], 1u, 1u, 1.0f / span, 1.0f / span);
    }
    double worst = 0, lin_knot = 0, lin_between = 0;
    double exact = 2.0 * c * (double)(span / frames) * (span / frames);
    for (int pass = 0; pass < 2; pass++) {
        for (int t = 0; t <= 2 * frames; t++) {
            int k = t < frames ? 0 : 1;
            float tau = (float)(t - k * frames) / (float)frames;
            disp_keyframe_view k0 = {pos, r + (size_t)k * nc, pass ? NULL : sl + (size_t)k * nc, depth, NULL, NULL,
                                     NULL, NULL};
            disp_keyframe_view k1 = {pos, r + (size_t)(k + 1) * nc, pass ? NULL : sl + (size_t)(k + 1) * nc, depth, NULL,
                                     NULL, NULL, NULL};
            disp_upsample_temporal(&d, tau, span, depth, NULL, NULL, NULL, &k0, tau > 0 ? &k1 : NULL, out + (size_t)t * nc, NULL);
        }
        for (int t = 1; t < 2 * frames; t++)
            for (int q = 0; q < nc; q++) {
                double d2 = (double)out[(size_t)(t + 1) * nc + q] - 2.0 * out[(size_t)t * nc + q] +
                            out[(size_t)(t - 1) * nc + q];
                if (!pass)
                    worst = fmax(worst, fabs(d2 - exact));
                else if (t == frames)
                    lin_knot = fmax(lin_knot, fabs(d2));
                else
                    lin_between = fmax(lin_between, fabs(d2));
            }
    }
    printf("second difference of the ratio per frame: quadratic %.3g; Hermite off by at most %.3g; "
           "linear %.3g at the keyframe, %.3g between\n", exact, worst, lin_knot, lin_between);
    CHECK(worst < 0.02 * exact, "Hermite interpolation must follow the quadratic (off by %.3g)", worst);
    CHECK(lin_knot > 5.0 * exact && lin_between < 0.02 * exact, "linear interpolation must kink at the keyframe");
    free(r); free(sl); free(depth); free(pos); free(out);
    return 0;
}

/* Composing per-frame flows: two translations add; leaving the frame loses the point. */
static int flow_composition(void)
{
    int w = 40, h = 30;
    float *a = malloc(w * h * 2 * sizeof(float)), *b = malloc(w * h * 2 * sizeof(float));
    for (int i = 0; i < w * h; i++) {
        int x = i % w;
        a[2 * i] = 1.25f;
        a[2 * i + 1] = -0.5f;
        b[2 * i] = x < 20 ? 2.0f : 3.0f; /* a motion boundary at x = 20 */
        b[2 * i + 1] = 0.25f;
    }
    float pos[6] = {5.0f, 10.0f, 19.0f, 10.0f, 38.0f, 5.0f};
    disp_flow_advect(a, w, h, pos, 3);
    disp_flow_advect(b, w, h, pos, 3);
    printf("(5,10) -> (%.3f, %.3f); (19,10) -> (%.3f, %.3f); (38,5) -> (%.3f, %.3f)\n", pos[0], pos[1],
           pos[2], pos[3], pos[4], pos[5]);
    CHECK(fabsf(pos[0] - 8.25f) < 1e-5f && fabsf(pos[1] - 9.75f) < 1e-5f, "first point");
    /* After the first step the point is at x = 20.25: bilinear across the boundary. */
    CHECK(fabsf(pos[2] - (20.25f + 3.0f)) < 1e-5f, "second point %.6f", pos[2]);
    CHECK(isnan(pos[4]) && isnan(pos[5]), "the third point left the frame");
    free(a);
    free(b);
    return 0;
}

/* Occlusion in time as the solver's links decide it: a surface that moves
 * fast in depth (2 -> 2.5 -> 3.2 m, 25 % and 28 % per half interval, beyond
 * the 20 % depth tolerance) keeps both keyframes when its trajectory
 * matches (each keyframe's flow to the other lands on the sample there),
 * and loses a keyframe whose instance differs or whose flow goes elsewhere. */
static int temporal_trajectory(void)
{
    enum { NX = 8, NY = 6, NC = NX * NY };
    disp_upsample_desc d = {0};
    disp_grid_init(&d.grid, NX * 5, NY * 5, 5);
    float pos[2 * NC], z0[NC], zt[NC], z1[NC], r0[NC], r1[NC], id[NC], other_id[NC], still[2 * NC], away[2 * NC],
        out[NC];
    disp_grid_positions(&d.grid, pos);
    for (int q = 0; q < NC; q++) {
        z0[q] = 2.0f, zt[q] = 2.5f, z1[q] = 3.2f, r0[q] = 1.0f, r1[q] = 1.2f, id[q] = 3.0f, other_id[q] = 7.0f;
        still[2 * q] = still[2 * q + 1] = 0.0f;
        away[2 * q] = 3.0f, away[2 * q + 1] = 0.0f; /* three coarse pixels off the sample's path */
    }
    struct { const char *what; const float *id_t, *flow; float want; } cases[] = {
        {"on its trajectory: both keyframes", id, still, 1.1f},
        {"another instance: the nearer keyframe alone", other_id, still, 1.2f},
        {"off its trajectory: the nearer keyframe alone", id, away, 1.2f},
        {"no flow (depth test only, as before): the nearer keyframe alone", id, NULL, 1.2f},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        disp_keyframe_view k0 = {pos, r0, NULL, z0, id, cases[c].flow, NULL, NULL};
        disp_keyframe_view k1 = {pos, r1, NULL, z1, id, cases[c].flow, NULL, NULL};
        disp_upsample_temporal(&d, 0.5f, 1.0f / 6.0f, zt, cases[c].id_t, NULL, NULL, &k0, &k1, out, NULL);
        double worst = 0;
        for (int q = 0; q < NC; q++)
            worst = fmax(worst, fabs(out[q] - cases[c].want));
        printf("%s: ratio %.4f (want %.4f)\n", cases[c].what, out[0], cases[c].want);
        CHECK(worst < 1e-6, "%s: off by %.3g", cases[c].what, worst);
    }
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"detail_preserved", detail_preserved},
        {"bilateral_edge", bilateral_edge},
        {"temporal_flow_and_occlusion", temporal_flow_and_occlusion},
        {"flow_composition", flow_composition},
        {"temporal_hermite", temporal_hermite},
        {"temporal_trajectory", temporal_trajectory},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
