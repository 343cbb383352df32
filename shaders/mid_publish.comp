#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve, last step: the solution becomes the next warm start (paper 4.5)
// and, from keyframe publish_from on, the ratio f / h that mid.upsample
// reads (Fig. 4: only the correction is upsampled; vergence is never 0),
// with its slope in time along the links (mid_ratio_slope), so the
// upsampling in time is C1 at keyframes (mid_hermite).
#include "mid_arena.glsl"
MID_ELEMENT_LAYOUT;

float ratio_at(uint j) { return vf[j] / H(j); }

// (A r)_i over the ratio of the solution; taps outside the mask weigh 0.
float gather_ratio(mid_link l)
{
    return mid_link_apply(mid_link_taps(l), ratio_at(l.base), ratio_at(l.base + 1u), ratio_at(l.base + pc.nx),
                          ratio_at(l.base + pc.nx + 1u));
}

void main()
{
    element_init();
    if (!inside)
        return;
    uint i = ei;
    fprev[i] = vf[i];
    if (ek >= pc.publish_from) {
        uint slot = (pc.store_first + ek) % pc.store_cap;
        mid_link lf = link[i], lb = link[pc.cap + i];
        float r = ratio_at(i);
        float rf = lf.mask != 0u ? gather_ratio(lf) : r, rb = lb.mask != 0u ? gather_ratio(lb) : r;
        uint q = ey * pc.nx + ex;
        pub_ratio[slot * pc.ns + q] = r;
        pub_ratio[(pc.store_cap + slot) * pc.ns + q] =
            mid_ratio_slope(r, rf, rb, lf.mask, lb.mask, INVDT_F(ek), INVDT_B(ek));
    }
    if (i == 0u) {
        pub.range_lo = st.range_lo;
        pub.range_hi = st.range_hi;
    }
}
