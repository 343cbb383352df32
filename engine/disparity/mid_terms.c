#include "mid_terms.h"

#include <stdlib.h>
#include <string.h>

mid_weights mid_weights_resolve(mid_weights w)
{
    if (w.data == 0 && w.spatial == 0 && w.temporal == 0 && w.accel == 0)
        return (mid_weights){MID_W_DATA, MID_W_SPATIAL, MID_W_TEMPORAL, MID_W_ACCEL};
    return w;
}

vg_status mid_lin_alloc(mid_lin *lin, int n)
{
    *lin = (mid_lin){0};
    float **fields[] = {&lin->q_f, &lin->q_b, &lin->m_a, &lin->alpha,
                        &lin->beta, &lin->c_f, &lin->c_b, &lin->d_self};
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++)
        if (!(*fields[i] = calloc((size_t)n, sizeof(float)))) {
            mid_lin_free(lin);
            return VG_ERR_NOMEM;
        }
    return VG_OK;
}

void mid_lin_free(mid_lin *lin)
{
    if (!lin)
        return;
    free(lin->q_f);
    free(lin->q_b);
    free(lin->m_a);
    free(lin->alpha);
    free(lin->beta);
    free(lin->c_f);
    free(lin->c_b);
    free(lin->d_self);
    *lin = (mid_lin){0};
}

/* Grid position of an element, advanced incrementally (no divisions in the loops). */
typedef struct cursor {
    int k, x, y;
} cursor;

static inline cursor cursor_at(const mid_window *w, int i)
{
    int p = i % w->ns;
    return (cursor){i / w->ns, p % w->nx, p / w->nx};
}

static inline void cursor_next(const mid_window *w, cursor *c)
{
    if (++c->x == w->nx) {
        c->x = 0;
        if (++c->y == w->ny) {
            c->y = 0;
            c->k++;
        }
    }
}

/* ------------------------------------------------------------------------- */
/* Pass 1: residuals, slopes, adjoint sources, cost                          */
/* ------------------------------------------------------------------------- */

typedef struct lin_ctx {
    const mid_window *w;
    mid_weights wt;
    const float *f;
    mid_lin *lin;
    double *partial; /* 4 per block */
} lin_ctx;

static void linearize_block(void *c, int block, int begin, int end)
{
    lin_ctx *x = c;
    const mid_window *w = x->w;
    const float *f = x->f, *h = w->h;
    const float scale = 2.0f / (float)w->n;
    double sm = 0, ss = 0, st = 0, sa = 0;
    cursor cur = cursor_at(w, begin);
    for (int i = begin; i < end; i++, cursor_next(w, &cur)) {
        int k = cur.k, px = cur.x, py = cur.y;
        float e = f[i] - h[i];
        sm += (double)e * e;
        /* c_s over the edges to the right and below, each counted once. */
        if (px + 1 < w->nx) {
            float d = (f[i + 1] - h[i + 1]) - e;
            ss += (double)w->edge_x[i] * d * d;
        }
        if (py + 1 < w->ny) {
            float d = (f[i + w->nx] - h[i + w->nx]) - e;
            ss += (double)w->edge_y[i] * d * d;
        }
        float m_f = w->fwd[i].mask ? 1.0f : 0.0f, m_b = w->bwd[i].mask ? 1.0f : 0.0f;
        float fa = mid_link_gather(w->fwd, w->nx, i, f);
        float fb = mid_link_gather(w->bwd, w->nx, i, f);
        mid_pixel r = mid_pixel_eval(f[i], fa, fb, w->inv_dt_f[k], w->inv_dt_b[k], m_f, m_b,
                                     w->ph[i], w->pg_acc[i]);
        st += (double)r.r_t * r.r_t;
        sa += (double)r.r_a * r.r_a;
        mid_lin *lin = x->lin;
        if (lin) {
            float m_a = m_f * m_b;
            lin->q_f[i] = r.q_f;
            lin->q_b[i] = r.q_b;
            lin->m_a[i] = m_a;
            /* dc/d(A_f f - f)_i and dc/d(f - A_b f)_i (r_a has -p(v-)). */
            lin->alpha[i] = scale * (x->wt.temporal * r.r_t + x->wt.accel * r.r_a) * r.q_f;
            lin->beta[i] = -scale * x->wt.accel * r.r_a * r.q_b;
            float qf2 = r.q_f * r.q_f, qb2 = r.q_b * r.q_b, qs = r.q_f + r.q_b;
            lin->c_f[i] = scale * (x->wt.temporal * qf2 + x->wt.accel * m_a * qf2);
            lin->c_b[i] = scale * x->wt.accel * m_a * qb2;
            lin->d_self[i] = scale * (x->wt.temporal * qf2 + x->wt.accel * m_a * qs * qs);
        }
    }
    double *out = x->partial + 4 * block;
    out[0] = x->wt.data * sm;
    out[1] = x->wt.spatial * ss;
    out[2] = x->wt.temporal * st;
    out[3] = x->wt.accel * sa;
}

double mid_terms_linearize(const mid_window *w, mid_weights wt, const float *f, mid_lin *lin,
                           mid_cost_terms *terms, double *partial, vg_pool *pool)
{
    int blocks = vg_block_count(w->n, MID_BLOCK);
    double *own = NULL;
    if (!partial) {
        own = malloc((size_t)blocks * 4 * sizeof(double));
        if (!own)
            return NAN;
        partial = own;
    }
    lin_ctx c = {.w = w, .wt = wt, .f = f, .lin = lin, .partial = partial};
    vg_parallel_for(pool, w->n, MID_BLOCK, linearize_block, &c);
    mid_cost_terms t = {0};
    /* Fixed-order reduction: block partials added in block order. */
    for (int b = 0; b < blocks; b++)
        for (int j = 0; j < 4; j++)
            t.term[j] += partial[4 * b + j];
    for (int j = 0; j < 4; j++) {
        t.term[j] /= (double)w->n;
        t.total += t.term[j];
    }
    if (terms)
        *terms = t;
    free(own);
    return t.total;
}

/* ------------------------------------------------------------------------- */
/* Pass 1 for a direction p (Gauss-Newton product)                           */
/* ------------------------------------------------------------------------- */

typedef struct dir_ctx {
    const mid_window *w;
    mid_weights wt;
    const mid_lin *lin;
    const float *p;
    float *alpha, *beta;
} dir_ctx;

static void direction_block(void *c, int block, int begin, int end)
{
    (void)block;
    dir_ctx *x = c;
    const mid_window *w = x->w;
    const float scale = 2.0f / (float)w->n;
    for (int i = begin; i < end; i++) {
        float pa = mid_link_gather(w->fwd, w->nx, i, x->p);
        float pb = mid_link_gather(w->bwd, w->nx, i, x->p);
        float qf = x->lin->q_f[i], qb = x->lin->q_b[i];
        /* Linearised residuals J p; q_f, q_b are already 0 on invalid links. */
        float dd_f = pa - x->p[i], dd_b = x->p[i] - pb;
        float dr_t = qf * dd_f;
        float dr_a = x->lin->m_a[i] * (qf * dd_f - qb * dd_b);
        x->alpha[i] = scale * (x->wt.temporal * dr_t + x->wt.accel * dr_a) * qf;
        x->beta[i] = -scale * x->wt.accel * dr_a * qb;
    }
}

void mid_terms_direction(const mid_window *w, mid_weights wt, const mid_lin *lin, const float *p,
                         float *alpha, float *beta, vg_pool *pool)
{
    dir_ctx c = {.w = w, .wt = wt, .lin = lin, .p = p, .alpha = alpha, .beta = beta};
    vg_parallel_for(pool, w->n, MID_BLOCK, direction_block, &c);
}

/* ------------------------------------------------------------------------- */
/* Pass 2: local terms plus adjoint gathers                                  */
/* ------------------------------------------------------------------------- */

typedef struct gather_ctx {
    const mid_window *w;
    mid_weights wt;
    const float *a, *b, *alpha, *beta;
    float *out;
} gather_ctx;

static inline float diff_at(const gather_ctx *x, int i)
{
    return x->b ? x->a[i] - x->b[i] : x->a[i];
}

static void gather_block(void *c, int block, int begin, int end)
{
    (void)block;
    gather_ctx *x = c;
    const mid_window *w = x->w;
    const float scale = 2.0f / (float)w->n;
    cursor cur = cursor_at(w, begin);
    for (int j = begin; j < end; j++, cursor_next(w, &cur)) {
        int px = cur.x, py = cur.y;
        float e = diff_at(x, j);
        /* Weighted Laplacian of (f - h): the normal equations of c_s, i.e. the
         * paper's A_n (4 on the diagonal, -1 per neighbour) with edge weights. */
        float lap = 0.0f;
        if (px + 1 < w->nx)
            lap += w->edge_x[j] * (e - diff_at(x, j + 1));
        if (px > 0)
            lap += w->edge_x[j - 1] * (e - diff_at(x, j - 1));
        if (py + 1 < w->ny)
            lap += w->edge_y[j] * (e - diff_at(x, j + w->nx));
        if (py > 0)
            lap += w->edge_y[j - w->nx] * (e - diff_at(x, j - w->nx));
        float local = scale * (x->wt.data * e + x->wt.spatial * lap);
        /* d(A_f f - f)/df_j and d(f - A_b f)/df_j, transposed. */
        float af = 0.0f, ab = 0.0f;
        for (uint32_t q = w->fwd_adj.offset[j]; q < w->fwd_adj.offset[j + 1]; q++)
            af += w->fwd_adj.entry[q].w * x->alpha[w->fwd_adj.entry[q].src];
        for (uint32_t q = w->bwd_adj.offset[j]; q < w->bwd_adj.offset[j + 1]; q++)
            ab += w->bwd_adj.entry[q].w * x->beta[w->bwd_adj.entry[q].src];
        x->out[j] = local + (af - x->alpha[j]) + (x->beta[j] - ab);
    }
}

void mid_terms_gather(const mid_window *w, mid_weights wt, const float *a, const float *b,
                      const float *alpha, const float *beta, float *out, vg_pool *pool)
{
    gather_ctx c = {.w = w, .wt = wt, .a = a, .b = b, .alpha = alpha, .beta = beta, .out = out};
    vg_parallel_for(pool, w->n, MID_BLOCK, gather_block, &c);
}

/* ------------------------------------------------------------------------- */
/* Diagonal of the Gauss-Newton Hessian                                      */
/* ------------------------------------------------------------------------- */

typedef struct diag_ctx {
    const mid_window *w;
    mid_weights wt;
    const mid_lin *lin;
    float *diag;
} diag_ctx;

static void diagonal_block(void *c, int block, int begin, int end)
{
    (void)block;
    diag_ctx *x = c;
    const mid_window *w = x->w;
    const float scale = 2.0f / (float)w->n;
    cursor cur = cursor_at(w, begin);
    for (int j = begin; j < end; j++, cursor_next(w, &cur)) {
        int px = cur.x, py = cur.y;
        float edges = (px + 1 < w->nx ? w->edge_x[j] : 0.0f) + (px > 0 ? w->edge_x[j - 1] : 0.0f) +
                      (py + 1 < w->ny ? w->edge_y[j] : 0.0f) +
                      (py > 0 ? w->edge_y[j - w->nx] : 0.0f);
        float d = scale * (x->wt.data + x->wt.spatial * edges) + x->lin->d_self[j];
        for (uint32_t q = w->fwd_adj.offset[j]; q < w->fwd_adj.offset[j + 1]; q++) {
            mid_adj_entry e = w->fwd_adj.entry[q];
            d += e.w * e.w * x->lin->c_f[e.src];
        }
        for (uint32_t q = w->bwd_adj.offset[j]; q < w->bwd_adj.offset[j + 1]; q++) {
            mid_adj_entry e = w->bwd_adj.entry[q];
            d += e.w * e.w * x->lin->c_b[e.src];
        }
        x->diag[j] = d;
    }
}

void mid_terms_diagonal(const mid_window *w, mid_weights wt, const mid_lin *lin, float *diag,
                        vg_pool *pool)
{
    diag_ctx c = {.w = w, .wt = wt, .lin = lin, .diag = diag};
    vg_parallel_for(pool, w->n, MID_BLOCK, diagonal_block, &c);
}

/* ------------------------------------------------------------------------- */
/* Conveniences                                                              */
/* ------------------------------------------------------------------------- */

double mid_cost(const mid_window *w, mid_weights wt, const float *f, mid_cost_terms *terms,
                vg_pool *pool)
{
    return mid_terms_linearize(w, mid_weights_resolve(wt), f, NULL, terms, NULL, pool);
}

vg_status mid_gradient(const mid_window *w, mid_weights wt, const float *f, float *grad,
                       vg_pool *pool)
{
    mid_lin lin;
    vg_status st = mid_lin_alloc(&lin, w->n);
    if (st != VG_OK)
        return st;
    wt = mid_weights_resolve(wt);
    mid_terms_linearize(w, wt, f, &lin, NULL, NULL, pool);
    mid_terms_gather(w, wt, f, w->h, lin.alpha, lin.beta, grad, pool);
    mid_lin_free(&lin);
    return VG_OK;
}

/* Compulsory traffic per pass: arrays read or written once per element,
 * the link taps and adjoint entries counted at their actual sizes. */
double mid_terms_bytes_linearize(const mid_window *w)
{
    /* reads f, h, edge_x, edge_y, ph, pg_acc, fwd, bwd; writes 8 floats */
    return (double)w->n * (4.0 * 6 + 2.0 * sizeof(mid_link) + 4.0 * 8);
}

double mid_terms_bytes_gather(const mid_window *w)
{
    /* reads a, b, edge_x, edge_y, alpha, beta, 2 offsets, entries; writes out */
    return (double)w->n * (4.0 * 6 + 2.0 * 4 + 4.0) +
           (double)(w->fwd_adj.count + w->bwd_adj.count) * sizeof(mid_adj_entry);
}

double mid_terms_bytes_direction(const mid_window *w)
{
    /* reads p, q_f, q_b, m_a, fwd, bwd; writes alpha, beta */
    return (double)w->n * (4.0 * 4 + 2.0 * sizeof(mid_link) + 4.0 * 2);
}
