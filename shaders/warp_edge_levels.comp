#version 460
#extension GL_GOOGLE_include_directive : require
// warp.classify.levels: the edges of one bucket of warp_edges (one number
// of samples), levelled by sampling the cascade along them (vgx_edge_level).
#define VG_FRAME_STORAGE
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"
#include "classify.glsl"

layout(local_size_x = VG_WORKLIST_GROUP) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= work_lists[pc.bucket].x)
        return;
    uint e = work_items[pc.bucket * pc.edge_count + i];
    vg_warp_edge ed = edges[e];
    edge_levels[e] = uint(vgx_edge_level(position(ed.v0), position(ed.v1)));
}
