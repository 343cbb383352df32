/* The temporal end-point error (disp_tepe, issue 43), checked against
 * values worked out by hand on a 3-pixel, 4-frame sequence. Run: test_tepe NAME. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "../test.h"
#include "disparity/disp_metrics.h"

/* Pixel 0: x follows g with an error that grows 1, 3, 6, 10 arcmin (its
 * changes 2, 3, 4; their changes 1, 1). Pixel 1: x = g + 5 always (an
 * offset: 0 and 0). Pixel 2: the same error as pixel 0, but another surface
 * comes in front at frame 2 (depth 10 m -> 2 m), and g is unknown at frame 3:
 * only its change from frame 0 to 1 counts (2), no acceleration.
 *   velocity: pixel 0: 2 + 3 + 4, pixel 1: 0 + 0 + 0, pixel 2: 2  ->  11 / 7
 *   acceleration: pixel 0: 1 + 1, pixel 1: 0 + 0                   ->   2 / 4 */
static int by_hand(void)
{
    enum { N = 3, T = 4 };
    const float err[T] = {1, 3, 6, 10};
    disp_tepe t;
    CHECK(disp_tepe_init(&t, N, 0.2f) == VG_OK, "init");
    CHECK(isnan(disp_tepe_velocity(&t)) && isnan(disp_tepe_accel(&t)), "nothing measured yet");
    for (int k = 0; k < T; k++) {
        float g[N] = {300.0f + k, 250.0f - 2 * k, 280.0f + 3 * k};
        float x[N] = {g[0] + err[k], g[1] + 5, g[2] + err[k]};
        float z[N] = {4, 6, k >= 2 ? 2.0f : 10.0f};
        uint8_t unknown[N] = {0, 0, k == 3};
        if (k == 3)
            g[2] = INFINITY;
        disp_tepe_frame(&t, x, g, z, unknown);
    }
    double v = disp_tepe_velocity(&t), a = disp_tepe_accel(&t);
    printf("TEPE %.6f arcmin over %ld pixel steps (by hand 11/7 = %.6f), acceleration %.6f over %ld (2/4)\n", v,
           t.count_v, 11.0 / 7.0, a, t.count_a);
    CHECK(t.count_v == 7 && fabs(v - 11.0 / 7.0) < 1e-9, "velocity %.9f over %ld", v, t.count_v);
    CHECK(t.count_a == 4 && fabs(a - 0.5) < 1e-9, "acceleration %.9f over %ld", a, t.count_a);
    disp_tepe_free(&t);
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"by_hand", by_hand},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
