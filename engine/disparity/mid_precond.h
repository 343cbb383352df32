/* vergence — the temporal line preconditioner of the Gauss-Newton solve.
 *
 * The stiff part of the MID Hessian is each pixel's chain through time: on a
 * static pixel p'(0)/dt is about 75 per arcmin, so c_t and c_a couple
 * consecutive keyframes thousands of times more strongly than c_m holds
 * them, and plain Jacobi scaling leaves CG a condition number of ~1e5.
 * and, on a moving object, its trajectory: CG alone moves information one
 * keyframe per step along the flow. M is the Gauss-Newton matrix of the
 * same residuals along the window's flow chains (mid_window: each link put
 * on its heaviest tap, exact for static pixels), plus the data and spatial
 * diagonal, restricted to the free variables and raised to at least the true
 * Jacobi diagonal: a pentadiagonal SPD matrix per chain, factored by banded
 * Cholesky. Chains step from keyframe k to k+1, so factor and substitutions
 * are sweeps over keyframes, each step a gather over one keyframe's nodes.
 * Equations: docs/method.md "Solver". */
#pragma once
#include "core/parallel.h"
#include "mid_terms.h"
#include "mid_window.h"

/* Factors M at the current linearisation into l0 (diagonal of L), l1 and l2
 * (L[m][m-1], L[m][m-2] for the chain positions m), n floats each, stored at
 * each node's index; diag is the Jacobi diagonal. */
void mid_precond_factor(const mid_window *w, mid_weights wt, const mid_lin *lin,
                        const float *free_mask, const float *diag, float *l0, float *l1, float *l2,
                        vg_pool *pool);
/* z = M^-1 r. */
void mid_precond_apply(const mid_window *w, const float *l0, const float *l1, const float *l2,
                       const float *r, float *z, vg_pool *pool);

/* Compulsory traffic of a factorisation and of an application (bench). */
double mid_precond_bytes_factor(const mid_window *w);
double mid_precond_bytes_apply(const mid_window *w);
