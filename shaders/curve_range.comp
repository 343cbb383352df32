#version 460
#extension GL_GOOGLE_include_directive : require
#include "curve.glsl"
layout(local_size_x = 256) in;
shared float s_lo[256], s_hi[256];
// 0: per tile, 1: over the tiles (a specialisation constant: a CPU
// rasteriser would run both stages in each dispatch).
layout(constant_id = 0) const uint STAGE = 0u;

// Stage 0: each workgroup the range of its 64x64 tile, into tile_count
// (2 values a tile, positive floats as bits). Stage 1: one workgroup the
// range over the tiles, into the curve. Minimum and maximum are exact in
// any order: the curve is the same on every device.
void reduce(uint t, float lo, float hi)
{
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
}

void main()
{
    uint t = gl_LocalInvocationID.x;
    float lo = 1e30, hi = 0.0;
    if (STAGE == 0u) {
        ivec2 size = imageSize(depth_image);
        ivec2 origin = ivec2(gl_WorkGroupID.xy) * CURVE_TILE;
        for (uint i = t; i < CURVE_TILE * CURVE_TILE; i += 256u) {
            ivec2 p = origin + ivec2(i % CURVE_TILE, i / CURVE_TILE);
            if (any(greaterThanEqual(p, size)))
                continue;
            float z = imageLoad(depth_image, p).r;
            if (is_geometry(z)) {
                lo = min(lo, 1.0 / z);
                hi = max(hi, 1.0 / z);
            }
        }
        reduce(t, lo, hi);
        uint tile = gl_WorkGroupID.y * pc.tiles_x + gl_WorkGroupID.x;
        if (t == 0u) {
            tile_count[2u * tile] = floatBitsToUint(s_lo[0]);
            tile_count[2u * tile + 1u] = floatBitsToUint(s_hi[0]);
        }
        return;
    }
    for (uint i = t; i < pc.tiles_x * pc.tiles_y; i += 256u) {
        lo = min(lo, uintBitsToFloat(tile_count[2u * i]));
        hi = max(hi, uintBitsToFloat(tile_count[2u * i + 1u]));
    }
    reduce(t, lo, hi);
    if (t == 0u) {
        curve.valid = s_hi[0] > 0.0 ? 1u : 0u;
        curve.pad = 0u;
        curve.inv_depth_far = s_hi[0] > 0.0 ? s_lo[0] : 0.0;
        // A single depth still needs a span to index bins.
        curve.inv_depth_near = s_hi[0] > s_lo[0] ? s_hi[0] : curve.inv_depth_far * 1.001 + 1e-6;
    }
}
