#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve: the temporal line preconditioner of mid_precond.c. ASSEMBLE is
// a gather over all nodes; FACTOR (banded Cholesky) and APPLY (the two
// substitutions) walk each flow chain from its head, one invocation per
// chain (dispatched over the heads' list): the same operations in the same
// order as the CPU's sweeps.
#include "mid_arena.glsl"
// Reads go through the texel views (mid_arena.glsl R_*) except what a walk
// wrote itself: its forward sweep's z and r, read back by its backward sweep.
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
    int nxt = R_CHAIN_NEXT(i), prv = R_CHAIN_PREV(i);
    float qf = R_Q_F(i), qb = R_Q_B(i);
    if (nxt < 0 || qf == 0.0)
        return c;
    c.t_mid = -qf * R_FREE(i);
    c.t_next = qf * R_FREE(uint(nxt));
    if (prv >= 0 && R_M_A(i) != 0.0) {
        c.a_prev = qb * R_FREE(uint(prv));
        c.a_mid = -(qf + qb) * R_FREE(i);
        c.a_next = qf * R_FREE(uint(nxt));
    }
    return c;
}

void assemble(uint i)
{
    if (R_FREE(i) == 0.0) {
        L0(i) = 1.0; // held: decoupled (a principal submatrix)
        L1(i) = 0.0;
        L2(i) = 0.0;
        return;
    }
    float scale = pc.grad_scale, wt_t = scale * pc.w_temporal, wt_a = scale * pc.w_accel;
    uint px = ex, py = ey;
    float edges = (px + 1u < pc.nx ? R_EDGE_X(i) : 0.0) + (px > 0u ? R_EDGE_X(i - 1u) : 0.0) +
                  (py + 1u < pc.ny ? R_EDGE_Y(i) : 0.0) + (py > 0u ? R_EDGE_Y(i - pc.nx) : 0.0);
    chain_res self = residuals_of(i);
    float d = scale * (pc.w_data + pc.w_spatial * edges) + wt_t * self.t_mid * self.t_mid +
              wt_a * self.a_mid * self.a_mid;
    float e1 = 0.0, e2 = 0.0;
    int prv = R_CHAIN_PREV(i), nxt = R_CHAIN_NEXT(i);
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
    float diag = R_DIAG(i);
    L0(i) = diag > d ? diag : d;
    L1(i) = e1;
    L2(i) = e2;
}

// The walks carry what the previous nodes of the chain just computed (their
// factor entries, their z) instead of loading it again through the chain's
// links: CHAIN_PREV of a node is the node the walk came from (the chains'
// links are mutual), so the values are the same, and a CPU rasteriser does a
// third fewer per-lane loads.
void factor(uint head)
{
    float l0_p1 = 0.0, l0_p2 = 0.0, l1_p1 = 0.0; // L0 and L1 of the node before, L0 of the one before it
    int before = 0;                              // nodes before this one on the chain
    for (int i = int(head); i >= 0; i = R_CHAIN_NEXT(uint(i))) {
        uint u = uint(i);
        float a2 = before >= 2 ? R_L2(u) / l0_p2 : 0.0;
        float a1 = before >= 1 ? (R_L1(u) - a2 * l1_p1) / l0_p1 : 0.0;
        float d = R_L0(u) - a1 * a1 - a2 * a2;
        float l0 = sqrt(d > 1e-30 ? d : 1e-30);
        L0(u) = l0;
        L1(u) = a1;
        L2(u) = a2;
        l0_p2 = l0_p1;
        l0_p1 = l0;
        l1_p1 = a1;
        before++;
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
    float a_cg = OP == MID_OP_APPLY_CG ? st.a_cg : 0.0;
    float z_p1 = 0.0, z_p2 = 0.0; // y of the node before and of the one before it
    int before = 0;
    for (int i = int(head); i >= 0; i = R_CHAIN_NEXT(uint(i))) {
        uint u = uint(i);
        float v = R_R(u);
        if (OP == MID_OP_APPLY_CG) {
            vs[u] = R_S(u) + a_cg * R_P(u);
            v -= a_cg * R_HP(u);
            vr[u] = v;
        }
        if (before >= 1)
            v -= R_L1(u) * z_p1;
        if (before >= 2)
            v -= R_L2(u) * z_p2;
        float y = v / R_L0(u);
        vz[u] = y;
        z_p2 = z_p1;
        z_p1 = y;
        before++;
        last = i;
    }
    // Back: z of the node after and of the one after it, with their L1 and L2.
    float z_n1 = 0.0, z_n2 = 0.0, l1_n1 = 0.0, l2_n1 = 0.0, l2_n2 = 0.0;
    int after = 0;
    for (int i = last; i >= 0; i = R_CHAIN_PREV(uint(i))) {
        uint u = uint(i);
        float v = vz[u];
        if (after >= 1)
            v -= l1_n1 * z_n1;
        if (after >= 2)
            v -= l2_n2 * z_n2;
        float z = v / R_L0(u);
        vz[u] = z;
        if (OP == MID_OP_APPLY_CG) // column 5 keeps vec.zp_init's zeros: control.rz reads column 4 only
            DOT(4u, u) = vr[u] * z;
        z_n2 = z_n1;
        l2_n2 = l2_n1;
        z_n1 = z;
        l1_n1 = R_L1(u);
        l2_n1 = R_L2(u);
        after++;
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
