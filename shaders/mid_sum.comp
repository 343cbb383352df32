#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve: the sums the CPU solver keeps per block, as sums over chunks of
// MID_SUM_CHUNK consecutive elements in order (one invocation each, no
// barriers); mid_control.comp adds the chunks in order. Deterministic.
#include "mid_arena.glsl"
// The operation is a specialization constant: one pipeline per operation,
// no branch on it at run time.
layout(constant_id = 0) const uint OP = 0u;
layout(local_size_x = 64) in;

void main()
{
    uint c = gl_GlobalInvocationID.x;
    if (c >= pc.blocks)
        return;
    uint first = c * MID_SUM_CHUNK, last = min(first + MID_SUM_CHUNK, pc.n);
    uint col0 = OP == MID_OP_SUM_COST ? 0u : 4u, cols = OP == MID_OP_SUM_COST ? 4u : 2u;
    for (uint col = col0; col < col0 + cols; col++) {
        float s = 0.0;
        for (uint i = first; i < last; i++)
            s += R_DOT(col, i); // written by earlier dispatches: the texel view
        partial[c * MID_PARTIAL_FLOATS + col] = s;
    }
}
