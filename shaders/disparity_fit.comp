#version 460
#extension GL_GOOGLE_include_directive : require
// disparity.operator.fit (DESIGN.md step 4): the frame's mapping, from the
// samples of g on a grid of stride op.stride (the coarse grid of the solver,
// so a keyframe's full-resolution h and its coarse keyframe sample share one
// mapping; stride 1 is disp_operator_apply() on every pixel).
#include "disparity_operator.glsl"
layout(local_size_x = 256) in;
DISP_OP_PUSH;
layout(set = 0, binding = 0, r32f) uniform readonly image2D g_image;
layout(set = 0, binding = 1, rgba8) uniform readonly image2D color_image; // alpha = saliency
layout(set = 0, binding = 2) buffer StateBlock { float state[]; };
#include "disparity_state.glsl"

uint grid_w() { return (op.width + op.stride - 1u) / op.stride; }
uint grid_h() { return (op.height + op.stride - 1u) / op.stride; }
uint sample_count() { return grid_w() * grid_h(); }

// (g, integer weight) of sample s: the pixel at the centre of its block.
vec2 sample_at(uint s)
{
    uint qx = s % grid_w(), qy = s / grid_w();
    ivec2 p = ivec2(min(qx * op.stride + op.stride / 2u, op.width - 1u), min(qy * op.stride + op.stride / 2u, op.height - 1u));
    return vec2(imageLoad(g_image, p).r, op_weight(imageLoad(color_image, p).a));
}

#include "disparity_fit.glsl"

void main()
{
    op_fit(op.entry, op.prev, op.smooth_alpha);
}
