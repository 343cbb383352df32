/* The MID optimiser: derivatives against an independent double-precision
 * oracle, and the solver on synthetic scenes. Run one case: test_mid NAME. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../test.h"
#include "core/parallel.h"
#include "disparity/disp_metrics.h"
#include "disparity/mid_solver.h"
#include "testlib.h"

/* ------------------------------------------------------------------------- */
/* Derivatives                                                               */
/* ------------------------------------------------------------------------- */

static void link_census(const mid_window *w, int *valid, int *invalid_inside, int *last)
{
    *valid = *invalid_inside = *last = 0;
    for (int i = 0; i < w->n; i++) {
        int k = i / w->ns;
        if (k + 1 == w->nt)
            (*last)++;
        else if (w->fwd[i].mask)
            (*valid)++;
        else
            (*invalid_inside)++;
    }
}

/* Analytic gradient (float kernels, adjoint gathers) vs central differences
 * of the double reference cost, on random fields with flow and occlusions. */
static int gradient_fd(void)
{
    mid_window *w = random_window(11, 9, 6, 7u);
    CHECK(w, "window");
    int valid, invalid, last;
    link_census(w, &valid, &invalid, &last);
    printf("forward links: %d valid, %d occluded or out of frame, %d on the last keyframe\n", valid, invalid, last);
    CHECK(valid > w->n / 4 && invalid > w->n / 10, "the random window must exercise both cases");
    unsigned s = 99u;
    float *f = malloc(w->n * sizeof(float)), *grad = malloc(w->n * sizeof(float));
    double *fd = malloc(w->n * sizeof(double)), *x = malloc(w->n * sizeof(double));
    for (int i = 0; i < w->n; i++)
        x[i] = f[i] = rnd_uniform(&s, 205, 335);
    mid_weights wt = {0};
    CHECK(mid_gradient(w, wt, f, grad, NULL) == VG_OK, "gradient");
    const double eps = 1e-3;
    double num = 0, den = 0, worst = 0;
    int worst_i = 0;
    for (int i = 0; i < w->n; i++) {
        double keep = x[i];
        x[i] = keep + eps;
        double cp = reference_cost(w, wt, x);
        x[i] = keep - eps;
        double cm = reference_cost(w, wt, x);
        x[i] = keep;
        fd[i] = (cp - cm) / (2 * eps);
        double d = grad[i] - fd[i];
        num += d * d;
        den += fd[i] * fd[i];
        if (fabs(d) > worst) {
            worst = fabs(d);
            worst_i = i;
        }
    }
    double rel = sqrt(num / den);
    printf("gradient vs finite differences: relative L2 error %.3g (|fd| %.4g); worst at %d: %.6g vs %.6g\n",
           rel, sqrt(den), worst_i, grad[worst_i], fd[worst_i]);
    CHECK(rel < 1e-4, "relative error %.3g", rel);
    free(f);
    free(grad);
    free(fd);
    free(x);
    mid_window_destroy(w);
    return 0;
}

/* The float cost (the solver's) agrees with the double oracle. */
static int cost_reference(void)
{
    mid_window *w = random_window(13, 7, 5, 3u);
    CHECK(w, "window");
    unsigned s = 5u;
    float *f = malloc(w->n * sizeof(float));
    double *x = malloc(w->n * sizeof(double));
    for (int i = 0; i < w->n; i++)
        x[i] = f[i] = rnd_uniform(&s, 205, 335);
    mid_cost_terms t;
    double c = mid_cost(w, (mid_weights){0}, f, &t, NULL);
    double r = reference_cost(w, (mid_weights){0}, x);
    printf("cost %.9g (terms %.4g %.4g %.4g %.4g), reference %.9g, relative %.3g\n", c, t.term[0],
           t.term[1], t.term[2], t.term[3], r, fabs(c - r) / r);
    CHECK(fabs(c - r) < 1e-5 * r, "float %.9g vs double %.9g", c, r);
    free(f);
    free(x);
    mid_window_destroy(w);
    return 0;
}

/* The Gauss-Newton product is symmetric and its diagonal is the Jacobi
 * preconditioner: u.Hv = v.Hu, and e_j.He_j = diag_j. */
static int gauss_newton_operator(void)
{
    mid_window *w = random_window(9, 8, 5, 11u);
    CHECK(w, "window");
    mid_weights wt = mid_weights_resolve((mid_weights){0});
    mid_lin lin;
    CHECK(mid_lin_alloc(&lin, w->n) == VG_OK, "alloc");
    unsigned s = 1u;
    float *f = calloc(w->n, sizeof(float)), *u = calloc(w->n, sizeof(float)), *v = calloc(w->n, sizeof(float));
    float *hu = calloc(w->n, sizeof(float)), *hv = calloc(w->n, sizeof(float)), *diag = calloc(w->n, sizeof(float));
    float *a = calloc(w->n, sizeof(float)), *b = calloc(w->n, sizeof(float));
    for (int i = 0; i < w->n; i++) {
        f[i] = rnd_uniform(&s, 205, 335);
        u[i] = rnd_uniform(&s, -1, 1);
        v[i] = rnd_uniform(&s, -1, 1);
    }
    mid_terms_linearize(w, wt, f, &lin, NULL, NULL, NULL);
    mid_terms_diagonal(w, wt, &lin, diag, NULL);
    mid_terms_direction(w, wt, &lin, u, a, b, NULL);
    mid_terms_gather(w, wt, u, NULL, a, b, hu, NULL);
    mid_terms_direction(w, wt, &lin, v, a, b, NULL);
    mid_terms_gather(w, wt, v, NULL, a, b, hv, NULL);
    double uhv = 0, vhu = 0;
    for (int i = 0; i < w->n; i++) {
        uhv += (double)u[i] * hv[i];
        vhu += (double)v[i] * hu[i];
    }
    printf("u.Hv %.9g  v.Hu %.9g\n", uhv, vhu);
    CHECK(fabs(uhv - vhu) < 1e-5 * (fabs(uhv) + fabs(vhu)), "asymmetric: %.9g vs %.9g", uhv, vhu);
    double worst = 0;
    for (int j = 0; j < w->n; j += 7) {
        memset(u, 0, w->n * sizeof(float));
        u[j] = 1;
        mid_terms_direction(w, wt, &lin, u, a, b, NULL);
        mid_terms_gather(w, wt, u, NULL, a, b, hu, NULL);
        double e = fabs(hu[j] - diag[j]) / diag[j];
        worst = fmax(worst, e);
        CHECK(e < 1e-5, "diag %d: e.He %.9g vs %.9g", j, hu[j], diag[j]);
    }
    printf("diagonal vs e_j.H.e_j: worst relative %.3g\n", worst);
    free(f); free(u); free(v); free(hu); free(hv); free(diag); free(a); free(b);
    mid_lin_free(&lin);
    mid_window_destroy(w);
    return 0;
}

/* ------------------------------------------------------------------------- */
/* Solver on the synthetic scenes                                            */
/* ------------------------------------------------------------------------- */

typedef struct outcome {
    disp_metrics mh, mf;
    mid_solve_stats st;
} outcome;

static int solve_scene(const synth_desc *sd, mid_solve_desc sol, float **f_out, outcome *o, mid_window **w_out)
{
    mid_window *w = synth_window(sd);
    if (!w)
        return 1;
    float *f = malloc(w->n * sizeof(float));
    if (mid_solve(w, &sol, f, &o->st) != VG_OK)
        return 1;
    disp_metrics_window(w, w->h, NULL, &o->mh);
    disp_metrics_window(w, f, NULL, &o->mf);
    *f_out = f;
    *w_out = w;
    return 0;
}

static int mid_reduction(synth_motion motion, const char *label)
{
    synth_desc sd = {.motion = motion};
    float *f;
    mid_window *w;
    outcome o;
    CHECK(solve_scene(&sd, (mid_solve_desc){0}, &f, &o, &w) == 0, "solve");
    double range = w->range_hi - w->range_lo, red = 1.0 - o.mf.mid_distortion_jnd / o.mh.mid_distortion_jnd;
    printf("%s: MID distortion h %.3f JND -> f %.3f JND (%.1f %% less) over %d moving samples\n", label,
           o.mh.mid_distortion_jnd, o.mf.mid_distortion_jnd, 100 * red, o.mf.moving_measured);
    printf("  f range violation %.4f, static RMS(f-h) %.3f arcmin (%.2f %% of the %.0f arcmin range), grad %.3f\n",
           o.mf.range_violation, o.mf.static_rms, 100 * o.mf.static_rms / range, range, o.mf.static_grad_rms);
    printf("  cost %.5g -> %.5g in %d iterations (%d CG steps), %.1f ms\n", o.st.cost_initial, o.st.cost_final,
           o.st.iterations, o.st.cg_steps, o.st.ms);
    CHECK(o.mh.mid_distortion_jnd > 1.0, "h must distort motion in depth: %.3f JND", o.mh.mid_distortion_jnd);
    CHECK(red >= 0.5, "f cuts MID distortion by %.1f %% only", 100 * red);
    float lo = 1e9f, hi = -1e9f;
    for (int i = 0; i < w->n; i++) {
        lo = fminf(lo, f[i]);
        hi = fmaxf(hi, f[i]);
    }
    CHECK(lo >= w->range_lo && hi <= w->range_hi, "f in [%.4f, %.4f], range [%.4f, %.4f]", lo, hi, w->range_lo, w->range_hi);
    CHECK(o.mf.static_rms < 0.05 * range, "static RMS %.3f arcmin >= 5 %% of range", o.mf.static_rms);
    free(f);
    mid_window_destroy(w);
    return 0;
}

static int reduction_constant_speed(void) { return mid_reduction(SYNTH_CONSTANT_SPEED, "constant speed"); }
static int reduction_constant_accel(void) { return mid_reduction(SYNTH_CONSTANT_ACCEL, "constant acceleration"); }


/* The long reference solve: many Gauss-Newton iterations with long CG runs,
 * accepted only when the projected gradient (the KKT residual) vanishes. */
static int reference_minimum(const mid_window *w, double *c_ref, float *f_ref)
{
    mid_solve_stats st;
    if (mid_solve(w, &(mid_solve_desc){.iterations = 12, .cg_iterations = 100}, f_ref, &st) != VG_OK)
        return 1;
    double kkt = mid_projected_gradient_norm(w, (mid_weights){0}, f_ref, NULL);
    double kkt_h = mid_projected_gradient_norm(w, (mid_weights){0}, w->h, NULL);
    printf("  reference: cost %.6g after %d iterations, %d CG steps; KKT residual %.3g (%.3g at h)\n",
           st.cost_final, st.iterations, st.cg_steps, kkt, kkt_h);
    CHECK(kkt < 1e-3 * kkt_h, "the reference solve did not converge: KKT residual %.3g", kkt);
    *c_ref = st.cost_final;
    return 0;
}

static int converged(synth_motion motion, const char *label)
{
    mid_window *w = synth_window(&(synth_desc){.motion = motion});
    CHECK(w, "window");
    float *f = malloc(w->n * sizeof(float)), *fr = malloc(w->n * sizeof(float));
    double c_ref;
    printf("%s:\n", label);
    CHECK(reference_minimum(w, &c_ref, fr) == 0, "reference");
    mid_solve_stats st, sd;
    CHECK(mid_solve(w, &(mid_solve_desc){0}, f, &st) == VG_OK, "default solve");
    CHECK(mid_solve(w, &(mid_solve_desc){.solver = MID_SOLVER_DESCENT}, f, &sd) == VG_OK, "descent");
    double gap = st.cost_final / c_ref - 1.0;
    printf("  default (%d x %d CG): cost %.6g = minimum %+.2f %% (%.1f %% of the way from h left), %d passes\n",
           st.iterations, MID_GN_CG_STEPS, st.cost_final, 100 * gap,
           100 * (st.cost_final - c_ref) / (st.cost_initial - c_ref), st.passes);
    printf("  paper's descent (8 x lambda 0.5): cost %.6g = minimum %+.2f %%, %d passes\n", sd.cost_final,
           100 * (sd.cost_final / c_ref - 1.0), sd.passes);
    CHECK(gap <= 0.05, "default solve ends %.2f %% above the minimum", 100 * gap);
    CHECK(st.cost_final >= c_ref * (1 - 1e-6), "the reference is not the minimum: %.9g < %.9g", st.cost_final, c_ref);
    free(f);
    free(fr);
    mid_window_destroy(w);
    return 0;
}

static int converged_constant_speed(void) { return converged(SYNTH_CONSTANT_SPEED, "constant speed"); }
static int converged_constant_accel(void) { return converged(SYNTH_CONSTANT_ACCEL, "constant acceleration"); }

/* The Armijo line search makes every accepted step lower the cost. */
static int cost_monotone(void)
{
    for (int motion = 0; motion < 2; motion++) {
        mid_window *w = synth_window(&(synth_desc){.motion = motion});
        CHECK(w, "window");
        float *f = malloc(w->n * sizeof(float));
        double hist[MID_GN_ITERATIONS + 1];
        mid_solve_stats st;
        CHECK(mid_solve(w, &(mid_solve_desc){.cost_history = hist}, f, &st) == VG_OK, "solve");
        printf("motion %d: cost", motion);
        for (int i = 0; i <= MID_GN_ITERATIONS; i++)
            printf(" %.6g", hist[i]);
        printf("\n");
        CHECK(hist[1] < hist[0], "the first iteration must lower the cost");
        for (int i = 1; i <= MID_GN_ITERATIONS; i++)
            CHECK(hist[i] <= hist[i - 1], "cost rose at iteration %d: %.9g -> %.9g", i, hist[i - 1], hist[i]);
        free(f);
        mid_window_destroy(w);
    }
    return 0;
}

/* h = g with constant speed: g already has g's motion, so f = g. */
static int identity_when_h_is_g(void)
{
    synth_desc sd = {.motion = SYNTH_CONSTANT_SPEED, .h_equals_g = true};
    mid_window *w = synth_window(&sd);
    CHECK(w, "window");
    float *f = malloc(w->n * sizeof(float));
    for (int solver = MID_SOLVER_GAUSS_NEWTON; solver <= MID_SOLVER_DESCENT; solver++) {
        mid_solve_stats st;
        CHECK(mid_solve(w, &(mid_solve_desc){.solver = solver}, f, &st) == VG_OK, "solve");
        double worst = 0, moving = 0;
        for (int i = 0; i < w->n; i++) {
            worst = fmax(worst, fabs(f[i] - w->g[i]));
            if (w->fwd[i].mask && fabs(mid_link_gather(w->fwd, w->nx, i, w->g) - w->g[i]) > 1)
                moving++;
        }
        printf("solver %d: max |f - g| = %.3g arcmin (cost %.3g; %.0f moving samples)\n", solver, worst,
               st.cost_final, moving);
        CHECK(moving > 50, "the scene must move in depth");
        CHECK(worst <= 1e-3, "f departs from g by %.3g arcmin", worst);
    }
    free(f);
    mid_window_destroy(w);
    return 0;
}

/* Deterministic reductions: 1 and 2 threads give the same bits. */
static int threads_deterministic(void)
{
    mid_window *w = synth_window(&(synth_desc){.motion = SYNTH_CONSTANT_ACCEL});
    CHECK(w, "window");
    vg_pool *pool;
    CHECK(vg_pool_create(&(vg_pool_desc){.threads = 2}, &pool) == VG_OK, "pool");
    float *f1 = malloc(w->n * sizeof(float)), *f2 = malloc(w->n * sizeof(float));
    mid_solve_stats s1, s2;
    CHECK(mid_solve(w, &(mid_solve_desc){0}, f1, &s1) == VG_OK, "1 thread");
    CHECK(mid_solve(w, &(mid_solve_desc){.pool = pool}, f2, &s2) == VG_OK, "2 threads");
    int differ = 0;
    for (int i = 0; i < w->n; i++)
        differ += memcmp(&f1[i], &f2[i], sizeof(float)) != 0;
    printf("1 thread: cost %.17g, %.1f ms; 2 threads: cost %.17g, %.1f ms; %d values differ\n", s1.cost_final,
           s1.ms, s2.cost_final, s2.ms, differ);
    CHECK(differ == 0 && s1.cost_final == s2.cost_final, "%d values differ", differ);
    vg_pool_destroy(pool);
    free(f1);
    free(f2);
    mid_window_destroy(w);
    return 0;
}

/* Sec. 4.5: the solver starts from the last solution; a solve split in two
 * warm-started halves continues where the first stopped. */
static int warm_start(void)
{
    mid_window *w = synth_window(&(synth_desc){.motion = SYNTH_CONSTANT_SPEED});
    CHECK(w, "window");
    float *f1 = malloc(w->n * sizeof(float)), *f2 = malloc(w->n * sizeof(float));
    mid_solve_stats a, b, cold;
    CHECK(mid_solve(w, &(mid_solve_desc){.iterations = 2}, f1, &a) == VG_OK, "first");
    CHECK(mid_solve(w, &(mid_solve_desc){.iterations = 2, .f_init = f1}, f2, &b) == VG_OK, "warm");
    CHECK(mid_solve(w, &(mid_solve_desc){.iterations = 2}, f1, &cold) == VG_OK, "cold");
    printf("cold 2 iterations: %.6g -> %.6g; warm start: %.6g -> %.6g\n", a.cost_initial, a.cost_final,
           b.cost_initial, b.cost_final);
    CHECK(fabs(b.cost_initial - a.cost_final) <= 1e-9 * a.cost_final, "the warm start must begin at the last solution");
    CHECK(b.cost_final < cold.cost_final, "warm-started iterations must add to the cold ones");
    /* A window that slid by one keyframe: old keyframes shift down, new ones start at h. */
    mid_window_warm_start(w, f2, 1, f1);
    CHECK(memcmp(f1, f2 + w->ns, (size_t)(w->n - w->ns) * sizeof(float)) == 0, "shifted keyframes");
    CHECK(memcmp(f1 + (w->n - w->ns), w->h + (w->n - w->ns), (size_t)w->ns * sizeof(float)) == 0, "new keyframe = h");
    free(f1);
    free(f2);
    mid_window_destroy(w);
    return 0;
}

/* Samples of unknown g (a dataset's inf or 0) are out of the costs and the
 * metrics: whatever g holds there, f and the metrics are the same bits;
 * without the mask the same made-up g changes f. */
static int unknown_masked(void)
{
    float *f[3];
    disp_metrics m[3];
    int unknown = 0, n = 0;
    for (int run = 0; run < 3; run++) {
        mid_window *w = synth_window(&(synth_desc){.motion = SYNTH_CONSTANT_ACCEL});
        CHECK(w, "window");
        n = w->n;
        unknown = 0;
        unsigned seed = 5u + (unsigned)run;
        for (int i = 0; i < w->n; i++) {
            int x = i % w->ns % w->nx;
            if (x < w->nx / 2 - 2 || x > w->nx / 2 + 2)
                continue; /* a band of columns every keyframe, crossed by the ball */
            w->unknown[i] = run < 2;
            w->g[i] = run == 0 ? 200.0f : rnd_uniform(&seed, 150, 450);
            unknown++;
        }
        CHECK(mid_window_build(w, NULL) == VG_OK, "build");
        for (int i = 0; i < w->n && run < 2; i++) {
            mid_link l[2] = {w->fwd[i], w->bwd[i]};
            for (int d = 0; d < 2; d++) {
                uint idx[4] = {l[d].base, l[d].base + 1, l[d].base + (uint)w->nx, l[d].base + (uint)w->nx + 1};
                for (int t = 0; t < 4; t++)
                    CHECK(!(l[d].mask & (1u << t)) || (!w->unknown[i] && !w->unknown[idx[t]]),
                          "a link touches an unknown sample at %d", i);
            }
            CHECK(!w->unknown[i] || (w->edge_x[i] == 0 && w->edge_y[i] == 0), "an edge from an unknown sample");
        }
        f[run] = malloc(w->n * sizeof(float));
        mid_solve_stats st;
        CHECK(mid_solve(w, &(mid_solve_desc){0}, f[run], &st) == VG_OK, "solve");
        disp_metrics_window(w, f[run], NULL, &m[run]);
        mid_window_destroy(w);
    }
    int same = 0, moved = 0;
    for (int i = 0; i < n; i++) {
        same += memcmp(&f[0][i], &f[1][i], sizeof(float)) == 0;
        moved += fabsf(f[2][i] - f[1][i]) > 1e-3f;
    }
    printf("%d of %d samples unknown: f identical at %d of %d with two made-up g's (MID %.4f / %.4f JND over %d / %d "
           "samples); unmasked, the made-up g moves f at %d samples (MID %.4f JND)\n",
           unknown, n, same, n, m[0].mid_distortion_jnd, m[1].mid_distortion_jnd, m[0].samples, m[1].samples, moved,
           m[2].mid_distortion_jnd);
    CHECK(same == n && m[0].mid_distortion_jnd == m[1].mid_distortion_jnd && m[0].samples == n - unknown,
          "unknown g leaks into f or the metrics");
    CHECK(moved > 0, "the made-up g must matter when not masked (the check could not fail)");
    for (int run = 0; run < 3; run++)
        free(f[run]);
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"gradient_fd", gradient_fd},
        {"cost_reference", cost_reference},
        {"gauss_newton_operator", gauss_newton_operator},
        {"reduction_constant_speed", reduction_constant_speed},
        {"reduction_constant_accel", reduction_constant_accel},
        {"converged_constant_speed", converged_constant_speed},
        {"converged_constant_accel", converged_constant_accel},
        {"cost_monotone", cost_monotone},
        {"identity_when_h_is_g", identity_when_h_is_g},
        {"threads_deterministic", threads_deterministic},
        {"warm_start", warm_start},
        {"unknown_masked", unknown_masked},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
