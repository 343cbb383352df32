#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve, last step: the solution becomes the next warm start (paper 4.5)
// and, from keyframe publish_from on, the ratio f / h that mid.upsample
// reads (Fig. 4: only the correction is upsampled; vergence is never 0).
#include "mid_arena.glsl"

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.n)
        return;
    uint k = i / pc.ns;
    fprev[i] = vf[i];
    if (k >= pc.publish_from) {
        uint slot = (pc.store_first + k) % pc.store_cap;
        pub_ratio[slot * pc.ns + i % pc.ns] = vf[i] / H(i);
    }
    if (i == 0u) {
        pub.range_lo = st.range_lo;
        pub.range_hi = st.range_hi;
    }
}
