#version 460
#extension GL_GOOGLE_include_directive : require
// warp.classify: each scene triangle is culled, flat (no edge needs
// subdivision: a plain vertex shader draws it) or tessellated; the same
// decision as the tessellation control shader (tess_levels.glsl), which
// takes the levels decided here (warp.compact puts them in draw order).
#define VG_FRAME_STORAGE
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"
#include "tess_levels.glsl"
#include "classify.glsl"

layout(local_size_x = 256) in;
shared uint s_flat[256], s_tess[256];

vec3 position(uint v)
{
    return vec3(vertices[6u * v], vertices[6u * v + 1u], vertices[6u * v + 2u]);
}

void main()
{
    vg_warp_chunk ch = chunks[gl_WorkGroupID.x];
    vg_warp_instance inst = instances[ch.instance];
    uint t = gl_LocalInvocationID.x, kind = KIND_CULLED, packed = 0u;
    uint tri = ch.first_triangle + t;
    if (t < ch.triangle_count) {
        uint first = inst.first_index + 3u * tri;
        uvec3 idx = uvec3(indices[first], indices[first + 1u], indices[first + 2u]);
        vec3 p0 = position(inst.first_vertex + idx.x), p1 = position(inst.first_vertex + idx.y),
             p2 = position(inst.first_vertex + idx.z);
        if (!outside(u.view_proj * vec4(p0, 1.0), u.view_proj * vec4(p1, 1.0), u.view_proj * vec4(p2, 1.0))) {
            // The tessellation control shader takes these levels as they are
            // (edge_level is at most the maximum level, 64: 8 bits each).
            float e0 = edge_level(p1, p2), e1 = edge_level(p2, p0), e2 = edge_level(p0, p1);
            kind = max(e0, max(e1, e2)) > 1.0 ? KIND_TESSELLATED : KIND_FLAT;
            packed = kind | uint(e0) << 8 | uint(e1) << 16 | uint(e2) << 24;
        }
        kinds[inst.first_index / 3u + tri] = packed;
    }
    s_flat[t] = kind == KIND_FLAT ? 1u : 0u;
    s_tess[t] = kind == KIND_TESSELLATED ? 1u : 0u;
    barrier();
    for (uint s = 128u; s > 0u; s >>= 1) {
        if (t < s) {
            s_flat[t] += s_flat[t + s];
            s_tess[t] += s_tess[t + s];
        }
        barrier();
    }
    if (t == 0u)
        counts[gl_WorkGroupID.x] = uvec2(s_flat[0], s_tess[0]);
}
