#version 460
#extension GL_GOOGLE_include_directive : require
// warp.compact: after warp.classify, writes each chunk's flat and
// tessellated triangles at their place in the instance's lists, and the
// indirect draw commands (chunk 0 of each instance).
#extension GL_EXT_scalar_block_layout : require
#include "shared.h"
#include "classify.glsl"

layout(local_size_x = 256) in;
shared uint s_flat[256], s_tess[256];

void write_args(uint slot, uint index_count, uint first_index, uint first_vertex, uint first_instance)
{
    args[5u * slot + 0u] = index_count;
    args[5u * slot + 1u] = 1u;
    args[5u * slot + 2u] = first_index;
    args[5u * slot + 3u] = first_vertex; /* vertexOffset (int32, never negative here) */
    args[5u * slot + 4u] = first_instance;
}

void main()
{
    uint c = gl_WorkGroupID.x, t = gl_LocalInvocationID.x;
    vg_warp_chunk ch = chunks[c];
    vg_warp_instance inst = instances[ch.instance];
    // Where this chunk's triangles start: the counts of the instance's earlier chunks.
    uvec2 base = uvec2(0u);
    for (uint k = ch.first_chunk; k < c; k++)
        base += counts[k];
    uint tri = ch.first_triangle + t;
    uint packed = t < ch.triangle_count ? kinds[inst.first_index / 3u + tri] : 0u, kind = packed & 0xffu;
    s_flat[t] = kind == KIND_FLAT ? 1u : 0u;
    s_tess[t] = kind == KIND_TESSELLATED ? 1u : 0u;
    barrier();
    for (uint off = 1u; off < 256u; off <<= 1) {
        uint a = t >= off ? s_flat[t - off] : 0u, b = t >= off ? s_tess[t - off] : 0u;
        barrier();
        s_flat[t] += a;
        s_tess[t] += b;
        barrier();
    }
    if (kind != KIND_CULLED) {
        uint src = inst.first_index + 3u * tri;
        uint slot = kind == KIND_FLAT ? base.x + s_flat[t] - 1u : base.y + s_tess[t] - 1u;
        uint dst = inst.first_index + 3u * slot;
        for (uint k = 0u; k < 3u; k++) {
            if (kind == KIND_FLAT)
                flat_indices[dst + k] = indices[src + k];
            else
                tess_indices[dst + k] = indices[src + k];
        }
        if (kind == KIND_TESSELLATED)
            tess_levels[dst / 3u] = packed;
    }
    if (c != ch.first_chunk)
        return;
    // Chunk 0 of the instance writes its draws: the totals over all its chunks.
    uvec2 total = uvec2(0u);
    for (uint k = c; k < pc.chunk_count && chunks[k].instance == ch.instance; k++)
        total += counts[k];
    if (t == 0u) {
        write_args(ch.instance, 3u * total.x, inst.first_index, inst.first_vertex, 0u);
        // How many tessellated chunks hold triangles (vkCmdDrawIndexedIndirectCount).
        uint used = pc.chunk_triangles == 0xffffffffu ? min(total.y, 1u)
                                                      : (total.y + pc.chunk_triangles - 1u) / pc.chunk_triangles;
        args[5u * (pc.instance_count + pc.tess_slots) + ch.instance] = used;
    }
    for (uint d = t; d < inst.tess_chunks; d += 256u) {
        uint start = d * pc.chunk_triangles;
        uint n = total.y > start ? min(total.y - start, pc.chunk_triangles) : 0u;
        // firstInstance: the draw-order index of the draw's first patch.
        uint first = inst.first_index + 3u * start;
        write_args(pc.instance_count + inst.tess_args + d, 3u * n, first, inst.first_vertex, first / 3u);
    }
}
