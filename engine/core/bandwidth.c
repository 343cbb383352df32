/* vergence — STREAM triad bandwidth (bandwidth.h). */
#include "bandwidth.h"

#include <math.h>
#include <stdlib.h>

#include "clock.h"

typedef struct triad_ctx {
    float *a;
    const float *b, *c;
} triad_ctx;

static void triad_block(void *p, int block, int begin, int end)
{
    (void)block;
    triad_ctx *t = p;
    for (int i = begin; i < end; i++)
        t->a[i] = t->b[i] + 3.0f * t->c[i];
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double vg_stream_triad_gbs(vg_pool *pool, int runs)
{
    const int n = 1 << 24; /* 64 MB per array */
    runs = runs < 1 ? 1 : (runs > 15 ? 15 : runs);
    float *a = malloc((size_t)n * 4), *b = malloc((size_t)n * 4), *c = malloc((size_t)n * 4);
    if (!a || !b || !c) {
        free(a);
        free(b);
        free(c);
        return NAN;
    }
    for (int i = 0; i < n; i++) {
        a[i] = 0;
        b[i] = (float)i;
        c[i] = 1.0f;
    }
    triad_ctx t = {a, b, c};
    double ms[15];
    vg_parallel_for(pool, n, 1 << 16, triad_block, &t); /* warm-up */
    for (int r = 0; r < runs; r++) {
        double t0 = vg_now_ms();
        vg_parallel_for(pool, n, 1 << 16, triad_block, &t);
        ms[r] = vg_now_ms() - t0;
    }
    qsort(ms, (size_t)runs, sizeof *ms, cmp_double);
    double m = runs % 2 ? ms[runs / 2] : 0.5 * (ms[runs / 2 - 1] + ms[runs / 2]);
    free(a);
    free(b);
    free(c);
    return 3.0 * n * 4 / (m * 1e6);
}
