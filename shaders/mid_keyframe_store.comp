#version 460
#extension GL_GOOGLE_include_directive : require
// mid.keyframes.store: each keyframe rendered this frame enters the ring of
// the keyframe store: g, h (its own mapping), depth and the flows to the
// neighbouring keyframes, all at coarse resolution (coarse pixels), and the
// instance id (flow links stay on their instance, mid_window.c).
#include "common.glsl"
#include "stereo.glsl"
#include "disparity_operator.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
DISP_OP_PUSH;
layout(set = 0, binding = 1, r32f) uniform readonly image2D depth_atlas;
layout(set = 0, binding = 2, rgba32f) uniform readonly image2D motion_atlas;
layout(set = 0, binding = 3) readonly buffer StateBlock { float state[]; };
layout(set = 0, binding = 4) writeonly buffer StoreBlock { float store[]; };
layout(set = 0, binding = 5, r32ui) uniform readonly uimage2D ids_atlas;
#include "disparity_state.glsl"

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(op.width) || p.y >= int(op.tile_height * op.tiles))
        return;
    uint tile = uint(p.y) / op.tile_height, ns = op.width * op.tile_height;
    uint q = (uint(p.y) % op.tile_height) * op.width + uint(p.x);
    float z = imageLoad(depth_atlas, p).r, g = vergence_from_depth(z);
    vec4 m = imageLoad(motion_atlas, p);
    uint base = ((op.store_first + tile) % op.store_cap) * MID_STORE_FLOATS * ns;
    store[base + MID_STORE_G * ns + q] = g;
    store[base + MID_STORE_H * ns + q] = op_map(DISP_OP_ENTRY_TILE0 + tile, g);
    store[base + MID_STORE_DEPTH * ns + q] = z;
    store[base + MID_STORE_FLOW_F * ns + 2u * q] = m.z;
    store[base + MID_STORE_FLOW_F * ns + 2u * q + 1u] = m.w;
    store[base + MID_STORE_FLOW_B * ns + 2u * q] = m.x;
    store[base + MID_STORE_FLOW_B * ns + 2u * q + 1u] = m.y;
    store[base + MID_STORE_ID * ns + q] = float(imageLoad(ids_atlas, p).r);
}
