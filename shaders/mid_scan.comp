#version 460
#extension GL_GOOGLE_include_directive : require
// mid.window: exclusive prefix sums of the CSR row counts (both transposes)
// into row offsets, in three steps: per block of MID_SCAN_BLOCK counts, over
// the block totals, then the block offsets added (and the counts cleared to
// serve as fill cursors). Row n's offset is the entry count.
#include "mid_arena.glsl"

shared uint s_sum[MID_LOCAL_SIZE];

uint scan_stride()
{
    return (pc.cap + 1u) / MID_SCAN_BLOCK + 1u;
}

void main()
{
    uint t = gl_LocalInvocationID.x, dir = gl_WorkGroupID.y, block = gl_WorkGroupID.x;
    uint per = MID_SCAN_BLOCK / MID_LOCAL_SIZE;
    uint first = block * MID_SCAN_BLOCK + t * per;
    uint off = dir * (pc.cap + 1u);
    if (pc.op == MID_OP_SCAN_BLOCKS) {
        uint v[MID_SCAN_BLOCK / MID_LOCAL_SIZE];
        uint sum = 0u;
        for (uint e = 0u; e < per; e++) {
            uint idx = first + e;
            v[e] = idx < pc.n ? cursor[dir * pc.cap + idx] : 0u;
            sum += v[e];
        }
        s_sum[t] = sum;
        barrier();
        // Hillis-Steele inclusive scan of the thread sums.
        for (uint s = 1u; s < MID_LOCAL_SIZE; s <<= 1u) {
            uint add = t >= s ? s_sum[t - s] : 0u;
            barrier();
            s_sum[t] += add;
            barrier();
        }
        uint run = s_sum[t] - sum;
        for (uint e = 0u; e < per; e++) {
            uint idx = first + e;
            if (idx <= pc.n)
                adj_off[off + idx] = run;
            run += v[e];
        }
        if (t == MID_LOCAL_SIZE - 1u)
            scan[dir * scan_stride() + block] = s_sum[t];
    } else if (pc.op == MID_OP_SCAN_TOP) {
        if (t < 2u) {
            uint blocks = (pc.n + 1u + MID_SCAN_BLOCK - 1u) / MID_SCAN_BLOCK, run = 0u;
            for (uint b = 0u; b < blocks; b++) {
                uint v = scan[t * scan_stride() + b];
                scan[t * scan_stride() + b] = run;
                run += v;
            }
        }
    } else if (pc.op == MID_OP_SCAN_ADD) {
        uint add = scan[dir * scan_stride() + block];
        for (uint e = 0u; e < per; e++) {
            uint idx = first + e;
            if (idx <= pc.n)
                adj_off[off + idx] += add;
            if (idx < pc.n)
                cursor[dir * pc.cap + idx] = 0u;
        }
    }
}
