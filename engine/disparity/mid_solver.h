/* vergence — the MID minimisation (paper Sec. 4.3 and 4.5) over a window.
 *
 * Two solvers, both projecting f onto the target range after every step:
 *   gauss-newton (default): per outer iteration, linearise the perceptual
 *     terms, solve the Gauss-Newton system on the free variables with a few
 *     Jacobi-preconditioned conjugate-gradient steps (matrix-free, the
 *     products are gathers), then a backtracking line search on the true
 *     cost. The cost falls monotonically.
 *   descent: the paper's f <- P(f - lambda D^-1 grad c), D the diagonal of
 *     the Gauss-Newton Hessian (DESIGN.md), lambda 0.5, 8 iterations.
 * Equations and the choice of defaults: docs/method.md. */
#pragma once
#include "core/parallel.h"
#include "core/status.h"
#include "mid_terms.h"
#include "mid_window.h"

typedef enum mid_solver_kind {
    MID_SOLVER_DEFAULT = 0, /* Gauss-Newton */
    MID_SOLVER_GAUSS_NEWTON,
    MID_SOLVER_DESCENT,
} mid_solver_kind;

typedef enum mid_precond_kind {
    MID_PRECOND_DEFAULT = 0, /* temporal lines */
    MID_PRECOND_LINES,
    MID_PRECOND_JACOBI,
} mid_precond_kind;

typedef struct mid_solve_desc {
    mid_solver_kind solver;
    mid_precond_kind precond; /* of the Gauss-Newton CG */
    int iterations;        /* outer iterations, 0 = MID_GN_ITERATIONS / MID_DESCENT_ITERATIONS */
    int cg_iterations;     /* CG steps per Gauss-Newton iteration, 0 = MID_GN_CG_STEPS */
    float step;            /* descent lambda, 0 = MID_DESCENT_STEP */
    mid_weights weights;   /* all zero = the paper's */
    const float *f_init;   /* warm start (Sec. 4.5), NULL = f0 = h */
    double *cost_history;  /* optional: cost at f0 and after each iteration (iterations + 1) */
    vg_pool *pool;         /* NULL = calling thread only */
} mid_solve_desc;

typedef struct mid_solve_stats {
    int iterations;        /* outer iterations run (a converged solve stops early) */
    int cg_steps;          /* total CG steps */
    int line_trials;       /* total cost evaluations of the line search */
    int passes;            /* traversals of the window: kernels, vector updates, preconditioner sweeps */
    double cost_initial, cost_final;
    mid_cost_terms terms;  /* at the result */
    double ms;             /* wall time */
    double bytes;          /* compulsory memory traffic of all passes */
} mid_solve_stats;

typedef struct mid_solver mid_solver;

/* Workspace for windows of n unknowns; reuse it across frames. */
vg_status mid_solver_create(int n, mid_solver **out);
void mid_solver_destroy(mid_solver *s);
/* Minimises c over the built window; f receives the result (n floats). */
vg_status mid_solver_run(mid_solver *s, const mid_window *w, const mid_solve_desc *desc, float *f,
                         mid_solve_stats *stats);
/* One-shot: create, run, destroy. */
vg_status mid_solve(const mid_window *w, const mid_solve_desc *desc, float *f,
                    mid_solve_stats *stats);

/* Norm of the projected gradient ||P(f - grad) - f|| / sqrt(n): zero exactly
 * at a stationary point of the box-constrained problem (a KKT check). */
double mid_projected_gradient_norm(const mid_window *w, mid_weights wt, const float *f,
                                   vg_pool *pool);
