/* bench_solver — the MID solver on a 192x108 x 32-keyframe window (the
 * paper's 1:5 / 1:10 subsampling of 960x540 at 60 Hz over 5.3 s).
 *
 * Prints, from one run of this program:
 *   - memory bandwidth (STREAM triad) with 1 thread and all threads;
 *   - solver ms per window (median of runs), 1 thread and all threads, for
 *     the paper's descent (8 iterations), Gauss-Newton with 8 outer
 *     iterations, and the default Gauss-Newton budget, with the achieved
 *     GB/s (compulsory traffic of the passes / time);
 *   - quality: cost and MID distortion reached by each, against a long
 *     reference solve.
 * Usage: bench_solver [runs (default 5)] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/bandwidth.h"
#include "core/parallel.h"
#include "core/stats.h"
#include "disparity/disp_metrics.h"
#include "disparity/mid_solver.h"
#include "disparity/mid_synth.h"

#define NX MID_SYNTH_NX
#define NY MID_SYNTH_NY
#define NT MID_SYNTH_NT

/* ------------------------------------------------------------------------- */
/* Runs                                                                      */
/* ------------------------------------------------------------------------- */

typedef struct config {
    const char *name;
    mid_solve_desc desc;
} config;

int main(int argc, char **argv)
{
    int runs = argc > 1 ? atoi(argv[1]) : 5;
    runs = runs < 1 ? 1 : (runs > 15 ? 15 : runs);
    int cores = vg_cpu_count();
    vg_pool *pools[2] = {NULL, NULL};
    vg_pool_create(&(vg_pool_desc){.threads = 1}, &pools[0]);
    vg_pool_create(&(vg_pool_desc){.threads = cores}, &pools[1]);
    mid_window *w = mid_synth_window();
    float *f = malloc((size_t)NX * NY * NT * sizeof(float));
    if (!w || !f || !pools[0] || !pools[1]) {
        fprintf(stderr, "bench_solver: setup failed\n");
        return 1;
    }
    printf("bench_solver: window %dx%d x %d keyframes = %d unknowns, %u + %u adjoint entries, %d chains\n",
           NX, NY, NT, w->n, w->fwd_adj.count, w->bwd_adj.count, w->chain_count);
    int thread_counts[2] = {1, cores};
    double triad[2];
    for (int p = 0; p < 2; p++) {
        triad[p] = vg_stream_triad_gbs(pools[p], runs);
        printf("memory bandwidth (STREAM triad, %d thread%s): %.2f GB/s\n", thread_counts[p],
               thread_counts[p] > 1 ? "s" : "", triad[p]);
    }

    config configs[] = {
        {"descent, 8 iterations (paper)", {.solver = MID_SOLVER_DESCENT, .iterations = 8}},
        {"gauss-newton, 8 x 8 CG", {.solver = MID_SOLVER_GAUSS_NEWTON, .iterations = 8, .cg_iterations = 8}},
        {"gauss-newton default (4 x 8 CG)", {0}},
    };
    int nc = (int)(sizeof configs / sizeof configs[0]);
    mid_solve_stats st;
    printf("\n%-34s %8s %7s %9s %9s %8s\n", "solver", "threads", "passes", "ms/window", "GB/s", "% triad");
    for (int c = 0; c < nc; c++)
        for (int p = 0; p < 2; p++) {
            double ms[16];
            configs[c].desc.pool = pools[p];
            for (int r = 0; r < runs; r++) {
                mid_solve(w, &configs[c].desc, f, &st);
                ms[r] = st.ms;
            }
            double m = vg_median(ms, (size_t)runs, 1), gbs = st.bytes / (m * 1e6);
            printf("%-34s %8d %7d %9.1f %9.2f %7.0f%%\n", configs[c].name, thread_counts[p], st.passes, m, gbs,
                   100 * gbs / triad[p]);
        }

    /* Quality: against a long reference solve. */
    mid_solve(w, &(mid_solve_desc){.iterations = 10, .cg_iterations = 60, .pool = pools[1]}, f, &st);
    double c_ref = st.cost_final;
    double kkt = mid_projected_gradient_norm(w, (mid_weights){0}, f, pools[1]);
    disp_metrics m_ref, m_h, m;
    disp_metrics_window(w, f, NULL, &m_ref);
    disp_metrics_window(w, w->h, NULL, &m_h);
    printf("\nreference (10 x 60 CG, %.0f ms): cost %.5g, KKT residual %.2g, MID distortion %.3f JND\n", st.ms,
           c_ref, kkt, m_ref.mid_distortion_jnd);
    printf("%-34s %10s %12s %12s %12s\n", "", "cost", "above min", "MID (JND)", "of h's MID");
    printf("%-34s %10.5g %11.1f%% %12.3f %12.3f\n", "h (f0)", st.cost_initial, 100 * (st.cost_initial / c_ref - 1),
           m_h.mid_distortion_jnd, 1.0);
    for (int c = 0; c < nc; c++) {
        configs[c].desc.pool = pools[1];
        mid_solve(w, &configs[c].desc, f, &st);
        disp_metrics_window(w, f, NULL, &m);
        printf("%-34s %10.5g %11.1f%% %12.3f %12.3f\n", configs[c].name, st.cost_final,
               100 * (st.cost_final / c_ref - 1), m.mid_distortion_jnd, m.mid_distortion_jnd / m_h.mid_distortion_jnd);
    }
    printf("%-34s %10.5g %11.1f%% %12.3f %12.3f\n", "reference", c_ref, 0.0, m_ref.mid_distortion_jnd,
           m_ref.mid_distortion_jnd / m_h.mid_distortion_jnd);
    free(f);
    mid_window_destroy(w);
    vg_pool_destroy(pools[0]);
    vg_pool_destroy(pools[1]);
    return 0;
}
