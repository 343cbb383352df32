#version 450
// Compiles mid_shared.h as GLSL: every shared layout and formula in one shader.
#extension GL_GOOGLE_include_directive : require
#include "disparity/mid_shared.h"
layout(local_size_x = MID_LOCAL_SIZE) in;
layout(std430, binding = 0) readonly buffer Links { mid_link links[]; };
layout(std430, binding = 1) readonly buffer Field { float f[]; };
layout(std430, binding = 2) writeonly buffer Out { float o[]; };
layout(std430, binding = 3) readonly buffer Params { mid_params params; };
layout(std430, binding = 4) readonly buffer Adj { mid_adj_entry adj[]; };
void main()
{
    uint i = gl_GlobalInvocationID.x;
    mid_link l = links[i];
    mid_taps t = mid_link_taps(l);
    uint b = l.base;
    float fa = mid_link_apply(t, f[b], f[b + 1u], f[b + params.nx], f[b + params.nx + 1u]);
    mid_pixel r = mid_pixel_eval(f[i], fa, fa, 6.0f, 6.0f, 1.0f, 1.0f, 0.0f, 0.0f);
    o[i] = r.r_t + r.r_a + r.q_f + r.q_b + mid_edge_weight(0.1f) + mid_dp(fa) + adj[i].w + VGX_UINT(adj[i].src);
}
