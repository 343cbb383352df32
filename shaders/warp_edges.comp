#version 460
#extension GL_GOOGLE_include_directive : require
// warp.classify.vertices (with warp_vertices): the level of every edge a visible triangle
// uses, once per edge (two triangles share most edges). Here only what
// needs no sampling (vgx_edge_prepare: short, behind the camera, a fixed
// pixel length); each edge to sample goes to the bucket of its number of
// samples, and warp_edge_levels levels the buckets: llvmpipe runs a loop as
// long as the longest lane of its row of eight needs, so rows of edges with
// one sample count do no idle sampling. The same vgx_edge_level, so the
// levels, and the pictures, are the same. No barrier.
#define VG_FRAME_STORAGE
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"
#include "classify.glsl"

layout(local_size_x = 64) in;

void main()
{
    uint e = gl_GlobalInvocationID.x;
    if (e >= pc.edge_count)
        return;
    vg_warp_edge ed = edges[e];
    bool needed = ed.t0 == VG_EDGE_ALWAYS || kinds[ed.t0] != 0u || (ed.t1 != VG_EDGE_NONE && kinds[ed.t1] != 0u);
    float level = 1.0;
    if (needed) {
        vec3 a = position(ed.v0), b = position(ed.v1);
        vec4 ca, cb;
        float max_level;
        int m;
        level = vgx_edge_prepare(a, b, ca, cb, max_level, m);
        if (level == 0.0) {
            uint k = m == 6 ? 0u : m == 12 ? 1u : 2u, i;
            VG_WORKLIST_APPEND(work_lists[k], i);
            work_items[k * pc.edge_count + i] = e;
            return; // warp_edge_levels writes its level
        }
    }
    edge_levels[e] = uint(level);
}
