#version 460
// vgx.depth (the SDK, VGX_DEPTH_DEVICE): a host's z-buffer to linear depth
// along the view axis, from the projection it was drawn with: clip z =
// m10 z + m14 and clip w = m11 z + m15 of view-space z, so z = (m14 - d m15)
// / (d m11 - m10) and the depth is clip w (any handedness, reversed or not).
// Nothing at all behind the far plane (d at 1 with an infinite far plane)
// becomes 1e6 m.
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform sampler2D zbuffer;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D linear_depth;
layout(push_constant) uniform DepthPush {
    vec4 m; // m10, m11, m14, m15 of the column-major projection
} pc;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(linear_depth))))
        return;
    float d = texelFetch(zbuffer, p, 0).r;
    float z = (pc.m.z - d * pc.m.w) / (d * pc.m.y - pc.m.x);
    float w = pc.m.y * z + pc.m.w;
    imageStore(linear_depth, p, vec4(isinf(w) || isnan(w) || w > 1e6 || w < 0.0 ? 1e6 : w));
}
