// vergence — the vertices' warp of warp.classify, shared by its two kernels
// (warp_vertices in warp.classify.vertices, warp_vertex_search in .levels)
// (warp_vertices.comp, warp_vertex_search.comp): the warp of every vertex a
// visible triangle uses (warp_cull stamped them), once for both eyes:
// vgx_warp_disparity, which the flat triangles' vertex shader then only adds
// to its clip position (vgx_warp_shift). The eyes' vertex stage runs on one
// thread on lavapipe and shaded each corner's cascade once per eye; this
// runs on all of them, once. The same function on the same position,
// `precise`: the same bits as before. No barrier.
//
// warp_vertices: the cascade without its Halton search, whose 64-sample
// loop llvmpipe would run for a whole row of eight lanes whenever one lane
// needs it; a vertex the 3x3 neighbourhood leaves unresolved goes to the
// list VG_HALTON_LIST instead. warp_vertex_search (VG_VERTEX_SEARCH): the
// whole vgx_warp_disparity over that list, dispatched indirectly; it only
// reads the lists (two kernels, not two specialisations: synchronization
// validation counts what a shader module could write). Where the search
// does not run, both give the same values.
#define VG_FRAME_STORAGE
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"
#include "classify.glsl"

layout(local_size_x = VG_WORKLIST_GROUP) in;

void main()
{
#ifdef VG_VERTEX_SEARCH
    uint i = gl_GlobalInvocationID.x;
    if (i >= work_lists[VG_HALTON_LIST].x)
        return;
    uint v = work_items[VG_EDGE_BUCKETS * pc.edge_count + i];
    const bool halton = true;
#else
    uint v = gl_GlobalInvocationID.x;
    if (v >= pc.vertex_count || vertex_seen[v] != pc.stamp)
        return;
    const bool halton = false;
#endif
    precise vec4 clip = u.view_proj * vec4(vertices[6u * v], vertices[6u * v + 1u], vertices[6u * v + 2u], 1.0);
    int stage;
    float d_times_w = vgx_warp_disparity_search(clip, halton, stage);
#ifndef VG_VERTEX_SEARCH
    if (stage == VGX_STAGE_CURVE) {
        uint i;
        VG_WORKLIST_APPEND(work_lists[VG_HALTON_LIST], i);
        work_items[VG_EDGE_BUCKETS * pc.edge_count + i] = v;
        return; // warp_vertex_search writes its warp
    }
#endif
    vertex_warp[v] = vec2(d_times_w, float(stage));
}
