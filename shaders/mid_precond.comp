#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve: the temporal line preconditioner of mid_precond.c. ASSEMBLE is
// a gather over all nodes; FACTOR (banded Cholesky) and APPLY (the two
// substitutions) walk each flow chain from its head, one invocation per
// chain (dispatched over the heads' list): the same operations in the same
// order as the CPU's sweeps.
#include "mid_arena.glsl"
// The operation is a specialization constant: one pipeline per operation,
// no branch on it at run time.
layout(constant_id = 0) const uint OP = 0u;
MID_ELEMENT_LAYOUT;

struct chain_res {
    float t_mid, t_next, a_prev, a_mid, a_next;
};

// Coefficients of node i's residuals along its chain (mid_precond.c).
chain_res residuals_of(uint i)
{
    chain_res c = chain_res(0.0, 0.0, 0.0, 0.0, 0.0);
    int nxt = CHAIN_NEXT(i), prv = CHAIN_PREV(i);
    float qf = Q_F(i), qb = Q_B(i);
    if (nxt < 0 || qf == 0.0)
        return c;
    c.t_mid = -qf * vfree[i];
    c.t_next = qf * vfree[uint(nxt)];
    if (prv >= 0 && M_A(i) != 0.0) {
        c.a_prev = qb * vfree[uint(prv)];
        c.a_mid = -(qf + qb) * vfree[i];
        c.a_next = qf * vfree[uint(nxt)];
    }
    return c;
}

void assemble(uint i)
{
    if (vfree[i] == 0.0) {
        L0(i) = 1.0; // held: decoupled (a principal submatrix)
        L1(i) = 0.0;
        L2(i) = 0.0;
        return;
    }
    float scale = pc.grad_scale, wt_t = scale * pc.w_temporal, wt_a = scale * pc.w_accel;
    uint px = ex, py = ey;
    float edges = (px + 1u < pc.nx ? EDGE_X(i) : 0.0) + (px > 0u ? EDGE_X(i - 1u) : 0.0) +
                  (py + 1u < pc.ny ? EDGE_Y(i) : 0.0) + (py > 0u ? EDGE_Y(i - pc.nx) : 0.0);
    chain_res self = residuals_of(i);
    float d = scale * (pc.w_data + pc.w_spatial * edges) + wt_t * self.t_mid * self.t_mid +
              wt_a * self.a_mid * self.a_mid;
    float e1 = 0.0, e2 = 0.0;
    int prv = CHAIN_PREV(i), nxt = CHAIN_NEXT(i);
    if (prv >= 0) {
        chain_res pr = residuals_of(uint(prv));
        d += wt_t * pr.t_next * pr.t_next + wt_a * pr.a_next * pr.a_next;
        e1 = wt_t * pr.t_mid * pr.t_next + wt_a * pr.a_mid * pr.a_next + wt_a * self.a_prev * self.a_mid;
        e2 = wt_a * pr.a_prev * pr.a_next;
    }
    if (nxt >= 0) {
        chain_res nr = residuals_of(uint(nxt));
        d += wt_a * nr.a_prev * nr.a_prev;
    }
    // Raised to the true Jacobi diagonal: keeps M SPD and covers the
    // residuals that do not follow the chain.
    L0(i) = vdiag[i] > d ? vdiag[i] : d;
    L1(i) = e1;
    L2(i) = e2;
}

void factor(uint head)
{
    for (int i = int(head); i >= 0; i = CHAIN_NEXT(uint(i))) {
        uint u = uint(i);
        int p1 = CHAIN_PREV(u), p2 = p1 >= 0 ? CHAIN_PREV(uint(p1)) : -1;
        float a2 = p2 >= 0 ? L2(u) / L0(uint(p2)) : 0.0;
        float a1 = p1 >= 0 ? (L1(u) - a2 * L1(uint(p1))) / L0(uint(p1)) : 0.0;
        float d = L0(u) - a1 * a1 - a2 * a2;
        L0(u) = sqrt(d > 1e-30 ? d : 1e-30);
        L1(u) = a1;
        L2(u) = a2;
    }
}

// z = M^-1 r: L y = r along the chain, then L^T z = y back. APPLY_CG
// first makes a CG step's updates of its nodes (mid_vec.comp CG_UPDATE:
// s += a p, r -= a Hp) and last writes their r.z terms (RZ): every element
// is on exactly one chain, so the three element-wise steps become one walk,
// with the same operations on the same values.
void apply_chain(uint head)
{
    int last = int(head);
    for (int i = int(head); i >= 0; i = CHAIN_NEXT(uint(i))) {
        uint u = uint(i);
        int p1 = CHAIN_PREV(u), p2 = p1 >= 0 ? CHAIN_PREV(uint(p1)) : -1;
        if (OP == MID_OP_APPLY_CG) {
            vs[u] += st.a_cg * vp[u];
            vr[u] -= st.a_cg * vhp[u];
        }
        float v = vr[u];
        if (p1 >= 0)
            v -= L1(u) * vz[uint(p1)];
        if (p2 >= 0)
            v -= L2(u) * vz[uint(p2)];
        vz[u] = v / L0(u);
        last = i;
    }
    for (int i = last; i >= 0; i = CHAIN_PREV(uint(i))) {
        uint u = uint(i);
        int n1 = CHAIN_NEXT(u), n2 = n1 >= 0 ? CHAIN_NEXT(uint(n1)) : -1;
        float v = vz[u];
        if (n1 >= 0)
            v -= L1(uint(n1)) * vz[uint(n1)];
        if (n2 >= 0)
            v -= L2(uint(n2)) * vz[uint(n2)];
        vz[u] = v / L0(u);
        if (OP == MID_OP_APPLY_CG) {
            DOT(4u, u) = vr[u] * vz[u];
            DOT(5u, u) = 0.0;
        }
    }
}

void main()
{
    if (OP == MID_OP_ASSEMBLE) {
        element_init();
        if (inside)
            assemble(ei);
        return;
    }
    // The walks: one invocation per chain head (window.heads), not per
    // element. A CPU rasteriser runs a loop at least once for every SIMD
    // row, so a row without a head cost one pass of each walk's body.
    uint h = gl_WorkGroupID.x * (MID_TILE * MID_TILE) + gl_LocalInvocationIndex;
    if (h >= st.heads)
        return;
    if (OP == MID_OP_FACTOR)
        factor(heads[h]);
    else
        apply_chain(heads[h]);
}
