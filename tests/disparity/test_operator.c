/* Disparity operators h = M(g, saliency). Run one case: test_operator NAME. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../test.h"
#include "disparity/disp_operator.h"
#include "stereo/stereo_display.h"
#include "testlib.h"

#define W 96
#define H 54
#define N (W * H)

static double screen_vergence(void)
{
    stereo_display d;
    stereo_display_init(&d, &(stereo_display_desc){0});
    return d.screen_vergence;
}

/* A frame of four depth layers (wall, two slabs, a near post) with a wide
 * vergence range, the kind a comfort operator must compress. */
static void layered_frame(float *g, double a_near, double a_far)
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double v = 30.0;
            if (y < H / 4)
                v = a_far;
            else if (y >= H - H / 4)
                v = a_near;
            else if (x > W - 10)
                v = 420.0;
            g[y * W + x] = (float)(v + 0.5 * sin(0.3 * x + 0.2 * y)); /* a little texture */
        }
}

static disp_operator *make(disp_operator_kind kind, disp_operator_preset preset)
{
    disp_operator *op = NULL;
    disp_operator_create(&(disp_operator_desc){.kind = kind, .preset = preset, .screen_vergence = screen_vergence()}, &op);
    return op;
}

static int lang_in_range(void)
{
    float *g = malloc(N * sizeof(float)), *h = malloc(N * sizeof(float));
    for (int preset = DISP_PRESET_DEFAULT; preset <= DISP_PRESET_STUDY; preset++)
        for (int kind = DISP_OPERATOR_LINEAR; kind <= DISP_OPERATOR_LANG_SMOOTHED; kind++) {
            disp_operator *op = make(kind, preset);
            CHECK(op, "create");
            double lo, hi, hmin = 1e9, hmax = -1e9;
            disp_operator_range(op, &lo, &hi);
            for (int frame = 0; frame < 5; frame++) {
                layered_frame(g, 150 + 60 * frame, 60 + 10 * frame);
                disp_operator_apply(op, g, NULL, N, h, NULL);
                for (int i = 0; i < N; i++) {
                    hmin = fmin(hmin, h[i]);
                    hmax = fmax(hmax, h[i]);
                }
            }
            printf("%-13s preset %d: g in [29.5, 420.5] -> h in [%.3f, %.3f], range [%.3f, %.3f]\n",
                   disp_operator_kind_name(kind), preset, hmin, hmax, lo, hi);
            CHECK(hmin >= lo - 1e-3 && hmax <= hi + 1e-3, "h leaves the target range");
            /* Scaled about the screen: the far end reaches the range, the near end need not. */
            CHECK(fabs(hmin - lo) < 1e-3 && hmax - hmin > 0.5 * (hi - lo), "h must fill the range from its far end");
            disp_operator_destroy(op);
        }
    free(g);
    free(h);
    return 0;
}

static int lang_monotone(void)
{
    float *g = malloc(N * sizeof(float)), *h = malloc(N * sizeof(float));
    disp_operator *op = make(DISP_OPERATOR_LANG, DISP_PRESET_STUDY);
    CHECK(op, "create");
    layered_frame(g, 200, 80);
    disp_operator_apply(op, g, NULL, N, h, NULL);
    double prev = -1e9, min_slope = 1e9, max_slope = 0;
    /* The frame's domain is [min g, max g] = [29.5, 420.5]. */
    for (double x = 29.55; x <= 420.45; x += 0.05) {
        double y = disp_operator_map(op, x);
        if (x > 29.55) {
            CHECK(y > prev, "not increasing at %.2f: %.6f <= %.6f", x, y, prev);
            min_slope = fmin(min_slope, (y - prev) / 0.05);
            max_slope = fmax(max_slope, (y - prev) / 0.05);
        }
        prev = y;
    }
    /* Pixels keep their depth order. */
    for (int i = 1; i < N; i++)
        CHECK((g[i] > g[i - 1]) == (h[i] > h[i - 1]) || g[i] == g[i - 1], "order of pixels %d, %d", i - 1, i);
    printf("lang mapping slopes in [%.4f, %.4f]: strictly increasing\n", min_slope, max_slope);
    CHECK(max_slope > 5 * min_slope, "lang should be non-linear here");
    disp_operator_destroy(op);
    free(g);
    free(h);
    return 0;
}

/* Output range given to the depth interval [a - 3, a + 3] arcmin. */
static double local_range(const disp_operator *op, double a)
{
    return disp_operator_map(op, a + 3) - disp_operator_map(op, a - 3);
}

/* Lang et al.: salient depths get more of the output range. Two objects of
 * equal size at 100 and 250 arcmin; saliency on one, then on the other. */
static int lang_saliency(void)
{
    float *g = malloc(N * sizeof(float)), *h = malloc(N * sizeof(float)), *sal = malloc(N * sizeof(float));
    for (int i = 0; i < N; i++) {
        int x = i % W;
        g[i] = x < W / 3 ? 100.0f + 0.01f * (i % 7) : (x < 2 * W / 3 ? 250.0f + 0.01f * (i % 5) : 30.0f);
    }
    disp_operator *op = make(DISP_OPERATOR_LANG, DISP_PRESET_DEFAULT);
    CHECK(op, "create");
    double r[3][2];
    for (int mode = 0; mode < 3; mode++) {
        for (int i = 0; i < N; i++) {
            int x = i % W, obj = x < W / 3 ? 1 : (x < 2 * W / 3 ? 2 : 0);
            sal[i] = mode == 0 ? 0.5f : (obj == mode ? 1.0f : 0.0f);
        }
        disp_operator_apply(op, g, sal, N, h, NULL);
        r[mode][0] = local_range(op, 100);
        r[mode][1] = local_range(op, 250);
    }
    printf("output arcmin for 6 arcmin of input: uniform %.3f / %.3f; near salient %.3f / %.3f; far salient %.3f / %.3f\n",
           r[0][0], r[0][1], r[1][0], r[1][1], r[2][0], r[2][1]);
    CHECK(r[1][0] > 1.2 * r[0][0] && r[1][1] < r[0][1], "saliency on the object at 100 arcmin must give it more range");
    CHECK(r[2][1] > 1.2 * r[0][1] && r[2][0] < r[0][0], "saliency on the object at 250 arcmin must give it more range");
    disp_operator_destroy(op);
    free(g);
    free(h);
    free(sal);
    return 0;
}

static int linear_identity(void)
{
    float *g = malloc(N * sizeof(float)), *h = malloc(N * sizeof(float));
    double as = screen_vergence();
    disp_operator *op = make(DISP_OPERATOR_LINEAR, DISP_PRESET_DEFAULT);
    CHECK(op, "create");
    unsigned s = 1;
    for (int i = 0; i < N; i++)
        g[i] = (float)(as + rnd_uniform(&s, -59.5f, 59.9f));
    disp_operator_apply(op, g, NULL, N, h, NULL);
    double worst = 0;
    for (int i = 0; i < N; i++)
        worst = fmax(worst, fabs(h[i] - g[i]));
    printf("g within +-60 arcmin: max |h - g| = %.3g\n", worst);
    CHECK(worst == 0, "linear must be the identity when the range fits: %.3g", worst);
    /* Too deep: scaled about the screen until the far end touches the range. */
    for (int i = 0; i < N; i++)
        g[i] = (float)(as + rnd_uniform(&s, -200, 30));
    g[0] = (float)(as - 200);
    disp_operator_apply(op, g, NULL, N, h, NULL);
    double lo, hi, hmin = 1e9;
    disp_operator_range(op, &lo, &hi);
    for (int i = 0; i < N; i++)
        hmin = fmin(hmin, h[i]);
    printf("g down to a_s - 200: h down to %.4f (range starts %.4f)\n", hmin, lo);
    CHECK(fabs(hmin - lo) < 1e-3, "the far end must land on the range boundary");
    disp_operator_destroy(op);
    free(g);
    free(h);
    return 0;
}

/* lang-smoothed: a mapping that jumps between two histograms settles with the
 * time constant instead of following at once. */
static int lang_smoothed_damps(void)
{
    float *g = malloc(N * sizeof(float)), *h = malloc(N * sizeof(float));
    disp_operator *raw = make(DISP_OPERATOR_LANG, DISP_PRESET_DEFAULT);
    disp_operator *smooth = make(DISP_OPERATOR_LANG_SMOOTHED, DISP_PRESET_DEFAULT);
    CHECK(raw && smooth, "create");
    double jump_raw = 0, jump_smooth = 0, prev_raw = 0, prev_smooth = 0;
    for (int frame = 0; frame < 60; frame++) {
        layered_frame(g, frame < 30 ? 150 : 300, 60);
        disp_operator_apply(raw, g, NULL, N, h, NULL);
        double a = disp_operator_map(raw, 200.0);
        disp_operator_apply(smooth, g, NULL, N, h, NULL);
        double b = disp_operator_map(smooth, 200.0);
        if (frame > 0) {
            jump_raw = fmax(jump_raw, fabs(a - prev_raw));
            jump_smooth = fmax(jump_smooth, fabs(b - prev_smooth));
        }
        prev_raw = a;
        prev_smooth = b;
    }
    double gap = fabs(prev_smooth - prev_raw);
    printf("largest frame-to-frame change of h(200): lang %.3f, lang-smoothed %.3f; after 30 frames %.3f apart\n",
           jump_raw, jump_smooth, gap);
    CHECK(jump_raw > 1.0, "the histogram change must move lang's mapping");
    CHECK(jump_smooth < 0.1 * jump_raw, "smoothing must damp the jump");
    CHECK(gap < 0.5 * jump_raw, "smoothing must converge to the new mapping");
    disp_operator_destroy(raw);
    disp_operator_destroy(smooth);
    free(g);
    free(h);
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"lang_in_range", lang_in_range},
        {"lang_monotone", lang_monotone},
        {"lang_saliency", lang_saliency},
        {"linear_identity", linear_identity},
        {"lang_smoothed_damps", lang_smoothed_damps},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
