/* vergence — the four costs of the MID optimiser and their derivatives as
 * gather passes (paper Sec. 4.1 and 4.3; derivation in docs/method.md).
 *
 *   c(f) = 1/n [ w_m sum_i (f-h)_i^2 + w_s sum_edges a_e^2 (D_e(f-h))^2
 *              + w_t sum_i r_t,i^2 + w_a sum_i r_a,i^2 ]
 *
 * Every derivative is two passes, both gathers:
 *   1. per pixel i, from f at i and at its link taps: residuals, slopes q,
 *      and the adjoint sources alpha_i = dc/d(A_f f - f)_i, beta_i = dc/d(f - A_b f)_i;
 *   2. per pixel j: local terms plus (A_f^T alpha)_j - alpha_j + beta_j - (A_b^T beta)_j,
 *      the transposes read through the CSR adjoints.
 * The same pass 2 gives the gradient (x = f - h, sources of pass 1) and the
 * Gauss-Newton product J^T W J p (x = p, sources of mid_terms_direction). */
#pragma once
#include "core/parallel.h"
#include "mid_window.h"

typedef struct mid_weights {
    float data, spatial, temporal, accel; /* all zero = the paper's (0.05, 1, 0.1, 0.1) */
} mid_weights;

/* Returns the weights with the all-zero default resolved. */
mid_weights mid_weights_resolve(mid_weights w);

/* Linearisation buffers (n floats each), written by mid_terms_linearize. */
typedef struct mid_lin {
    float *q_f, *q_b;       /* slopes of the velocity terms (0 on invalid links) */
    float *m_a;             /* 1 where both links are valid (c_a exists), else 0 */
    float *alpha, *beta;    /* adjoint sources (gradient, or a direction for H p) */
    float *c_f, *c_b;       /* diagonal contributions read through the adjoints */
    float *d_self;          /* diagonal contribution of pixel's own residuals */
} mid_lin;

vg_status mid_lin_alloc(mid_lin *lin, int n);
void mid_lin_free(mid_lin *lin);

/* Cost terms: [0] w_m c_m, [1] w_s c_s, [2] w_t c_t, [3] w_a c_a (each over n). */
typedef struct mid_cost_terms {
    double term[4];
    double total;
} mid_cost_terms;

/* Pass 1 at f: the cost, and (lin != NULL) the linearisation with gradient
 * sources. partial: scratch of 4 * vg_block_count(n, MID_BLOCK) doubles, or
 * NULL to allocate. Returns the total cost. */
double mid_terms_linearize(const mid_window *w, mid_weights wt, const float *f, mid_lin *lin,
                           mid_cost_terms *terms, double *partial, vg_pool *pool);

/* Pass 1 for a direction p: alpha/beta of J^T W J p (uses lin's slopes). */
void mid_terms_direction(const mid_window *w, mid_weights wt, const mid_lin *lin, const float *p,
                         float *alpha, float *beta, vg_pool *pool);

/* Pass 2: out_j = 2/n [w_m x_j + w_s sum_e a_e^2 (x_j - x_e)] + adjoint terms,
 * with x = a - b (b may be NULL). Gradient: (f, h, lin.alpha, lin.beta);
 * Hessian product: (p, NULL, alpha, beta of mid_terms_direction). */
void mid_terms_gather(const mid_window *w, mid_weights wt, const float *a, const float *b,
                      const float *alpha, const float *beta, float *out, vg_pool *pool);

/* Diagonal of the Gauss-Newton Hessian 2/n J^T W J (the Jacobi preconditioner). */
void mid_terms_diagonal(const mid_window *w, mid_weights wt, const mid_lin *lin, float *diag,
                        vg_pool *pool);

/* Convenience for tests and metrics: the cost, and the gradient at f. */
double mid_cost(const mid_window *w, mid_weights wt, const float *f, mid_cost_terms *terms,
                vg_pool *pool);
vg_status mid_gradient(const mid_window *w, mid_weights wt, const float *f, float *grad,
                       vg_pool *pool);

/* Bytes one pass moves at least (each array element read or written once),
 * for the bandwidth figures of the bench. */
double mid_terms_bytes_linearize(const mid_window *w);
double mid_terms_bytes_gather(const mid_window *w);
double mid_terms_bytes_direction(const mid_window *w);
