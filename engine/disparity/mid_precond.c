#include "mid_precond.h"

#include <math.h>
#include <stdbool.h>

/* Chain links always go from keyframe k to k+1, so the banded Cholesky along
 * every chain is a sweep over keyframes: a node needs only its chain
 * predecessors (forward) or successors (backward). On the CPU each group of
 * MID_CHAIN_GROUP chains sweeps its own node list (mid_window: keyframe by
 * keyframe), one parallel call per sweep; a GPU can equally run one dispatch
 * per keyframe over that keyframe's nodes. Assembly is one gather over all
 * nodes. */

typedef struct pc_ctx {
    const mid_window *w;
    mid_weights wt;
    const mid_lin *lin;
    const float *free_mask, *diag, *r;
    float *l0, *l1, *l2, *z;
} pc_ctx;

/* Coefficients of the residuals of node i along its chain (0 where a
 * residual does not follow the chain): r_t couples (i, next) with
 * (-q_f, +q_f); r_a couples (prev, i, next) with (q_b, -(q_f + q_b), q_f).
 * Each link is put on its heaviest tap; held variables get coefficient 0. */
typedef struct chain_res {
    float t_mid, t_next;             /* r_t */
    float a_prev, a_mid, a_next;     /* r_a */
} chain_res;

static chain_res residuals_of(const pc_ctx *x, int i)
{
    const mid_window *w = x->w;
    chain_res c = {0};
    int nxt = w->chain_next[i], prv = w->chain_prev[i];
    float qf = x->lin->q_f[i], qb = x->lin->q_b[i];
    if (nxt < 0 || qf == 0.0f)
        return c;
    const float *m = x->free_mask;
    c.t_mid = -qf * m[i];
    c.t_next = qf * m[nxt];
    if (prv >= 0 && x->lin->m_a[i] != 0.0f) {
        c.a_prev = qb * m[prv];
        c.a_mid = -(qf + qb) * m[i];
        c.a_next = qf * m[nxt];
    }
    return c;
}

/* Band of M at node i: l0 = M[i][i], l1 = M[i][prev], l2 = M[i][prev of prev]. */
static void assemble_block(void *c, int block, int begin, int end)
{
    (void)block;
    pc_ctx *x = c;
    const mid_window *w = x->w;
    const float scale = 2.0f / (float)w->n, wt_t = scale * x->wt.temporal, wt_a = scale * x->wt.accel;
    for (int i = begin; i < end; i++) {
        if (x->free_mask[i] == 0.0f) {
            x->l0[i] = 1.0f; /* held: decoupled (a principal submatrix) */
            x->l1[i] = x->l2[i] = 0.0f;
            continue;
        }
        int p = i % w->ns, px = p % w->nx, py = p / w->nx;
        float edges = (px + 1 < w->nx ? w->edge_x[i] : 0.0f) + (px > 0 ? w->edge_x[i - 1] : 0.0f) +
                      (py + 1 < w->ny ? w->edge_y[i] : 0.0f) + (py > 0 ? w->edge_y[i - w->nx] : 0.0f);
        chain_res self = residuals_of(x, i);
        float d = scale * (x->wt.data + x->wt.spatial * edges) + wt_t * self.t_mid * self.t_mid +
                  wt_a * self.a_mid * self.a_mid;
        float e1 = 0.0f, e2 = 0.0f;
        int prv = w->chain_prev[i], nxt = w->chain_next[i];
        if (prv >= 0) {
            chain_res pr = residuals_of(x, prv);
            d += wt_t * pr.t_next * pr.t_next + wt_a * pr.a_next * pr.a_next;
            e1 = wt_t * pr.t_mid * pr.t_next + wt_a * pr.a_mid * pr.a_next + wt_a * self.a_prev * self.a_mid;
            e2 = wt_a * pr.a_prev * pr.a_next;
        }
        if (nxt >= 0) {
            chain_res nr = residuals_of(x, nxt);
            d += wt_a * nr.a_prev * nr.a_prev;
        }
        /* Raising the diagonal to the true Jacobi diagonal keeps M SPD and
         * covers the residuals that do not follow the chain. */
        x->l0[i] = x->diag[i] > d ? x->diag[i] : d;
        x->l1[i] = e1;
        x->l2[i] = e2;
    }
}

/* Cholesky along the chains of a group, node by node in keyframe order. */
static void factor_group(void *c, int block, int begin, int end)
{
    (void)block;
    pc_ctx *x = c;
    const mid_window *w = x->w;
    float *l0 = x->l0, *l1 = x->l1, *l2 = x->l2;
    for (int o = w->chain_group[begin]; o < w->chain_group[end]; o++) {
        int i = w->chain_order[o];
        int p1 = w->chain_prev[i], p2 = p1 >= 0 ? w->chain_prev[p1] : -1;
        float a2 = p2 >= 0 ? l2[i] / l0[p2] : 0.0f;
        float a1 = p1 >= 0 ? (l1[i] - a2 * l1[p1]) / l0[p1] : 0.0f;
        float d = l0[i] - a1 * a1 - a2 * a2;
        l0[i] = sqrtf(d > 1e-30f ? d : 1e-30f);
        l1[i] = a1;
        l2[i] = a2;
    }
}

void mid_precond_factor(const mid_window *w, mid_weights wt, const mid_lin *lin,
                        const float *free_mask, const float *diag, float *l0, float *l1, float *l2,
                        vg_pool *pool)
{
    pc_ctx c = {.w = w, .wt = wt, .lin = lin, .free_mask = free_mask, .diag = diag,
                .l0 = l0, .l1 = l1, .l2 = l2};
    vg_parallel_for(pool, w->n, MID_BLOCK, assemble_block, &c);
    vg_parallel_for(pool, w->chain_groups, 1, factor_group, &c);
}

/* L y = r, then L^T z = y (z holds y in between), along a group's chains. */
static void solve_group(void *c, int block, int begin, int end)
{
    (void)block;
    pc_ctx *x = c;
    const mid_window *w = x->w;
    int first = w->chain_group[begin], last = w->chain_group[end];
    for (int o = first; o < last; o++) {
        int i = w->chain_order[o];
        int p1 = w->chain_prev[i], p2 = p1 >= 0 ? w->chain_prev[p1] : -1;
        float v = x->r[i];
        if (p1 >= 0)
            v -= x->l1[i] * x->z[p1];
        if (p2 >= 0)
            v -= x->l2[i] * x->z[p2];
        x->z[i] = v / x->l0[i];
    }
    for (int o = last - 1; o >= first; o--) {
        int i = w->chain_order[o];
        int n1 = w->chain_next[i], n2 = n1 >= 0 ? w->chain_next[n1] : -1;
        float v = x->z[i];
        if (n1 >= 0)
            v -= x->l1[n1] * x->z[n1];
        if (n2 >= 0)
            v -= x->l2[n2] * x->z[n2];
        x->z[i] = v / x->l0[i];
    }
}

void mid_precond_apply(const mid_window *w, const float *l0, const float *l1, const float *l2,
                       const float *r, float *z, vg_pool *pool)
{
    pc_ctx c = {.w = w, .l0 = (float *)l0, .l1 = (float *)l1, .l2 = (float *)l2, .r = r, .z = z};
    vg_parallel_for(pool, w->chain_groups, 1, solve_group, &c);
}

/* Assembly reads q_f, q_b, m_a, the free mask, diag, two edge arrays and the
 * chain links and writes the band; the factor sweep reads and rewrites it. */
double mid_precond_bytes_factor(const mid_window *w)
{
    return (double)w->n * (4.0 * 7 + 8.0 + 4.0 * 3 + 4.0 + 4.0 * 6);
}

/* Forward and backward sweeps: r or z, the band, a chain link, z. */
double mid_precond_bytes_apply(const mid_window *w)
{
    return (double)w->n * 2.0 * (4.0 * 5 + 4.0 + 4.0);
}
