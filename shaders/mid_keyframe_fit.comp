#version 460
#extension GL_GOOGLE_include_directive : require
// mid.keyframes.operator: the operator's mapping of every keyframe rendered
// this frame (tiles of the coarse atlas, in time order), g from the coarse
// depth as disparity.original does. lang-smoothed runs at the keyframe rate:
// each tile blends with the previous keyframe's mapping (the chain entry),
// and its mapping is kept in the keyframes' ring (a frame between keyframes
// blends with it: disparity_fit.comp).
#include "common.glsl"
#include "stereo.glsl"
#include "disparity_operator.glsl"
layout(local_size_x = 256) in;
DISP_OP_PUSH;
layout(set = 0, binding = 1, r32f) uniform readonly image2D depth_atlas;
layout(set = 0, binding = 2, rgba8) uniform readonly image2D color_atlas;
layout(set = 0, binding = 3) buffer StateBlock { float state[]; };
#include "disparity_state.glsl"

uint tile;

uint sample_count() { return op.width * op.tile_height; }

vec2 sample_at(uint s)
{
    ivec2 p = ivec2(s % op.width, tile * op.tile_height + s / op.width);
    return vec2(vergence_from_depth(imageLoad(depth_atlas, p).r), op_weight(imageLoad(color_atlas, p).a));
}

#include "disparity_fit.glsl"

void main()
{
    // Keyframes fitted again (the causal window predicts its future anew at
    // each move): the chain goes on from the keyframe before the first tile.
    if ((op.flags & DISP_OP_FLAG_CHAIN_FROM) != 0u) {
        for (uint f = gl_LocalInvocationID.x; f < DISP_OP_STATE_FLOATS; f += gl_WorkGroupSize.x)
            state[DISP_OP_ENTRY_CHAIN * DISP_OP_STATE_FLOATS + f] = state[op.prev * DISP_OP_STATE_FLOATS + f];
        memoryBarrierBuffer();
        barrier();
    }
    for (tile = 0u; tile < op.tiles; tile++) {
        uint e = DISP_OP_ENTRY_TILE0 + tile;
        op_fit(e, DISP_OP_ENTRY_CHAIN, op.key_alpha);
        barrier();
        memoryBarrierBuffer();
        if (gl_LocalInvocationID.x == 0u) {
            uint ring = op.keys + (op.store_first + tile) % op.store_cap;
            bool keep = (op.flags & DISP_OP_FLAG_KEY_RING) != 0u;
            for (uint f = 0u; f < DISP_OP_STATE_FLOATS; f++) {
                state[DISP_OP_ENTRY_CHAIN * DISP_OP_STATE_FLOATS + f] = state[e * DISP_OP_STATE_FLOATS + f];
                if (keep)
                    state[ring * DISP_OP_STATE_FLOATS + f] = state[e * DISP_OP_STATE_FLOATS + f];
            }
        }
        barrier();
        memoryBarrierBuffer();
    }
}
