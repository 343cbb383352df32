#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve: the four costs and their derivatives as gathers, exactly as
// mid_terms.c (paper 4.1, 4.3; docs/method.md Sec. 5-6):
//   LIN_F / LIN_FTRY  pass 1 at f (or the trial point): residuals, slopes,
//                     adjoint sources and the cost terms (per element)
//   GATHER_GRAD       pass 2: the gradient at f
//   GATHER_HESS       pass 2 for a direction p: the Gauss-Newton product,
//                     masked to the free set, and the terms of p.Hp
//   DIAGONAL          the Gauss-Newton diagonal (the Jacobi preconditioner)
//   DIRECTION         pass 1 for a direction p
#include "mid_arena.glsl"
// The operation is a specialization constant: one pipeline per operation,
// no branch on it at run time.
layout(constant_id = 0) const uint OP = 0u;
MID_ELEMENT_LAYOUT;

float fin(uint i)
{
    return OP == MID_OP_LIN_F ? vf[i] : vftry[i];
}

float link_gather_fin(mid_link l)
{
    if (l.mask == 0u)
        return 0.0;
    return mid_link_apply(mid_link_taps(l), fin(l.base), fin(l.base + 1u), fin(l.base + pc.nx),
                          fin(l.base + pc.nx + 1u));
}

float link_gather_p(mid_link l)
{
    return l.mask == 0u ? 0.0 : LINK_GATHER(l, vp, 0u);
}

// x = f - h (gradient) or p (Hessian product).
float diff_at(uint i)
{
    return OP == MID_OP_GATHER_GRAD ? vf[i] - H(i) : vp[i];
}

void linearize(uint i)
{
    vec4 sums = vec4(0.0);
    {
        uint k = ek, px = ex, py = ey;
        float fi = fin(i), e = fi - H(i);
        sums.x = e * e;
        // c_s over the edges to the right and below, each counted once.
        if (px + 1u < pc.nx) {
            float d = (fin(i + 1u) - H(i + 1u)) - e;
            sums.y += EDGE_X(i) * d * d;
        }
        if (py + 1u < pc.ny) {
            float d = (fin(i + pc.nx) - H(i + pc.nx)) - e;
            sums.y += EDGE_Y(i) * d * d;
        }
        mid_link lf = link[i], lb = link[pc.cap + i];
        float m_f = lf.mask != 0u ? 1.0 : 0.0, m_b = lb.mask != 0u ? 1.0 : 0.0;
        mid_pixel r = mid_pixel_eval(fi, link_gather_fin(lf), link_gather_fin(lb), INVDT_F(k), INVDT_B(k),
                                     m_f, m_b, PH(i), PG(i));
        sums.z = r.r_t * r.r_t;
        sums.w = r.r_a * r.r_a;
        float scale = pc.grad_scale, m_a = m_f * m_b;
        Q_F(i) = r.q_f;
        Q_B(i) = r.q_b;
        M_A(i) = m_a;
        // dc/d(A_f f - f)_i and dc/d(f - A_b f)_i (r_a has -p(v-)).
        ALPHA(i) = scale * (pc.w_temporal * r.r_t + pc.w_accel * r.r_a) * r.q_f;
        BETA(i) = -scale * pc.w_accel * r.r_a * r.q_b;
        float qf2 = r.q_f * r.q_f, qb2 = r.q_b * r.q_b, qs = r.q_f + r.q_b;
        C_F(i) = scale * (pc.w_temporal * qf2 + pc.w_accel * m_a * qf2);
        C_B(i) = scale * pc.w_accel * m_a * qb2;
        D_SELF(i) = scale * (pc.w_temporal * qf2 + pc.w_accel * m_a * qs * qs);
    }
    // Unweighted terms: mid_control.comp applies the weights.
    DOT(0u, i) = sums.x;
    DOT(1u, i) = sums.y;
    DOT(2u, i) = sums.z;
    DOT(3u, i) = sums.w;
}

void gather(uint j)
{
    {
        uint px = ex, py = ey;
        float e = diff_at(j);
        // Weighted Laplacian of (f - h): the normal equations of c_s.
        float lap = 0.0;
        if (px + 1u < pc.nx)
            lap += EDGE_X(j) * (e - diff_at(j + 1u));
        if (px > 0u)
            lap += EDGE_X(j - 1u) * (e - diff_at(j - 1u));
        if (py + 1u < pc.ny)
            lap += EDGE_Y(j) * (e - diff_at(j + pc.nx));
        if (py > 0u)
            lap += EDGE_Y(j - pc.nx) * (e - diff_at(j - pc.nx));
        float local = pc.grad_scale * (pc.w_data * e + pc.w_spatial * lap);
        // d(A_f f - f)/df_j and d(f - A_b f)/df_j, transposed (CSR, source order).
        float af = 0.0, ab = 0.0;
        for (uint q = adj_off[j]; q < adj_off[j + 1u]; q++)
            af += adj[q].w * ALPHA(adj[q].src);
        uint ob = pc.cap + 1u;
        for (uint q = adj_off[ob + j]; q < adj_off[ob + j + 1u]; q++)
            ab += adj[pc.adj_cap + q].w * BETA(adj[pc.adj_cap + q].src);
        float out_j = local + (af - ALPHA(j)) + (BETA(j) - ab);
        if (OP == MID_OP_GATHER_GRAD) {
            vgrad[j] = out_j;
        } else {
            float hp = out_j * vfree[j];
            vhp[j] = hp;
            DOT(4u, j) = e * hp; // e is p_j here (diff_at): one load fewer
        }
    }
}

void diagonal(uint j)
{
    uint px = ex, py = ey;
    float edges = (px + 1u < pc.nx ? EDGE_X(j) : 0.0) + (px > 0u ? EDGE_X(j - 1u) : 0.0) +
                  (py + 1u < pc.ny ? EDGE_Y(j) : 0.0) + (py > 0u ? EDGE_Y(j - pc.nx) : 0.0);
    float d = pc.grad_scale * (pc.w_data + pc.w_spatial * edges) + D_SELF(j);
    for (uint q = adj_off[j]; q < adj_off[j + 1u]; q++) {
        mid_adj_entry e = adj[q];
        d += e.w * e.w * C_F(e.src);
    }
    uint ob = pc.cap + 1u;
    for (uint q = adj_off[ob + j]; q < adj_off[ob + j + 1u]; q++) {
        mid_adj_entry e = adj[pc.adj_cap + q];
        d += e.w * e.w * C_B(e.src);
    }
    vdiag[j] = d;
}

void direction(uint i)
{
    float pa = link_gather_p(link[i]), pb = link_gather_p(link[pc.cap + i]);
    float qf = Q_F(i), qb = Q_B(i), p = vp[i];
    // Linearised residuals J p; q_f, q_b are already 0 on invalid links.
    float dd_f = pa - p, dd_b = p - pb;
    float dr_t = qf * dd_f;
    float dr_a = M_A(i) * (qf * dd_f - qb * dd_b);
    ALPHA(i) = pc.grad_scale * (pc.w_temporal * dr_t + pc.w_accel * dr_a) * qf;
    BETA(i) = -pc.grad_scale * pc.w_accel * dr_a * qb;
}

void main()
{
    element_init();
    if (!inside)
        return;
    if (OP == MID_OP_LIN_F || OP == MID_OP_LIN_FTRY)
        linearize(ei);
    else if (OP == MID_OP_GATHER_GRAD || OP == MID_OP_GATHER_HESS)
        gather(ei);
    else if (OP == MID_OP_DIAGONAL)
        diagonal(ei);
    else if (OP == MID_OP_DIRECTION)
        direction(ei);
}
