#version 460
#extension GL_GOOGLE_include_directive : require
// warp.classify.cull (the first of its four graph steps): which triangles the eyes may see (frustum
// culling, as vgx_patch_outside). kinds = 1 visible, 0 culled, and this
// frame's stamp on the visible triangles' vertices; warp_vertices then warps
// only those, warp_edges levels only the edges a visible triangle uses. No shared
// memory and no barrier (lavapipe runs a kernel with a barrier as coroutines).
#define VG_FRAME_STORAGE
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"
#include "classify.glsl"

layout(local_size_x = 256) in;

void main()
{
    if (gl_GlobalInvocationID.x == 0u) // warp_vertices and warp_edges count this frame's lists from here
        for (uint k = 0u; k < VG_CLASSIFY_LISTS; k++)
            work_lists[k] = VG_WORKLIST_EMPTY;
    // One group at least, for the reset: a scene without a whole triangle has no chunk.
    if (gl_WorkGroupID.x >= pc.chunk_count)
        return;
    vg_warp_chunk ch = chunks[gl_WorkGroupID.x];
    vg_warp_instance inst = instances[ch.instance];
    uint t = gl_LocalInvocationID.x;
    if (t >= ch.triangle_count)
        return;
    uint tri = ch.first_triangle + t, first = inst.first_index + 3u * tri;
    vec3 p0 = position(inst.first_vertex + indices[first]), p1 = position(inst.first_vertex + indices[first + 1u]),
         p2 = position(inst.first_vertex + indices[first + 2u]);
    bool seen = !vgx_patch_outside(u.view_proj * vec4(p0, 1.0), u.view_proj * vec4(p1, 1.0), u.view_proj * vec4(p2, 1.0));
    kinds[inst.first_index / 3u + tri] = seen ? 1u : 0u;
    if (seen) { // warp_vertices warps these (several triangles write the same stamp)
        vertex_seen[inst.first_vertex + indices[first]] = pc.stamp;
        vertex_seen[inst.first_vertex + indices[first + 1u]] = pc.stamp;
        vertex_seen[inst.first_vertex + indices[first + 2u]] = pc.stamp;
    }
}
