#version 460
#extension GL_GOOGLE_include_directive : require
// warp.classify.gather (the last of its four graph steps): each scene triangle is culled, flat (no edge
// needs subdivision: a plain vertex shader draws it) or tessellated; the
// same decision as the tessellation control shader (vgx_edge_level, include/vergence/warp.glsl),
// which takes the levels decided here (warp.compact puts them in draw
// order). The edges' levels come from warp_edges, the culling from
// warp_cull; this step only gathers them and counts each chunk's kinds.
#extension GL_EXT_scalar_block_layout : require
#include "shared.h"
#include "classify.glsl"

layout(local_size_x = 256) in;
shared uint s_flat[256], s_tess[256];

void main()
{
    vg_warp_chunk ch = chunks[gl_WorkGroupID.x];
    vg_warp_instance inst = instances[ch.instance];
    uint t = gl_LocalInvocationID.x, kind = KIND_CULLED, packed = 0u;
    uint g = inst.first_index / 3u + ch.first_triangle + t;
    if (t < ch.triangle_count) {
        if (kinds[g] != 0u) {
            // The tessellation control shader takes these levels as they are
            // (edge_level is at most the maximum level, 64: 8 bits each).
            uint e0 = edge_levels[tri_edges[3u * g]], e1 = edge_levels[tri_edges[3u * g + 1u]],
                 e2 = edge_levels[tri_edges[3u * g + 2u]];
            kind = max(e0, max(e1, e2)) > 1u ? KIND_TESSELLATED : KIND_FLAT;
            packed = kind | e0 << 8 | e1 << 16 | e2 << 24;
        }
        kinds[g] = packed;
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
