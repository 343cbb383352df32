#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve: the element-wise steps of mid_solver.c (vec_block), with
// per-element terms where the CPU keeps block sums, plus the solve's start
// (f0 = h or the warm start, paper 4.5).
#include "mid_arena.glsl"
// Reads go through the texel views (mid_arena.glsl R_*); a value this
// invocation writes and uses again is kept in a register.
// The operation is a specialization constant: one pipeline per operation,
// no branch on it at run time.
layout(constant_id = 0) const uint OP = 0u;
MID_ELEMENT_LAYOUT;

void main()
{
    element_init();
    uint i = ei;
    float lo = st.range_lo, hi = st.range_hi;
    float acc0 = 0.0, acc1 = 0.0;
    if (inside) {
        switch (OP) {
        case MID_OP_CG_START: {
            // Projected Newton (Bertsekas 1982): a variable at a bound whose
            // gradient pushes outward stays there this iteration.
            float f = R_F(i), g = R_GRAD(i);
            bool held = (f <= lo + MID_BOUND_EPS && g > 0.0) || (f >= hi - MID_BOUND_EPS && g < 0.0);
            float m = held ? 0.0 : 1.0;
            vfree[i] = m;
            vr[i] = -g * m;
            vs[i] = 0.0;
            float pg = clamp(f - g, lo, hi) - f;
            acc1 = pg * pg;
            break;
        }
        case MID_OP_ZP_INIT: {
            float r = R_R(i), z = pc.jacobi != 0u ? r / R_DIAG(i) : R_Z(i);
            if (pc.jacobi != 0u)
                vz[i] = z;
            vp[i] = z;
            acc0 = r * z;
            break;
        }
        case MID_OP_CG_UPDATE: {
            vs[i] = R_S(i) + st.a_cg * R_P(i);
            float r = R_R(i) - st.a_cg * R_HP(i);
            vr[i] = r;
            if (pc.jacobi != 0u) {
                float z = r / R_DIAG(i);
                vz[i] = z;
                acc0 = r * z;
            }
            break;
        }
        case MID_OP_P_UPDATE:
            vp[i] = R_Z(i) + st.b_cg * R_P(i);
            break;
        case MID_OP_TRIAL: {
            float f = R_F(i), t = clamp(f + pc.scalar * R_S(i), lo, hi);
            vftry[i] = t;
            acc0 = R_GRAD(i) * (t - f);
            break;
        }
        case MID_OP_DESCENT: {
            float f = R_F(i), g = R_GRAD(i), t = clamp(f - pc.scalar * g / R_DIAG(i), lo, hi);
            vftry[i] = t;
            acc0 = g * (t - f);
            break;
        }
        case MID_OP_COMMIT:
            vf[i] = R_FTRY(i);
            break;
        case MID_OP_INIT: {
            // f0 = h (Sec. 4.5), or the last solution where the slid window
            // overlaps the previous one, projected into the range.
            int src = int(ek) + int(pc.shift);
            float init = pc.warm != 0u && src >= 0 && src < int(pc.nt_prev) ? fprev[uint(src) * pc.ns + ey * pc.nx + ex] : H(i);
            vf[i] = clamp(init, lo, hi);
            break;
        }
        default:
            break;
        }
    }
    if (inside && (OP == MID_OP_CG_START || OP == MID_OP_ZP_INIT || OP == MID_OP_TRIAL ||
                   OP == MID_OP_DESCENT || (OP == MID_OP_CG_UPDATE && pc.jacobi != 0u))) {
        DOT(4u, i) = acc0;
        DOT(5u, i) = acc1;
    }
}
