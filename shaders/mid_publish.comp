#version 460
#extension GL_GOOGLE_include_directive : require
// mid.solve, last steps. gate (causal look-ahead only, one workgroup): the
// realized keyframe's c_a residuals of the solve's own f and of h, summed
// and decayed into the gain (mid_shared.h MID_GATE_*). publish: the solution becomes
// the next warm start (paper 4.5) and, from keyframe publish_from on, the
// correction m = f / g that mid.upsample reads (Fig. 4: only the correction
// is upsampled; vergence is never 0; mid_ratio_to_h), f as the gate's gain
// shows it, with its slope in time along the links (mid_ratio_slope), so the
// upsampling in time is C1 at keyframes (mid_hermite); and the solve's own
// ratio f / h, which the gate measures once its keyframe is realized.
#include "mid_arena.glsl"
MID_ELEMENT_LAYOUT;

layout(constant_id = 0) const uint OP = 0u;

float ratio_at(uint j) { return vf[j] / H(j); }

// The correction of f as shown: h + gain (f - h) under the causal gate, as
// f / h (a closed gate shows h at every frame); f / g without it.
float shown_at(uint j)
{
    return pc.gate != 0u ? 1.0 + pub.gate_gain * (vf[j] / H(j) - 1.0) : vf[j] / G(j);
}

// The solve's own f at window element j as published: h times the ratio
// of the gate's plane (its keyframe is observed and its ratio final).
float candidate(uint j)
{
    uint k = j / pc.ns, slot = (pc.store_first + k) % pc.store_cap;
    return H(j) * pub_ratio[(2u * pc.store_cap + slot) * pc.ns + (j - k * pc.ns)];
}

shared float s_c[MID_TILE * MID_TILE], s_h[MID_TILE * MID_TILE];

void gate()
{
    uint t = gl_LocalInvocationIndex, lanes = MID_TILE * MID_TILE;
    if (pc.gate_k == MID_GATE_NONE) {
        if (t == 0u)
            pub.gate_c = pub.gate_h = pub.gate_gain = 0.0;
        return;
    }
    float sc = 0.0, sh = 0.0;
    float idf = INVDT_F(pc.gate_k), idb = INVDT_B(pc.gate_k);
    for (uint q = t; q < pc.ns; q += lanes) {
        uint i = pc.gate_k * pc.ns + q;
        mid_link lf = link[i], lb = link[pc.cap + i];
        if (lf.mask == 0u || lb.mask == 0u)
            continue;
        float ga = R_LINK_GATHER(lf, G), gb = R_LINK_GATHER(lb, G), g = G(i);
        float ec = mid_accel_residual(R_LINK_GATHER(lf, candidate), candidate(i), R_LINK_GATHER(lb, candidate), ga, g,
                                      gb, idf, idb);
        float eh = mid_accel_residual(R_LINK_GATHER(lf, H), H(i), R_LINK_GATHER(lb, H), ga, g, gb, idf, idb);
        sc += ec * ec;
        sh += eh * eh;
    }
    s_c[t] = sc;
    s_h[t] = sh;
    barrier();
    for (uint s = lanes / 2u; s > 0u; s >>= 1u) {
        if (t < s) {
            s_c[t] += s_c[t + s];
            s_h[t] += s_h[t + s];
        }
        barrier();
    }
    if (t == 0u) {
        float c = MID_GATE_DECAY * pub.gate_c + s_c[0], h = MID_GATE_DECAY * pub.gate_h + s_h[0];
        pub.gate_c = c;
        pub.gate_h = h;
        pub.gate_gain = mid_gate_gain(c, h, float(pc.ns), pub.gate_gain);
    }
}

void main()
{
    if (OP == MID_OP_GATE) {
        if (pc.gate != 0u)
            gate();
        return;
    }
    element_init();
    if (!inside)
        return;
    uint i = ei;
    fprev[i] = vf[i];
    if (ek >= pc.publish_from) {
        uint slot = (pc.store_first + ek) % pc.store_cap;
        mid_link lf = link[i], lb = link[pc.cap + i];
        float m = shown_at(i);
        // (A m)_i over the shown correction; taps outside the mask weigh 0.
        float mf = lf.mask != 0u ? R_LINK_GATHER(lf, shown_at) : m, mb = lb.mask != 0u ? R_LINK_GATHER(lb, shown_at) : m;
        uint q = ey * pc.nx + ex;
        pub_ratio[slot * pc.ns + q] = m;
        pub_ratio[(pc.store_cap + slot) * pc.ns + q] = mid_ratio_slope(m, mf, mb, lf.mask, lb.mask, INVDT_F(ek), INVDT_B(ek));
        pub_ratio[(2u * pc.store_cap + slot) * pc.ns + q] = ratio_at(i);
    }
    if (i == 0u) {
        pub.range_lo = st.range_lo;
        pub.range_hi = st.range_hi;
        pub.of_h = pc.gate;
    }
}
