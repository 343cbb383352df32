#version 460
#extension GL_GOOGLE_include_directive : require
#include "curve.glsl"
layout(local_size_x = 256) in;
shared float s_lo[256], s_hi[256];

void main()
{
    uint t = gl_LocalInvocationID.x;
    ivec2 size = imageSize(depth_image);
    float lo = 1e30, hi = 0.0;
    for (int i = int(t); i < size.x * size.y; i += 256) {
        float z = imageLoad(depth_image, ivec2(i % size.x, i / size.x)).r;
        if (is_geometry(z)) {
            lo = min(lo, 1.0 / z);
            hi = max(hi, 1.0 / z);
        }
    }
    s_lo[t] = lo;
    s_hi[t] = hi;
    barrier();
    for (uint s = 128u; s > 0u; s >>= 1) {
        if (t < s) {
            s_lo[t] = min(s_lo[t], s_lo[t + s]);
            s_hi[t] = max(s_hi[t], s_hi[t + s]);
        }
        barrier();
    }
    if (t == 0u) {
        curve.valid = s_hi[0] > 0.0 ? 1u : 0u;
        curve.pad = 0u;
        curve.inv_depth_far = s_hi[0] > 0.0 ? s_lo[0] : 0.0;
        // A single depth still needs a span to index bins.
        curve.inv_depth_near = s_hi[0] > s_lo[0] ? s_hi[0] : curve.inv_depth_far * 1.001 + 1e-6;
    }
}
