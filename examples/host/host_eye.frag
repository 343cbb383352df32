#version 450
#extension GL_GOOGLE_include_directive : require
// The example host's shading (its own: a sun on flat faces, a little fog),
// and where the surface is in the centre view (for the test).
#define VGX_WARP_SET 0
#include "vergence/warp.glsl"

layout(push_constant) uniform Push {
    vec4 color;
    uint right_eye;
} pc;
layout(location = 0) in vec3 e_world;
layout(location = 1) in vec4 e_centre_clip;
layout(location = 0) out vec4 o_color;
layout(location = 1) out float o_centre_x;

void main()
{
    vec3 n = normalize(cross(dFdx(e_world), dFdy(e_world)));
    vec3 sun = normalize(vec3(0.4, 0.8, 0.3));
    float light = 0.35 + 0.65 * abs(dot(n, sun));
    float fog = 1.0 - exp(-0.01 * e_centre_clip.w);
    o_color = vec4(mix(pc.color.rgb * light, vec3(0.78, 0.86, 0.95), fog), 1.0);
    o_centre_x = vgx_centre_pixel(e_centre_clip).x;
}
