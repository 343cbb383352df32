/* vergence — the GPU window build and solve against the CPU reference on
 * the same window (issue 4: max |f_gpu - f_cpu| < 0.05 arcmin after the same
 * iterations). Run one case: test_solve_gpu NAME. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "disparity/mid_solver.h"
#include "disparity/gpu/solve_gpu.h"
#include "disparity/testlib.h"
#include "test.h"

#define AGREEMENT_ARCMIN 0.05

typedef struct gpu_window {
    gpu *gpu;
    solve_gpu *m;
    mid_window *w;
    gpu_buffer published; /* a ring of nt slots: ratios, then slopes */
} gpu_window;

/* A built CPU window of the synthetic scene, and the GPU arena holding the
 * same inputs. */
static int open_window(gpu_window *c, synth_motion motion)
{
    memset(c, 0, sizeof *c);
    c->w = synth_window(&(synth_desc){.motion = motion, .op = DISP_OPERATOR_LANG, .salient_ball = true});
    CHECK(c->w, "synthetic window");
    CHECK(gpu_create(&(gpu_desc){0}, &c->gpu) == VG_OK, "gpu_create");
    const mid_window *w = c->w;
    CHECK(gpu_buffer_create(c->gpu, &(gpu_buffer_desc){.name = "mid.published",
                                                       .size = sizeof(mid_published) + 2 * (size_t)w->n * sizeof(float),
                                                       .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true},
                            &c->published) == VG_OK, "published");
    CHECK(solve_gpu_create(c->gpu, &(solve_gpu_desc){.nx = w->nx, .ny = w->ny, .max_keyframes = w->nt,
                                                 .host_visible = true, .published = c->published.buffer,
                                                 .published_size = c->published.size}, &c->m) == VG_OK,
          "solve_gpu_create");
    uint32_t cap = solve_gpu_capacity(c->m);
    float *field = solve_gpu_host(c->m, MID_B_FIELD, NULL), *flow = solve_gpu_host(c->m, MID_B_FLOW, NULL);
    float *invdt = solve_gpu_host(c->m, MID_B_INVDT, NULL);
    CHECK(field && flow && invdt, "host-visible arena");
    memcpy(field, w->g, (size_t)w->n * sizeof(float));
    memcpy(field + cap, w->h, (size_t)w->n * sizeof(float));
    memcpy(field + 2 * (size_t)cap, w->depth, (size_t)w->n * sizeof(float));
    memcpy(field + 3 * (size_t)cap, w->id, (size_t)w->n * sizeof(float));
    memcpy(flow, w->flow_fwd, 2 * (size_t)w->n * sizeof(float));
    memcpy(flow + 2 * (size_t)cap, w->flow_bwd, 2 * (size_t)w->n * sizeof(float));
    memcpy(invdt, w->inv_dt_f, (size_t)w->nt * sizeof(float));
    memcpy(invdt + MID_MAX_KEYFRAMES, w->inv_dt_b, (size_t)w->nt * sizeof(float));
    return 0;
}

static int close_window(gpu_window *c)
{
    solve_gpu_destroy(c->m);
    gpu_buffer_destroy(c->gpu, &c->published);
    gpu_destroy(c->gpu);
    mid_window_destroy(c->w);
    int messages = gpu_validation_messages();
    CHECK(messages == 0, "%d validation messages", messages);
    return 0;
}

static solve_gpu_params solve_of(const mid_window *w, const mid_solve_desc *d)
{
    return (solve_gpu_params){.keyframes = w->nt, .range_lo = w->range_lo, .range_hi = w->range_hi,
                           .solver = d->solver, .precond = d->precond, .iterations = d->iterations,
                           .cg_steps = d->cg_iterations, .publish = true, .store_cap = (uint32_t)w->nt};
}

static int run_program(gpu_window *c, int first, int last)
{
    VkCommandBuffer cmd;
    CHECK(gpu_oneshot_begin(c->gpu, &cmd) == VG_OK, "oneshot");
    solve_gpu_record(c->m, cmd, 0, first, last);
    CHECK(gpu_oneshot_submit(c->gpu, cmd) == VG_OK, "submit");
    return 0;
}

/* The links, the CSR transposes (row by row, in source order) and the
 * chains built on the GPU equal the CPU's. */
static int window_build(void)
{
    gpu_window c;
    if (open_window(&c, SYNTH_CONSTANT_ACCEL))
        return 1;
    const mid_window *w = c.w;
    solve_gpu_begin(c.m, &(solve_gpu_params){.keyframes = w->nt, .range_lo = w->range_lo, .range_hi = w->range_hi});
    if (run_program(&c, 0, 1))
        return 1;
    uint32_t cap = solve_gpu_capacity(c.m), acap = solve_gpu_adj_capacity(c.m);
    const mid_link *links = solve_gpu_host(c.m, MID_B_LINK, NULL);
    const uint32_t *off = solve_gpu_host(c.m, MID_B_ADJ_OFF, NULL);
    const mid_adj_entry *adj = solve_gpu_host(c.m, MID_B_ADJ, NULL);
    const int32_t *chain = solve_gpu_host(c.m, MID_B_CHAIN, NULL);
    const float *edge = solve_gpu_host(c.m, MID_B_EDGE, NULL), *target = solve_gpu_host(c.m, MID_B_TARGET, NULL);
    int bad_links = 0, bad_rows = 0, bad_chains = 0;
    double worst_edge = 0, worst_target = 0, worst_tap = 0;
    for (int i = 0; i < w->n; i++) {
        bad_links += memcmp(&links[i], &w->fwd[i], sizeof(mid_link)) != 0 ||
                     memcmp(&links[cap + i], &w->bwd[i], sizeof(mid_link)) != 0;
        for (int dir = 0; dir < 2; dir++) {
            const mid_adjoint *a = dir ? &w->bwd_adj : &w->fwd_adj;
            const uint32_t *o = off + (size_t)dir * (cap + 1);
            uint32_t len = a->offset[i + 1] - a->offset[i];
            bool same = o[i + 1] - o[i] == len;
            for (uint32_t q = 0; same && q < len; q++) {
                mid_adj_entry e = adj[(size_t)dir * acap + o[i] + q], r = a->entry[a->offset[i] + q];
                /* The same sources in the same order; tap weights to float
                 * rounding (a GPU compiler may fuse the products: NVIDIA's
                 * differ from the CPU's in the last bit). */
                same = e.src == r.src && fabsf(e.w - r.w) <= 1e-6f;
                worst_tap = fmax(worst_tap, fabs(e.w - r.w));
            }
            bad_rows += !same;
        }
        bad_chains += chain[i] != w->chain_next[i] || chain[cap + i] != w->chain_prev[i];
        worst_edge = fmax(worst_edge, fmax(fabs(edge[i] - w->edge_x[i]), fabs(edge[cap + i] - w->edge_y[i])));
        worst_target = fmax(worst_target, fmax(fabs(target[i] - w->ph[i]), fabs(target[cap + i] - w->pg_acc[i])));
    }
    printf("window %dx%dx%d: %d links, %d CSR rows, %d chain nodes differ; tap weights %.3g, edge weights %.3g, "
           "targets %.3g JND\n", w->nx, w->ny, w->nt, bad_links, bad_rows, bad_chains, worst_tap, worst_edge,
           worst_target);
    CHECK(bad_links == 0 && bad_rows == 0 && bad_chains == 0, "the GPU window differs from the CPU's");
    CHECK(worst_edge < 1e-5 && worst_target < 1e-3, "edge weights or targets differ");
    return close_window(&c);
}

/* f after the same solve on both sides. */
static int solve_agrees(synth_motion motion, mid_solve_desc d, const char *what)
{
    gpu_window c;
    if (open_window(&c, motion))
        return 1;
    const mid_window *w = c.w;
    float *f = malloc((size_t)w->n * sizeof(float));
    mid_solve_stats stats;
    CHECK(f && mid_solve(w, &d, f, &stats) == VG_OK, "CPU solve");
    solve_gpu_params s = solve_of(w, &d);
    solve_gpu_begin(c.m, &s);
    if (run_program(&c, 0, solve_gpu_item_count(c.m)))
        return 1;
    const float *fg = solve_gpu_host(c.m, MID_B_F, NULL);
    const mid_solve_state *st = solve_gpu_host(c.m, MID_B_STATE, NULL);
    double worst = 0, sum = 0, h_change = 0;
    int at = 0;
    for (int i = 0; i < w->n; i++) {
        double e = fabs((double)fg[i] - f[i]);
        sum += e;
        h_change = fmax(h_change, fabs((double)f[i] - w->h[i]));
        if (e > worst) {
            worst = e;
            at = i;
        }
    }
    printf("%s: CPU %d iterations, %d CG steps, cost %.6g -> %.6g; GPU %u iterations, %u CG steps, cost %.6g -> %.6g\n",
           what, stats.iterations, stats.cg_steps, stats.cost_initial, stats.cost_final, st->iteration, st->cg_steps,
           st->cost_initial, st->c);
    printf("%s: max |f_gpu - f_cpu| %.4g arcmin at %d (%.4f vs %.4f), mean %.3g; f moved up to %.3g arcmin from h\n",
           what, worst, at, fg[at], f[at], sum / w->n, h_change);
    CHECK(worst < AGREEMENT_ARCMIN, "GPU and CPU solutions differ by %.4g arcmin", worst);
    CHECK(h_change > 1.0, "the solve must change f for the comparison to mean something");
    /* The published corrections f / g and their slopes in time (what
     * mid.upsample interpolates with), against mid_window_ratio_slopes on the
     * CPU's f; a slope as the change of f it makes over a keyframe interval. */
    float *ratio = malloc((size_t)w->n * sizeof(float)), *slope = malloc((size_t)w->n * sizeof(float));
    CHECK(ratio && slope, "memory");
    for (int i = 0; i < w->n; i++)
        ratio[i] = f[i] / w->g[i];
    mid_window_ratio_slopes(w, ratio, slope);
    const float *pr = (const float *)((const mid_published *)c.published.mapped + 1);
    double worst_r = 0, worst_s = 0, slope_max = 0;
    for (int i = 0; i < w->n; i++) {
        int k = i / w->ns;
        double span = 1.0 / (w->inv_dt_f[k] > 0 ? w->inv_dt_f[k] : w->inv_dt_b[k]);
        worst_r = fmax(worst_r, fabs((double)pr[i] - ratio[i]) * w->g[i]);
        worst_s = fmax(worst_s, fabs((double)pr[w->n + i] - slope[i]) * span * w->g[i]);
        slope_max = fmax(slope_max, fabs((double)slope[i]) * span * w->g[i]);
    }
    printf("%s: published ratio max |gpu - cpu| %.4g arcmin, slope %.4g arcmin per interval (slopes up to %.3g)\n",
           what, worst_r, worst_s, slope_max);
    CHECK(worst_r < AGREEMENT_ARCMIN && worst_s < AGREEMENT_ARCMIN, "published corrections or slopes differ");
    CHECK(slope_max > 0.1, "the slopes must be non-trivial for the comparison to mean something");
    free(ratio);
    free(slope);
    free(f);
    return close_window(&c);
}

static int gauss_newton(void)
{
    return solve_agrees(SYNTH_CONSTANT_ACCEL, (mid_solve_desc){0}, "gauss-newton 4x8");
}

static int gauss_newton_8(void)
{
    return solve_agrees(SYNTH_CONSTANT_SPEED, (mid_solve_desc){.iterations = 8}, "gauss-newton 8x8");
}

static int descent_8(void)
{
    return solve_agrees(SYNTH_CONSTANT_ACCEL, (mid_solve_desc){.solver = MID_SOLVER_DESCENT, .iterations = 8},
                        "descent 8");
}

static int jacobi(void)
{
    return solve_agrees(SYNTH_CONSTANT_SPEED, (mid_solve_desc){.precond = MID_PRECOND_JACOBI}, "gauss-newton jacobi");
}

/* Two warm-started halves on the GPU end where one solve of both halves'
 * iterations ends on the CPU (paper 4.5: the last solution is the guess). */
static int warm_start(void)
{
    gpu_window c;
    if (open_window(&c, SYNTH_CONSTANT_ACCEL))
        return 1;
    const mid_window *w = c.w;
    float *f = malloc((size_t)w->n * sizeof(float)), *half = malloc((size_t)w->n * sizeof(float));
    CHECK(f && half, "memory");
    CHECK(mid_solve(w, &(mid_solve_desc){.iterations = 2}, half, NULL) == VG_OK, "CPU first half");
    CHECK(mid_solve(w, &(mid_solve_desc){.iterations = 2, .f_init = half}, f, NULL) == VG_OK, "CPU second half");
    solve_gpu_params s = solve_of(w, &(mid_solve_desc){.iterations = 2});
    s.publish_from = w->nt; /* the publish step keeps the solution for the warm start */
    solve_gpu_begin(c.m, &s);
    if (run_program(&c, 0, solve_gpu_item_count(c.m)))
        return 1;
    s.warm = true;
    s.prev_keyframes = w->nt;
    solve_gpu_begin(c.m, &s);
    if (run_program(&c, 1, solve_gpu_item_count(c.m))) /* the window is built */
        return 1;
    const float *fg = solve_gpu_host(c.m, MID_B_F, NULL);
    double worst = 0;
    for (int i = 0; i < w->n; i++)
        worst = fmax(worst, fabs((double)fg[i] - f[i]));
    printf("warm start, 2 + 2 iterations: max |f_gpu - f_cpu| %.4g arcmin\n", worst);
    CHECK(worst < AGREEMENT_ARCMIN, "warm-started solves differ by %.4g arcmin", worst);
    free(f);
    free(half);
    return close_window(&c);
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"window_build", window_build}, {"gauss_newton", gauss_newton}, {"gauss_newton_8", gauss_newton_8},
        {"descent_8", descent_8},       {"jacobi", jacobi},             {"warm_start", warm_start},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
