#version 460
#extension GL_GOOGLE_include_directive : require
// mid.window: exclusive prefix sums of the CSR row counts (both transposes)
// into row offsets: each invocation scans a chunk of MID_SCAN_BLOCK counts
// in order (no barriers), one invocation scans the chunk totals, then each
// chunk adds its offset (and clears the counts to serve as fill cursors).
// Row n's offset is the entry count.
#include "mid_arena.glsl"
// The operation is a specialization constant: one pipeline per operation,
// no branch on it at run time.
layout(constant_id = 0) const uint OP = 0u;
layout(local_size_x = 64) in;

uint scan_stride()
{
    return (pc.cap + 1u) / MID_SCAN_BLOCK + 1u;
}

void main()
{
    uint chunk = gl_GlobalInvocationID.x, dir = gl_GlobalInvocationID.y;
    uint chunks = (pc.n + 1u + MID_SCAN_BLOCK - 1u) / MID_SCAN_BLOCK;
    uint off = dir * (pc.cap + 1u);
    if (OP == MID_OP_SCAN_TOP) {
        if (chunk < 2u) {
            uint run = 0u;
            for (uint b = 0u; b < chunks; b++) {
                uint v = scan[chunk * scan_stride() + b];
                scan[chunk * scan_stride() + b] = run;
                run += v;
            }
        }
        return;
    }
    if (chunk >= chunks)
        return;
    uint first = chunk * MID_SCAN_BLOCK, last = min(first + MID_SCAN_BLOCK, pc.n + 1u);
    if (OP == MID_OP_SCAN_BLOCKS) {
        uint run = 0u;
        for (uint idx = first; idx < last; idx++) {
            uint v = idx < pc.n ? cursor[dir * pc.cap + idx] : 0u;
            adj_off[off + idx] = run;
            run += v;
        }
        scan[dir * scan_stride() + chunk] = run;
    } else if (OP == MID_OP_SCAN_ADD) {
        uint add = scan[dir * scan_stride() + chunk];
        for (uint idx = first; idx < last; idx++) {
            adj_off[off + idx] += add;
            if (idx < pc.n)
                cursor[dir * pc.cap + idx] = 0u;
        }
    }
}
