#version 460
#extension GL_GOOGLE_include_directive : require
// warp.classify, step 2 of 4: the warp of every vertex a visible triangle
// uses (warp_cull stamped them), once for both eyes: vgx_warp_disparity,
// which the flat triangles' vertex shader then only adds to its clip
// position (vgx_warp_shift). The eyes' vertex stage runs on one thread
// on lavapipe and shaded each corner's cascade once per eye; this runs on
// all of them, once. The same function on the same position, `precise`:
// the same bits as before. No barrier.
#define VG_FRAME_STORAGE
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"
#include "classify.glsl"

layout(local_size_x = 64) in;

void main()
{
    uint v = gl_GlobalInvocationID.x;
    if (v >= pc.vertex_count || vertex_seen[v] != pc.stamp)
        return;
    precise vec4 clip = u.view_proj * vec4(vertices[6u * v], vertices[6u * v + 1u], vertices[6u * v + 2u], 1.0);
    int stage;
    float d_times_w = vgx_warp_disparity(clip, stage);
    vertex_warp[v] = vec2(d_times_w, float(stage));
}
