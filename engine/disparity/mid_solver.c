#include "mid_solver.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/log.h"
#include "mid_precond.h"

/* Armijo constant and halvings of the backtracking line search; relative
 * residual at which CG stops early (deterministic: depends only on data); a
 * variable within BOUND_EPS arcmin of a bound can be held there. Shared with
 * the GPU solver (mid_shared.h). */
#define LINE_ARMIJO MID_LINE_ARMIJO
#define LINE_MAX_TRIALS MID_LINE_TRIALS
#define CG_TOLERANCE MID_CG_TOLERANCE
#define BOUND_EPS MID_BOUND_EPS

struct mid_solver {
    int n;
    mid_lin lin;
    float *grad, *diag, *s, *r, *z, *p, *hp, *f_try, *free_mask;
    float *l0, *l1, *l2; /* factor of the line preconditioner */
    double *partial; /* 4 per block */
};

vg_status mid_solver_create(int n, mid_solver **out)
{
    *out = NULL;
    mid_solver *s = calloc(1, sizeof *s);
    if (!s)
        return VG_ERR_NOMEM;
    s->n = n;
    vg_status st = mid_lin_alloc(&s->lin, n);
    float **fields[] = {&s->grad, &s->diag, &s->s, &s->r, &s->z, &s->p, &s->hp, &s->f_try, &s->free_mask,
                        &s->l0, &s->l1, &s->l2};
    for (size_t i = 0; st == VG_OK && i < sizeof fields / sizeof fields[0]; i++)
        if (!(*fields[i] = calloc((size_t)n, sizeof(float))))
            st = VG_ERR_NOMEM;
    if (st == VG_OK && !(s->partial = calloc((size_t)vg_block_count(n, MID_BLOCK) * 4, sizeof(double))))
        st = VG_ERR_NOMEM;
    if (st != VG_OK) {
        mid_solver_destroy(s);
        return st;
    }
    *out = s;
    return VG_OK;
}

void mid_solver_destroy(mid_solver *s)
{
    if (!s)
        return;
    mid_lin_free(&s->lin);
    free(s->grad);
    free(s->diag);
    free(s->s);
    free(s->r);
    free(s->z);
    free(s->p);
    free(s->hp);
    free(s->f_try);
    free(s->free_mask);
    free(s->l0);
    free(s->l1);
    free(s->l2);
    free(s->partial);
    free(s);
}

/* ------------------------------------------------------------------------- */
/* Element-wise passes with per-block partial sums                           */
/* ------------------------------------------------------------------------- */

typedef enum vec_op {
    OP_CG_START,   /* free set, r = -g, s = 0; sum |projected gradient|^2 */
    OP_ZP_INIT,    /* (Jacobi: z = r / D), p = z; sum r.z */
    OP_MASK_DOT,   /* Hp *= free mask; sum p.Hp */
    OP_CG_UPDATE,  /* s += a p, r -= a Hp, (Jacobi: z = r / D; sum r.z) */
    OP_RZ,         /* sum r.z */
    OP_P_UPDATE,   /* p = z + b p */
    OP_TRIAL,      /* f_try = P(f + t s); sum g.(f_try - f) */
    OP_DESCENT,    /* f_try = P(f - lambda g / D); sum g.(f_try - f) */
} vec_op;

typedef struct vec_ctx {
    vec_op op;
    mid_solver *s;
    const float *f;
    float lo, hi, scalar;
    int jacobi;
    double *partial;
    mid_solve_stats *stats; /* traffic accounting, may be NULL */
} vec_ctx;

static inline float clampf(float v, float lo, float hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

static void vec_block(void *c, int block, int begin, int end)
{
    vec_ctx *x = c;
    mid_solver *s = x->s;
    double acc0 = 0, acc1 = 0;
    for (int i = begin; i < end; i++) {
        switch (x->op) {
        case OP_CG_START: {
            /* Projected Newton (Bertsekas 1982): a variable at a bound whose
             * gradient pushes outward stays there this iteration. */
            float f = x->f[i], g = s->grad[i];
            bool held = (f <= x->lo + BOUND_EPS && g > 0) || (f >= x->hi - BOUND_EPS && g < 0);
            float m = held ? 0.0f : 1.0f;
            s->free_mask[i] = m;
            s->r[i] = -g * m;
            s->s[i] = 0.0f;
            float pg = clampf(f - g, x->lo, x->hi) - f;
            acc1 += (double)pg * pg;
            break;
        }
        case OP_ZP_INIT:
            if (x->jacobi)
                s->z[i] = s->r[i] / s->diag[i];
            s->p[i] = s->z[i];
            acc0 += (double)s->r[i] * s->z[i];
            break;
        case OP_MASK_DOT:
            s->hp[i] *= s->free_mask[i];
            acc0 += (double)s->p[i] * s->hp[i];
            break;
        case OP_CG_UPDATE:
            s->s[i] += x->scalar * s->p[i];
            s->r[i] -= x->scalar * s->hp[i];
            if (x->jacobi) {
                s->z[i] = s->r[i] / s->diag[i];
                acc0 += (double)s->r[i] * s->z[i];
            }
            break;
        case OP_RZ:
            acc0 += (double)s->r[i] * s->z[i];
            break;
        case OP_P_UPDATE:
            s->p[i] = s->z[i] + x->scalar * s->p[i];
            break;
        case OP_TRIAL:
            s->f_try[i] = clampf(x->f[i] + x->scalar * s->s[i], x->lo, x->hi);
            acc0 += (double)s->grad[i] * (s->f_try[i] - x->f[i]);
            break;
        case OP_DESCENT:
            s->f_try[i] = clampf(x->f[i] - x->scalar * s->grad[i] / s->diag[i], x->lo, x->hi);
            acc0 += (double)s->grad[i] * (s->f_try[i] - x->f[i]);
            break;
        }
    }
    x->partial[2 * block] = acc0;
    x->partial[2 * block + 1] = acc1;
}

/* Floats read and written per element by each op (bench traffic). */
static const int g_op_floats[] = {
    [OP_CG_START] = 5, [OP_ZP_INIT] = 4, [OP_MASK_DOT] = 4, [OP_CG_UPDATE] = 7,
    [OP_RZ] = 2,       [OP_P_UPDATE] = 3, [OP_TRIAL] = 4,   [OP_DESCENT] = 4,
};

/* Runs an element-wise op; returns its sums in fixed block order. */
static void vec_run(mid_solver *s, vg_pool *pool, vec_ctx c, double *sum0, double *sum1)
{
    c.s = s;
    c.partial = s->partial;
    vg_parallel_for(pool, s->n, MID_BLOCK, vec_block, &c);
    if (c.stats) {
        c.stats->passes++;
        c.stats->bytes += 4.0 * g_op_floats[c.op] * s->n;
    }
    double a = 0, b = 0;
    for (int k = 0; k < vg_block_count(s->n, MID_BLOCK); k++) {
        a += s->partial[2 * k];
        b += s->partial[2 * k + 1];
    }
    if (sum0)
        *sum0 = a;
    if (sum1)
        *sum1 = b;
}

/* ------------------------------------------------------------------------- */
/* Solvers                                                                   */
/* ------------------------------------------------------------------------- */

typedef struct run_state {
    const mid_window *w;
    mid_weights wt;
    vg_pool *pool;
    mid_solve_stats *st;
    float lo, hi;
    int jacobi; /* CG preconditioner: 1 Jacobi, 0 temporal lines */
} run_state;

static double linearize(mid_solver *s, run_state *rs, const float *f)
{
    rs->st->passes++;
    rs->st->bytes += mid_terms_bytes_linearize(rs->w);
    return mid_terms_linearize(rs->w, rs->wt, f, &s->lin, NULL, s->partial, rs->pool);
}

/* Gradient and Jacobi diagonal at the linearisation point (two gathers). */
static void gradient_and_diagonal(mid_solver *s, run_state *rs, const float *f)
{
    mid_terms_gather(rs->w, rs->wt, f, rs->w->h, s->lin.alpha, s->lin.beta, s->grad, rs->pool);
    mid_terms_diagonal(rs->w, rs->wt, &s->lin, s->diag, rs->pool);
    rs->st->passes += 2;
    rs->st->bytes += 2 * mid_terms_bytes_gather(rs->w);
}

/* Hp = M (2/n J^T W J) M p, M the free mask; returns p.Hp. */
static double hessian_product(mid_solver *s, run_state *rs)
{
    mid_terms_direction(rs->w, rs->wt, &s->lin, s->p, s->lin.alpha, s->lin.beta, rs->pool);
    mid_terms_gather(rs->w, rs->wt, s->p, NULL, s->lin.alpha, s->lin.beta, s->hp, rs->pool);
    rs->st->passes += 2;
    rs->st->bytes += mid_terms_bytes_direction(rs->w) + mid_terms_bytes_gather(rs->w);
    double php;
    vec_run(s, rs->pool, (vec_ctx){.stats = rs->st, .op = OP_MASK_DOT}, &php, NULL);
    return php;
}

/* z = M^-1 r with the chosen preconditioner, p = z (first step); sum r.z. */
static double precondition(mid_solver *s, run_state *rs, bool first)
{
    double rz;
    if (!rs->jacobi) {
        mid_precond_apply(rs->w, s->l0, s->l1, s->l2, s->r, s->z, rs->pool);
        rs->st->passes += 2;
        rs->st->bytes += mid_precond_bytes_apply(rs->w);
    }
    vec_run(s, rs->pool, (vec_ctx){.stats = rs->st, .op = first ? OP_ZP_INIT : OP_RZ, .jacobi = rs->jacobi}, &rz, NULL);
    return rz;
}

/* One Gauss-Newton iteration from f (linearised, cost c). Returns false when
 * no step lowers the cost (converged to float precision). On success f_try
 * holds the new point, linearised, and *c its cost. */
static bool gauss_newton_step(mid_solver *s, run_state *rs, const float *f, double *c, int cg_steps)
{
    gradient_and_diagonal(s, rs, f);
    double pg2;
    vec_run(s, rs->pool, (vec_ctx){.stats = rs->st, .op = OP_CG_START, .f = f, .lo = rs->lo, .hi = rs->hi}, NULL, &pg2);
    if (pg2 == 0.0)
        return false;
    if (!rs->jacobi) {
        mid_precond_factor(rs->w, rs->wt, &s->lin, s->free_mask, s->diag, s->l0, s->l1, s->l2, rs->pool);
        rs->st->passes += 2;
        rs->st->bytes += mid_precond_bytes_factor(rs->w);
    }
    double rz = precondition(s, rs, true);
    if (!(rz > 0.0))
        return false;
    /* Preconditioned CG on the free variables. */
    double rz0 = rz;
    for (int j = 0; j < cg_steps; j++) {
        double php = hessian_product(s, rs);
        rs->st->cg_steps++;
        if (!(php > 0.0))
            break;
        double rz_new;
        vec_run(s, rs->pool, (vec_ctx){.stats = rs->st, .op = OP_CG_UPDATE, .scalar = (float)(rz / php), .jacobi = rs->jacobi},
                &rz_new, NULL);
        if (!rs->jacobi)
            rz_new = precondition(s, rs, false);
        if (rz_new <= CG_TOLERANCE * rz0)
            break;
        vec_run(s, rs->pool, (vec_ctx){.stats = rs->st, .op = OP_P_UPDATE, .scalar = (float)(rz_new / rz)}, NULL, NULL);
        rz = rz_new;
    }
    /* Backtracking on the projected arc P(f + t s) with the Armijo test. */
    float t = 1.0f;
    for (int trial = 0; trial < LINE_MAX_TRIALS; trial++, t *= 0.5f) {
        double decrease;
        vec_run(s, rs->pool, (vec_ctx){.stats = rs->st, .op = OP_TRIAL, .f = f, .lo = rs->lo, .hi = rs->hi, .scalar = t},
                &decrease, NULL);
        double c_try = linearize(s, rs, s->f_try);
        rs->st->line_trials++;
        if (c_try < *c && c_try <= *c + LINE_ARMIJO * decrease) {
            *c = c_try;
            return true;
        }
    }
    return false;
}

/* The paper's step (Sec. 4.5) with the Jacobi scaling of DESIGN.md. */
static void descent_step(mid_solver *s, run_state *rs, const float *f, double *c, float lambda)
{
    gradient_and_diagonal(s, rs, f);
    vec_run(s, rs->pool, (vec_ctx){.stats = rs->st, .op = OP_DESCENT, .f = f, .lo = rs->lo, .hi = rs->hi, .scalar = lambda},
            NULL, NULL);
    *c = linearize(s, rs, s->f_try);
}

vg_status mid_solver_run(mid_solver *s, const mid_window *w, const mid_solve_desc *desc, float *f,
                         mid_solve_stats *stats)
{
    if (!w->built || s->n != w->n) {
        vg_error("MID solve: window not built or workspace size %d != %d", s->n, w->n);
        return VG_ERR_ARG;
    }
    double t0 = vg_now_ms();
    mid_solve_stats st = {0};
    mid_solver_kind kind = desc->solver == MID_SOLVER_DEFAULT ? MID_SOLVER_GAUSS_NEWTON : desc->solver;
    int iterations = desc->iterations > 0 ? desc->iterations
                     : kind == MID_SOLVER_DESCENT ? MID_DESCENT_ITERATIONS : MID_GN_ITERATIONS;
    int cg_steps = desc->cg_iterations > 0 ? desc->cg_iterations : MID_GN_CG_STEPS;
    float lambda = desc->step > 0 ? desc->step : MID_DESCENT_STEP;
    run_state rs = {.w = w, .wt = mid_weights_resolve(desc->weights), .pool = desc->pool, .st = &st,
                    .lo = w->range_lo, .hi = w->range_hi,
                    .jacobi = desc->precond == MID_PRECOND_JACOBI};

    /* f0 = h (Sec. 4.5) or the warm start, projected into the range. */
    const float *init = desc->f_init ? desc->f_init : w->h;
    for (int i = 0; i < w->n; i++)
        f[i] = clampf(init[i], rs.lo, rs.hi);
    double c = linearize(s, &rs, f);
    st.cost_initial = c;
    if (desc->cost_history)
        desc->cost_history[0] = c;
    float *cur = f;
    int it = 0;
    for (; it < iterations; it++) {
        if (kind == MID_SOLVER_DESCENT) {
            descent_step(s, &rs, cur, &c, lambda);
        } else if (!gauss_newton_step(s, &rs, cur, &c, cg_steps)) {
            break;
        }
        /* The accepted point is in f_try, already linearised: swap buffers. */
        float *next = s->f_try;
        s->f_try = cur;
        cur = next;
        if (desc->cost_history)
            desc->cost_history[it + 1] = c;
    }
    for (int j = it; desc->cost_history && j < iterations; j++)
        desc->cost_history[j + 1] = c; /* converged early: the cost stays */
    if (cur != f) {
        memcpy(f, cur, (size_t)w->n * sizeof(float));
        s->f_try = cur; /* hand the buffer back to the workspace */
    }
    st.iterations = it;
    st.cost_final = mid_terms_linearize(w, rs.wt, f, NULL, &st.terms, s->partial, rs.pool);
    st.ms = vg_now_ms() - t0;
    if (stats)
        *stats = st;
    return VG_OK;
}

vg_status mid_solve(const mid_window *w, const mid_solve_desc *desc, float *f,
                    mid_solve_stats *stats)
{
    mid_solver *s;
    vg_status st = mid_solver_create(w->n, &s);
    if (st == VG_OK)
        st = mid_solver_run(s, w, desc, f, stats);
    mid_solver_destroy(s);
    return st;
}

double mid_projected_gradient_norm(const mid_window *w, mid_weights wt, const float *f,
                                   vg_pool *pool)
{
    float *g = malloc((size_t)w->n * sizeof(float));
    if (!g || mid_gradient(w, wt, f, g, pool) != VG_OK) {
        free(g);
        return NAN;
    }
    /* In double: f - g cancels in float when |g| is below f's last digit. */
    double s = 0;
    for (int i = 0; i < w->n; i++) {
        double t = (double)f[i] - g[i];
        t = t < w->range_lo ? w->range_lo : (t > w->range_hi ? w->range_hi : t);
        s += (t - f[i]) * (t - f[i]);
    }
    free(g);
    return sqrt(s / w->n);
}
