#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve, last step: the solution becomes the next warm start (paper 4.5)
// and, from keyframe publish_from on, the ratio f / h that mid.upsample
// reads (Fig. 4: only the correction is upsampled; vergence is never 0).
#include "mid_arena.glsl"
MID_ELEMENT_LAYOUT;

void main()
{
    element_init();
    if (!inside)
        return;
    uint i = ei;
    fprev[i] = vf[i];
    if (ek >= pc.publish_from) {
        uint slot = (pc.store_first + ek) % pc.store_cap;
        pub_ratio[slot * pc.ns + ey * pc.nx + ex] = vf[i] / H(i);
    }
    if (i == 0u) {
        pub.range_lo = st.range_lo;
        pub.range_hi = st.range_hi;
    }
}
