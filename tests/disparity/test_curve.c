/* The global depth -> disparity curve (paper Sec. 4.6). Run: test_curve NAME. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../test.h"
#include "disparity/disp_curve.h"
#include "vergence/curve.h"
#include "testlib.h"

#define NPAIRS 200000

/* A monotone, strongly non-linear mapping of depth to vergence: a
 * compressed band around 2 m, as a manipulation operator would make. */
static double mapping(double z)
{
    return 250.0 + 40.0 * tanh(3.0 * (1.0 / z - 0.5)) + 8.0 / z;
}

/* Dense pairs of a monotone mapping come back exactly (to float and the
 * curvature of the mapping within one bin). */
static int exact_monotone(void)
{
    float *z = malloc(NPAIRS * sizeof(float)), *d = malloc(NPAIRS * sizeof(float));
    unsigned s = 42;
    for (int i = 0; i < NPAIRS; i++) {
        z[i] = 1.0f / rnd_uniform(&s, 0.1f, 2.0f); /* 0.5 m .. 10 m */
        d[i] = (float)mapping(z[i]);
    }
    vgx_curve_data c;
    CHECK(disp_curve_build(z, d, NPAIRS, &c) == VG_OK && c.valid, "build");
    double worst = 0, worst_lin = 0;
    for (double inv = 0.102; inv < 1.998; inv += 0.0007) {
        double e = fabs(vgx_curve_vergence(&c, (float)(1.0 / inv)) - mapping(1.0 / inv));
        worst = fmax(worst, e);
    }
    /* A mapping linear in inverse depth is reproduced to float precision. */
    for (int i = 0; i < NPAIRS; i++)
        d[i] = 200.0f + 60.0f / z[i];
    CHECK(disp_curve_build(z, d, NPAIRS, &c) == VG_OK, "build");
    for (double inv = 0.102; inv < 1.998; inv += 0.0007)
        worst_lin = fmax(worst_lin, fabs(vgx_curve_vergence(&c, (float)(1.0 / inv)) - (200.0 + 60.0 * inv)));
    printf("%d bins; max error: non-linear mapping %.4f arcmin, linear %.2g arcmin\n", VGX_CURVE_BINS, worst,
           worst_lin);
    CHECK(worst < 0.05, "non-linear mapping: %.4f arcmin", worst);
    CHECK(worst_lin < 2e-3, "linear mapping: %.3g arcmin", worst_lin);
    free(z);
    free(d);
    return 0;
}

/* Two clusters of depth with nothing between: across the empty bins the
 * curve is a straight line between the clusters' end nodes, however many
 * pairs each cluster holds. */
static int linear_across_gaps(void)
{
    float *z = malloc(NPAIRS * sizeof(float)), *d = malloc(NPAIRS * sizeof(float));
    unsigned s = 7;
    for (int i = 0; i < NPAIRS; i++) {
        bool near = i % 20 == 0; /* 5 % near, 95 % far */
        float inv = near ? rnd_uniform(&s, 1.2f, 1.6f) : rnd_uniform(&s, 0.15f, 0.4f);
        z[i] = 1.0f / inv;
        d[i] = (float)mapping(z[i]);
    }
    vgx_curve_data c;
    CHECK(disp_curve_build(z, d, NPAIRS, &c) == VG_OK, "build");
    /* The empty interval: inverse depth 0.4 .. 1.2; the curve is linear in
     * inverse depth there. */
    float va = vgx_curve_vergence(&c, 1.0f / 0.45f), vb = vgx_curve_vergence(&c, 1.0f / 1.15f);
    double worst = 0;
    for (double inv = 0.45; inv <= 1.15; inv += 0.001) {
        double line = va + (vb - va) * (inv - 0.45) / (1.15 - 0.45);
        worst = fmax(worst, fabs(vgx_curve_vergence(&c, (float)(1.0 / inv)) - line));
    }
    /* The line joins the clusters: its ends lie between the clusters' values. */
    double end_far = mapping(1.0 / 0.4), end_near = mapping(1.0 / 1.2);
    printf("gap: curve %.3f .. %.3f (clusters end at %.3f and %.3f); max departure from a line %.2g arcmin\n",
           va, vb, end_far, end_near, worst);
    CHECK(worst < 1e-3, "not linear across the gap: %.3g arcmin", worst);
    CHECK(va > end_far - 1 && vb < end_near + 1 && vb > va, "the line must bridge the two clusters");
    free(z);
    free(d);
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"exact_monotone", exact_monotone},
        {"linear_across_gaps", linear_across_gaps},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
