#version 460
#extension GL_GOOGLE_include_directive : require
#include "curve.glsl"
layout(local_size_x = 256) in;
shared uint s_count[VGX_CURVE_BINS], s_sum[VGX_CURVE_BINS], s_offset[VGX_CURVE_BINS];

void main()
{
    uint t = gl_LocalInvocationID.x;
    s_count[t] = 0u;
    s_sum[t] = 0u;
    s_offset[t] = 0u;
    barrier();
    ivec2 size = imageSize(depth_image);
    ivec2 origin = ivec2(gl_WorkGroupID.xy) * CURVE_TILE;
    float lo = curve.inv_depth_far, span = curve.inv_depth_near - curve.inv_depth_far;
    // Integer atomics commute: the sums do not depend on the order of threads.
    for (uint i = t; i < CURVE_TILE * CURVE_TILE; i += 256u) {
        ivec2 p = origin + ivec2(i % CURVE_TILE, i / CURVE_TILE);
        if (any(greaterThanEqual(p, size)))
            continue;
        float z = imageLoad(depth_image, p).r;
        if (!is_geometry(z))
            continue;
        float pos = clamp((1.0 / z - lo) / span * float(VGX_CURVE_BINS), 0.0, float(VGX_CURVE_BINS) - 1e-3);
        int bin = int(pos);
        atomicAdd(s_count[bin], 1u);
        atomicAdd(s_offset[bin], uint((pos - float(bin)) * CURVE_OFFSET_FIXED));
        atomicAdd(s_sum[bin], uint(max(imageLoad(target_image, p).r, 0.0) * CURVE_FIXED + 0.5));
    }
    barrier();
    uint tile = gl_WorkGroupID.y * pc.tiles_x + gl_WorkGroupID.x;
    tile_count[tile * VGX_CURVE_BINS + t] = s_count[t];
    tile_sum[tile * VGX_CURVE_BINS + t] = s_sum[t];
    tile_offset[tile * VGX_CURVE_BINS + t] = s_offset[t];
}
