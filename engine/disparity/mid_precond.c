#include "mid_precond.h"

#include <math.h>
#include <stdbool.h>

/* Chains per block of a CPU pass. */
#define CHAINS_PER_BLOCK 256

typedef struct pc_ctx {
    const mid_window *w;
    mid_weights wt;
    const mid_lin *lin;
    const float *free_mask, *diag, *r;
    float *l0, *l1, *l2, *z;
} pc_ctx;

/* Adds weight * c c^T for a residual with coefficients c at the chain nodes
 * prev, mid, next (-1 = absent). Band storage at each node: l0 = M[m][m],
 * l1 = M[m][m-1], l2 = M[m][m-2]. */
static void add_residual(float *l0, float *l1, float *l2, int prev, int mid, int next,
                         float c_prev, float c_mid, float c_next, float weight)
{
    l0[mid] += weight * c_mid * c_mid;
    if (prev >= 0) {
        l0[prev] += weight * c_prev * c_prev;
        l1[mid] += weight * c_prev * c_mid;
    }
    if (next >= 0) {
        l0[next] += weight * c_next * c_next;
        l1[next] += weight * c_mid * c_next;
    }
    if (prev >= 0 && next >= 0)
        l2[next] += weight * c_prev * c_next;
}

static void factor_block(void *c, int block, int begin, int end)
{
    (void)block;
    pc_ctx *x = c;
    const mid_window *w = x->w;
    const float scale = 2.0f / (float)w->n;
    float *l0 = x->l0, *l1 = x->l1, *l2 = x->l2;
    const float *m = x->free_mask;
    for (int ch = begin; ch < end; ch++) {
        int head = w->chain_head[ch];
        for (int i = head; i >= 0; i = w->chain_next[i]) {
            int p = i % w->ns, px = p % w->nx, py = p / w->nx;
            float edges = (px + 1 < w->nx ? w->edge_x[i] : 0.0f) + (px > 0 ? w->edge_x[i - 1] : 0.0f) +
                          (py + 1 < w->ny ? w->edge_y[i] : 0.0f) + (py > 0 ? w->edge_y[i - w->nx] : 0.0f);
            l0[i] = scale * (x->wt.data + x->wt.spatial * edges);
            l1[i] = l2[i] = 0.0f;
        }
        /* Residuals of c_t and c_a whose links follow the chain, with each
         * link put on its heaviest tap; the others reach M through the
         * Jacobi diagonal below. */
        for (int i = head; i >= 0; i = w->chain_next[i]) {
            int nxt = w->chain_next[i], prv = w->chain_prev[i];
            float qf = x->lin->q_f[i], qb = x->lin->q_b[i];
            float mn = nxt >= 0 ? m[nxt] : 0.0f, mp = prv >= 0 ? m[prv] : 0.0f;
            if (nxt < 0 || qf == 0.0f)
                continue;
            add_residual(l0, l1, l2, -1, i, nxt, 0.0f, -qf * m[i], qf * mn, scale * x->wt.temporal);
            if (prv >= 0 && x->lin->m_a[i] != 0.0f)
                add_residual(l0, l1, l2, prv, i, nxt, qb * mp, -(qf + qb) * m[i], qf * mn,
                             scale * x->wt.accel);
        }
        /* Held variables decouple (a principal submatrix); raising the
         * diagonal to the true Jacobi diagonal keeps M SPD. */
        for (int i = head; i >= 0; i = w->chain_next[i]) {
            if (m[i] == 0.0f) {
                l0[i] = 1.0f;
                l1[i] = l2[i] = 0.0f;
            } else if (x->diag[i] > l0[i]) {
                l0[i] = x->diag[i];
            }
        }
        /* In-place banded Cholesky along the chain. */
        for (int i = head; i >= 0; i = w->chain_next[i]) {
            int p1 = w->chain_prev[i], p2 = p1 >= 0 ? w->chain_prev[p1] : -1;
            float a2 = p2 >= 0 ? l2[i] / l0[p2] : 0.0f;
            float a1 = p1 >= 0 ? (l1[i] - a2 * l1[p1]) / l0[p1] : 0.0f;
            float d = l0[i] - a1 * a1 - a2 * a2;
            l0[i] = sqrtf(d > 1e-30f ? d : 1e-30f);
            l1[i] = a1;
            l2[i] = a2;
        }
    }
}

void mid_precond_factor(const mid_window *w, mid_weights wt, const mid_lin *lin,
                        const float *free_mask, const float *diag, float *l0, float *l1, float *l2,
                        vg_pool *pool)
{
    pc_ctx c = {.w = w, .wt = wt, .lin = lin, .free_mask = free_mask, .diag = diag,
                .l0 = l0, .l1 = l1, .l2 = l2};
    vg_parallel_for(pool, w->chain_count, CHAINS_PER_BLOCK, factor_block, &c);
}

static void apply_block(void *c, int block, int begin, int end)
{
    (void)block;
    pc_ctx *x = c;
    const mid_window *w = x->w;
    const float *l0 = x->l0, *l1 = x->l1, *l2 = x->l2;
    for (int ch = begin; ch < end; ch++) {
        /* L y = r along the chain (z holds y), then L^T z = y walking back. */
        int tail = -1;
        for (int i = w->chain_head[ch]; i >= 0; i = w->chain_next[i]) {
            int p1 = w->chain_prev[i], p2 = p1 >= 0 ? w->chain_prev[p1] : -1;
            float v = x->r[i];
            if (p1 >= 0)
                v -= l1[i] * x->z[p1];
            if (p2 >= 0)
                v -= l2[i] * x->z[p2];
            x->z[i] = v / l0[i];
            tail = i;
        }
        for (int i = tail; i >= 0; i = w->chain_prev[i]) {
            int n1 = w->chain_next[i], n2 = n1 >= 0 ? w->chain_next[n1] : -1;
            float v = x->z[i];
            if (n1 >= 0)
                v -= l1[n1] * x->z[n1];
            if (n2 >= 0)
                v -= l2[n2] * x->z[n2];
            x->z[i] = v / l0[i];
        }
    }
}

void mid_precond_apply(const mid_window *w, const float *l0, const float *l1, const float *l2,
                       const float *r, float *z, vg_pool *pool)
{
    pc_ctx c = {.w = w, .l0 = (float *)l0, .l1 = (float *)l1, .l2 = (float *)l2, .r = r, .z = z};
    vg_parallel_for(pool, w->chain_count, CHAINS_PER_BLOCK, apply_block, &c);
}
