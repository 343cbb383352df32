#version 460
#extension GL_GOOGLE_include_directive : require
// disparity.operator (DESIGN.md step 4): h = M(g) per pixel with the
// mapping disparity.operator.fit made.
#include "disparity_operator.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
DISP_OP_PUSH;
layout(set = 0, binding = 0, r32f) uniform readonly image2D g_image;
// The state through a texel view: its knots are read at each pixel's bin,
// which a CPU rasteriser gathers from texels and loads lane by lane from a
// storage buffer.
layout(set = 0, binding = 1) uniform samplerBuffer state_texels;
#define OP_STATE(i) texelFetch(state_texels, int(i)).r
layout(set = 0, binding = 2, r32f) uniform writeonly image2D h_image;
#include "disparity_state.glsl"

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(op.width) || p.y >= int(op.height))
        return;
    imageStore(h_image, p, vec4(op_map(op.entry, imageLoad(g_image, p).r)));
}
