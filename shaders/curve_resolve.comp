#version 460
#extension GL_GOOGLE_include_directive : require
#include "curve.glsl"
layout(local_size_x = 256) in;
shared float s_mean[VG_CURVE_BINS];
shared uint s_has[VG_CURVE_BINS];

void main()
{
    uint b = gl_LocalInvocationID.x;
    uint count = 0u;
    float sum = 0.0;
    for (uint tile = 0u; tile < pc.tiles_x * pc.tiles_y; tile++) {
        count += tile_count[tile * VG_CURVE_BINS + b];
        sum += float(tile_sum[tile * VG_CURVE_BINS + b]);
    }
    s_has[b] = count > 0u ? 1u : 0u;
    s_mean[b] = count > 0u ? sum / (float(count) * CURVE_FIXED) : 0.0;
    barrier();
    // Empty bins: linear between the nearest populated bins (constant at the ends).
    int l = int(b), r = int(b);
    while (l >= 0 && s_has[l] == 0u)
        l--;
    while (r < VG_CURVE_BINS && s_has[r] == 0u)
        r++;
    float v = 0.0;
    if (s_has[b] != 0u)
        v = s_mean[b];
    else if (l >= 0 && r < VG_CURVE_BINS)
        v = mix(s_mean[l], s_mean[r], float(int(b) - l) / float(r - l));
    else if (l >= 0)
        v = s_mean[l];
    else if (r < VG_CURVE_BINS)
        v = s_mean[r];
    curve.vergence[b] = v;
}
