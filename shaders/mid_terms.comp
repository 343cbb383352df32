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

// Every array these kernels read is written by an earlier dispatch: all
// reads go through the texel views (mid_arena.glsl R_*).
float fin(uint i)
{
    return OP == MID_OP_LIN_F ? R_F(i) : R_FTRY(i);
}

float link_gather_fin(mid_link l)
{
    return l.mask == 0u ? 0.0 : R_LINK_GATHER(l, fin);
}

float link_gather_p(mid_link l)
{
    return l.mask == 0u ? 0.0 : R_LINK_GATHER(l, R_P);
}

// x = f - h (gradient) or p (Hessian product).
float diff_at(uint i)
{
    return OP == MID_OP_GATHER_GRAD ? R_F(i) - R_H(i) : R_P(i);
}

void linearize(uint i)
{
    vec4 sums = vec4(0.0);
    {
        uint k = ek, px = ex, py = ey;
        float fi = fin(i), e = fi - R_H(i);
        sums.x = e * e;
        // c_s over the edges to the right and below, each counted once.
        if (px + 1u < pc.nx) {
            float d = (fin(i + 1u) - R_H(i + 1u)) - e;
            sums.y += R_EDGE_X(i) * d * d;
        }
        if (py + 1u < pc.ny) {
            float d = (fin(i + pc.nx) - R_H(i + pc.nx)) - e;
            sums.y += R_EDGE_Y(i) * d * d;
        }
        mid_link lf = r_link(i), lb = r_link(pc.cap + i);
        float m_f = lf.mask != 0u ? 1.0 : 0.0, m_b = lb.mask != 0u ? 1.0 : 0.0;
        mid_pixel r = mid_pixel_eval(fi, link_gather_fin(lf), link_gather_fin(lb), INVDT_F(k), INVDT_B(k),
                                     m_f, m_b, R_PH(i), R_PG(i));
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
            lap += R_EDGE_X(j) * (e - diff_at(j + 1u));
        if (px > 0u)
            lap += R_EDGE_X(j - 1u) * (e - diff_at(j - 1u));
        if (py + 1u < pc.ny)
            lap += R_EDGE_Y(j) * (e - diff_at(j + pc.nx));
        if (py > 0u)
            lap += R_EDGE_Y(j - pc.nx) * (e - diff_at(j - pc.nx));
        float local = pc.grad_scale * (pc.w_data * e + pc.w_spatial * lap);
        // d(A_f f - f)/df_j and d(f - A_b f)/df_j, transposed (CSR, source order).
        float af = 0.0, ab = 0.0;
        for (uint q = R_ADJ_OFF(0u, j); q < R_ADJ_OFF(0u, j + 1u); q++)
            af += R_ADJ_W(0u, q) * R_ALPHA(R_ADJ_SRC(0u, q));
        for (uint q = R_ADJ_OFF(1u, j); q < R_ADJ_OFF(1u, j + 1u); q++)
            ab += R_ADJ_W(1u, q) * R_BETA(R_ADJ_SRC(1u, q));
        float out_j = local + (af - R_ALPHA(j)) + (R_BETA(j) - ab);
        if (OP == MID_OP_GATHER_GRAD) {
            vgrad[j] = out_j;
        } else {
            float hp = out_j * R_FREE(j);
            vhp[j] = hp;
            DOT(4u, j) = e * hp; // e is p_j here (diff_at): one load fewer
        }
    }
}

void diagonal(uint j)
{
    uint px = ex, py = ey;
    float edges = (px + 1u < pc.nx ? R_EDGE_X(j) : 0.0) + (px > 0u ? R_EDGE_X(j - 1u) : 0.0) +
                  (py + 1u < pc.ny ? R_EDGE_Y(j) : 0.0) + (py > 0u ? R_EDGE_Y(j - pc.nx) : 0.0);
    float d = pc.grad_scale * (pc.w_data + pc.w_spatial * edges) + R_D_SELF(j);
    for (uint q = R_ADJ_OFF(0u, j); q < R_ADJ_OFF(0u, j + 1u); q++) {
        float w = R_ADJ_W(0u, q);
        d += w * w * R_C_F(R_ADJ_SRC(0u, q));
    }
    for (uint q = R_ADJ_OFF(1u, j); q < R_ADJ_OFF(1u, j + 1u); q++) {
        float w = R_ADJ_W(1u, q);
        d += w * w * R_C_B(R_ADJ_SRC(1u, q));
    }
    vdiag[j] = d;
}

void direction(uint i)
{
    float pa = link_gather_p(r_link(i)), pb = link_gather_p(r_link(pc.cap + i));
    float qf = R_Q_F(i), qb = R_Q_B(i), p = R_P(i);
    // Linearised residuals J p; q_f, q_b are already 0 on invalid links.
    float dd_f = pa - p, dd_b = p - pb;
    float dr_t = qf * dd_f;
    float dr_a = R_M_A(i) * (qf * dd_f - qb * dd_b);
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
