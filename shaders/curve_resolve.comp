#version 460
#extension GL_GOOGLE_include_directive : require
#include "curve.glsl"
layout(local_size_x = 256) in;
shared float s_q[VGX_CURVE_BINS], s_v[VGX_CURVE_BINS];
shared uint s_has[VGX_CURVE_BINS];

void main()
{
    uint b = gl_LocalInvocationID.x;
    uint count = 0u;
    float sum = 0.0, offset = 0.0;
    for (uint tile = 0u; tile < pc.tiles_x * pc.tiles_y; tile++) {
        uint k = tile * VGX_CURVE_BINS + b;
        count += tile_count[k];
        sum += float(tile_sum[k]);
        offset += float(tile_offset[k]);
    }
    float lo = curve.inv_depth_far, span = curve.inv_depth_near - curve.inv_depth_far;
    float inside = count > 0u ? offset / (float(count) * CURVE_OFFSET_FIXED) : 0.5;
    s_has[b] = count > 0u ? 1u : 0u;
    s_q[b] = lo + (float(b) + inside) / float(VGX_CURVE_BINS) * span;
    s_v[b] = count > 0u ? sum / (float(count) * CURVE_FIXED) : 0.0;
    barrier();
    // Empty bins: linear in inverse depth between the nearest populated
    // centroids (constant past the ends).
    int l = int(b), r = int(b);
    while (l >= 0 && s_has[l] == 0u)
        l--;
    while (r < VGX_CURVE_BINS && s_has[r] == 0u)
        r++;
    float v = s_v[b];
    if (s_has[b] == 0u) {
        if (l >= 0 && r < VGX_CURVE_BINS)
            v = mix(s_v[l], s_v[r], (s_q[b] - s_q[l]) / (s_q[r] - s_q[l]));
        else
            v = l >= 0 ? s_v[l] : r < VGX_CURVE_BINS ? s_v[r] : 0.0;
    }
    curve.inv_depth[b] = s_q[b];
    curve.vergence[b] = v;
}
