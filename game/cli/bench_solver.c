/* vergence bench solver — the MID solver on a 192x108 x 32-keyframe window
 * (the paper's 1:5 / 1:10 subsampling of 960x540 at 60 Hz over 5.3 s).
 *
 * Prints, from one run:
 *   - memory bandwidth (STREAM triad) with 1 thread and all threads;
 *   - solver ms per window (median of runs), 1 thread and all threads, for
 *     the paper's descent (8 iterations), Gauss-Newton with 8 outer
 *     iterations, and the default Gauss-Newton budget, with the achieved
 *     GB/s (compulsory traffic of the passes / time);
 *   - quality: cost and MID distortion reached by each, against a long
 *     reference solve (not with --no-quality).
 *
 * The project's one solver benchmark: `vergence bench` prints its speed
 * tables too (bench_solver_tables). Not a test: figures go to
 * docs/PERFORMANCE.md. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_modes.h"
#include "core/bandwidth.h"
#include "core/log.h"
#include "core/parallel.h"
#include "core/stats.h"
#include "disparity/disp_metrics.h"
#include "disparity/mid_solver.h"
#include "disparity/mid_synth.h"

#define NX MID_SYNTH_NX
#define NY MID_SYNTH_NY
#define NT MID_SYNTH_NT
#define MAX_RUNS 15

typedef struct config {
    const char *name;
    mid_solve_desc desc;
} config;

/* The speed table: the triad and every config with each pool. */
static vg_status speed(bench_report *r, mid_window *w, float *f, vg_pool *pools[2], const int threads[2], int runs,
                       config *configs, int nc)
{
    char cells[6][32], label[96];
    bench_heading(r, "CPU solver: ms per window and achieved bandwidth");
    snprintf(label, sizeof label, "window %dx%d x %d keyframes: %d unknowns, %u + %u adjoint entries, %d chains", NX,
             NY, NT, w->n, w->fwd_adj.count, w->bwd_adj.count, w->chain_count);
    bench_note(r, label);
    snprintf(cells[0], sizeof cells[0], "threads");
    snprintf(cells[1], sizeof cells[1], "passes");
    snprintf(cells[2], sizeof cells[2], "ms/window");
    snprintf(cells[3], sizeof cells[3], "GB/s");
    snprintf(cells[4], sizeof cells[4], "%% triad");
    bench_row(r, true, "solver", 5, cells);
    double triad[2];
    for (int p = 0; p < 2; p++) {
        vg_info("bench: STREAM triad, %d thread(s)", threads[p]);
        triad[p] = vg_stream_triad_gbs(pools[p], runs);
        snprintf(cells[0], sizeof cells[0], "%d", threads[p]);
        cells[1][0] = cells[2][0] = 0;
        snprintf(cells[3], sizeof cells[3], "%.2f", triad[p]);
        snprintf(cells[4], sizeof cells[4], "100%%");
        bench_row(r, false, "memory bandwidth (STREAM triad)", 5, cells);
    }
    vg_status st = VG_OK;
    for (int c = 0; c < nc && st == VG_OK; c++)
        for (int p = 0; p < 2 && st == VG_OK; p++) {
            double ms[MAX_RUNS];
            mid_solve_stats stats = {0};
            configs[c].desc.pool = pools[p];
            vg_info("bench: %s, %d thread(s), %d run(s)", configs[c].name, threads[p], runs);
            for (int k = 0; k < runs && st == VG_OK; k++) {
                st = mid_solve(w, &configs[c].desc, f, &stats);
                ms[k] = stats.ms;
            }
            if (st != VG_OK)
                break;
            double m = vg_median(ms, (size_t)runs, 1), gbs = stats.bytes / (m * 1e6);
            snprintf(cells[0], sizeof cells[0], "%d", threads[p]);
            snprintf(cells[1], sizeof cells[1], "%d", stats.passes);
            snprintf(cells[2], sizeof cells[2], "%.1f", m);
            snprintf(cells[3], sizeof cells[3], "%.2f", gbs);
            snprintf(cells[4], sizeof cells[4], "%.0f%%", 100 * gbs / triad[p]);
            bench_row(r, false, configs[c].name, 5, cells);
        }
    if (st == VG_OK)
        bench_note(r, "GB/s: the compulsory traffic of the solver's passes (every array element read or written once "
                      "per pass) over its wall time, against a triad of the same run; the GPU solve (mid.solve) runs "
                      "the same passes.");
    return st;
}

/* The quality table: each config's cost and MID distortion against a long reference solve. */
static vg_status quality(bench_report *r, mid_window *w, float *f, vg_pool *pool, config *configs, int nc)
{
    mid_solve_stats stats = {0};
    vg_info("bench: the reference solve (10 x 60 CG)");
    vg_status st = mid_solve(w, &(mid_solve_desc){.iterations = 10, .cg_iterations = 60, .pool = pool}, f, &stats);
    if (st != VG_OK)
        return st;
    double c_ref = stats.cost_final, c_h = stats.cost_initial, ref_ms = stats.ms;
    double kkt = mid_projected_gradient_norm(w, (mid_weights){0}, f, pool);
    disp_metrics m_ref, m_h, m;
    disp_metrics_window(w, f, NULL, &m_ref);
    disp_metrics_window(w, w->h, NULL, &m_h);
    char cells[6][32], text[256];
    bench_heading(r, "CPU solver: the quality each reaches");
    snprintf(text, sizeof text, "against a long reference solve (10 x 60 CG, %.0f ms): cost %.5g, KKT residual %.2g",
             ref_ms, c_ref, kkt);
    bench_note(r, text);
    snprintf(cells[0], sizeof cells[0], "cost");
    snprintf(cells[1], sizeof cells[1], "above min");
    snprintf(cells[2], sizeof cells[2], "MID (JND)");
    snprintf(cells[3], sizeof cells[3], "of h's MID");
    bench_row(r, true, "solver", 4, cells);
    for (int c = -1; c <= nc && st == VG_OK; c++) {
        const char *label = c < 0 ? "h (f0)" : c < nc ? configs[c].name : "reference";
        double cost = c < 0 ? c_h : c_ref, mid = c < 0 ? m_h.mid_distortion_jnd : m_ref.mid_distortion_jnd;
        if (c >= 0 && c < nc) {
            configs[c].desc.pool = pool;
            st = mid_solve(w, &configs[c].desc, f, &stats);
            disp_metrics_window(w, f, NULL, &m);
            cost = stats.cost_final;
            mid = m.mid_distortion_jnd;
        }
        snprintf(cells[0], sizeof cells[0], "%.5g", cost);
        snprintf(cells[1], sizeof cells[1], "%.1f%%", 100 * (cost / c_ref - 1));
        snprintf(cells[2], sizeof cells[2], "%.3f", mid);
        snprintf(cells[3], sizeof cells[3], "%.3f", mid / m_h.mid_distortion_jnd);
        if (st == VG_OK)
            bench_row(r, false, label, 4, cells);
    }
    return st;
}

vg_status bench_solver_tables(bench_report *r, int runs, bool with_quality)
{
    runs = runs < 1 ? 1 : runs > MAX_RUNS ? MAX_RUNS : runs;
    int threads[2] = {1, vg_cpu_count()};
    vg_pool *pools[2] = {NULL, NULL};
    vg_status st = VG_OK;
    for (int p = 0; p < 2 && st == VG_OK; p++)
        st = vg_pool_create(&(vg_pool_desc){.threads = threads[p]}, &pools[p]);
    vg_info("bench: the CPU solver's window (%dx%d x %d keyframes)", NX, NY, NT);
    mid_window *w = st == VG_OK ? mid_synth_window() : NULL;
    float *f = malloc((size_t)NX * NY * NT * sizeof(float));
    if (st == VG_OK && (!w || !f))
        st = VG_ERR_NOMEM;
    config configs[] = {
        {"descent, 8 iterations (paper)", {.solver = MID_SOLVER_DESCENT, .iterations = 8}},
        {"gauss-newton, 8 x 8 CG", {.solver = MID_SOLVER_GAUSS_NEWTON, .iterations = 8, .cg_iterations = 8}},
        {"gauss-newton default (4 x 8 CG)", {0}},
    };
    int nc = (int)(sizeof configs / sizeof configs[0]);
    if (st == VG_OK)
        st = speed(r, w, f, pools, threads, runs, configs, nc);
    if (st == VG_OK && with_quality)
        st = quality(r, w, f, pools[1], configs, nc);
    free(f);
    mid_window_destroy(w);
    vg_pool_destroy(pools[0]);
    vg_pool_destroy(pools[1]);
    return st;
}

/* ------------------------------------------------------------------------- */
/* The mode                                                                  */
/* ------------------------------------------------------------------------- */

static struct {
    int runs;
    bool no_quality;
} o;

static const vg_opt k_opts[] = {
    {"--runs", VG_OPT_INT, &o.runs, "N", "solves per solver and thread count, medians; also the triad's repetitions "
     "(default 5)", NULL, 1, MAX_RUNS},
    {"--no-quality", VG_OPT_FLAG, &o.no_quality, NULL,
     "skip the quality table and its long reference solve (10 x 60 CG)", NULL, 0, 0},
};

static int run(int argc, char **argv)
{
    memset(&o, 0, sizeof o);
    o.runs = 5;
    bool help = false;
    if (vg_cli_parse(&vg_cmd_bench_solver, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    printf("vergence bench solver: %d CPU cores; medians of %d run(s)\n", vg_cpu_count(), o.runs);
    bench_report r = {0};
    vg_status st = bench_solver_tables(&r, o.runs, !o.no_quality);
    if (st != VG_OK)
        vg_error("bench solver: %s", vg_status_text(st));
    return vg_status_exit_code(st);
}

const vg_cmd vg_cmd_bench_solver = {
    .name = "bench solver",
    .summary = "the CPU MID solver: ms per window and GB/s with 1 and all threads, the quality each solver reaches",
    .usage = "vergence bench solver [--runs N] [--no-quality]",
    .details = "The paper's descent (8 iterations), Gauss-Newton with 8 x 8 CG and the default Gauss-Newton\n"
               "(4 x 8 CG) on a synthetic 192x108 x 32-keyframe window (six balls crossing static layers in\n"
               "depth), each timed with 1 thread and all; GB/s against a STREAM triad of the same run. Then\n"
               "the cost and MID distortion each reaches against a long reference solve (about 30 s on a\n"
               "2-core CPU with --runs 1). 'vergence bench' prints the speed table too.",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
