#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve: one workgroup that adds the workgroup sums in a fixed order and
// takes the CPU solver's branches (mid_solver.c): CG steps, the backtracking
// line search, convergence. It writes the dispatch sizes of the kernels that
// follow, so work the CPU would skip costs nothing here either.
#include "mid_arena.glsl"
layout(local_size_x = MID_LOCAL_SIZE) in;

shared float s_sum[6][MID_LOCAL_SIZE];

void main()
{
    uint t = gl_LocalInvocationID.x;
    float acc[6] = float[6](0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (uint b = t; b < pc.blocks; b += MID_LOCAL_SIZE)
        for (uint c = 0u; c < 6u; c++)
            acc[c] += partial[b * MID_PARTIAL_FLOATS + c];
    for (uint c = 0u; c < 6u; c++)
        s_sum[c][t] = acc[c];
    barrier();
    for (uint s = MID_LOCAL_SIZE / 2u; s > 0u; s >>= 1u) {
        if (t < s)
            for (uint c = 0u; c < 6u; c++)
                s_sum[c][t] += s_sum[c][t + s];
        barrier();
    }
    if (t != 0u)
        return;
    float inv_n = 1.0 / float(pc.n);
    float cost = pc.w_data * s_sum[0][0] * inv_n + pc.w_spatial * s_sum[1][0] * inv_n +
                 pc.w_temporal * s_sum[2][0] * inv_n + pc.w_accel * s_sum[3][0] * inv_n;
    float acc0 = s_sum[4][0], acc1 = s_sum[5][0];
    switch (pc.op) {
    case MID_OP_C_RESET:
        st.g_min_bits = floatBitsToUint(3.0e38);
        st.g_max_bits = 0u;
        st.running = 0u;
        st.heads = 0u;
        break;
    case MID_OP_C_RANGE: {
        float lo = pc.range_lo, hi = pc.range_hi;
        if (pc.range_hull != 0u) {
            // `none` keeps g: its box is the hull of the target range and g.
            lo = min(lo, uintBitsToFloat(st.g_min_bits));
            hi = max(hi, uintBitsToFloat(st.g_max_bits));
        }
        st.range_lo = lo;
        st.range_hi = hi;
        st.inv_range = 1.0 / (hi - lo);
        break;
    }
    case MID_OP_C_INIT_COST:
        st.c = cost;
        st.cost_initial = cost;
        st.running = 1u;
        st.cg_running = 0u;
        st.accepted = 0u;
        st.iteration = 0u;
        st.cg_steps = 0u;
        st.line_trials = 0u;
        break;
    case MID_OP_C_ITER_BEGIN:
        st.cg_running = 1u;
        st.accepted = 0u;
        break;
    case MID_OP_C_PG2:
        // A stationary point of the box-constrained problem: converged.
        st.pg2 = acc1;
        if (st.running != 0u && acc1 == 0.0)
            st.running = 0u;
        break;
    case MID_OP_C_RZ0:
        if (st.running != 0u) {
            st.rz = acc0;
            st.rz0 = acc0;
            if (!(acc0 > 0.0))
                st.running = 0u;
        }
        break;
    case MID_OP_C_PHP:
        if (st.running != 0u && st.cg_running != 0u) {
            st.php = acc0;
            st.cg_steps++;
            if (!(acc0 > 0.0))
                st.cg_running = 0u;
            else
                st.a_cg = st.rz / acc0;
        }
        break;
    case MID_OP_C_RZNEW:
        if (st.running != 0u && st.cg_running != 0u) {
            st.rz_new = acc0;
            if (acc0 <= MID_CG_TOLERANCE * st.rz0) {
                st.cg_running = 0u;
            } else {
                st.b_cg = acc0 / st.rz;
                st.rz = acc0;
            }
        }
        break;
    case MID_OP_C_TRIAL:
        // Backtracking on the projected arc with the Armijo test.
        if (st.running != 0u && st.accepted == 0u) {
            st.line_trials++;
            st.c_try = cost;
            st.decrease = acc0;
            if (cost < st.c && cost <= st.c + MID_LINE_ARMIJO * acc0) {
                st.c = cost;
                st.accepted = 1u;
            }
        }
        break;
    case MID_OP_C_ITER_END:
        // No step lowers the cost: converged to float precision.
        if (st.running != 0u) {
            if (st.accepted != 0u)
                st.iteration++;
            else
                st.running = 0u;
        }
        break;
    case MID_OP_C_DESCENT:
        if (st.running != 0u) {
            st.c = cost;
            st.accepted = 1u;
            st.iteration++;
        }
        break;
    default:
        break;
    }
    bool run = st.running != 0u;
    bool open[MID_ARGS_GATES] = bool[MID_ARGS_GATES](run, run && st.cg_running != 0u, run && st.accepted == 0u,
                                                     run && st.accepted != 0u);
    for (uint g = 0u; g < MID_ARGS_GATES; g++) {
        // An element kernel's grid, a chunk sum's, a walk over the chain heads'.
        uint a = 3u * MID_ARGS_SIZES * g;
        args[a] = open[g] ? (pc.nx + MID_TILE - 1u) / MID_TILE : 0u;
        args[a + 1u] = (pc.ny + MID_TILE - 1u) / MID_TILE;
        args[a + 2u] = pc.nt;
        args[a + 3u] = open[g] ? (pc.blocks + 63u) / 64u : 0u;
        args[a + 4u] = 1u;
        args[a + 5u] = 1u;
        args[a + 6u] = open[g] ? (st.heads + MID_TILE * MID_TILE - 1u) / (MID_TILE * MID_TILE) : 0u;
        args[a + 7u] = 1u;
        args[a + 8u] = 1u;
    }
}
