#version 460
#extension GL_GOOGLE_include_directive : require
// Background of an eye: the sky, alpha 0.5 (geometry is 1, nothing is 0).
#include "common.glsl"
#include "lighting.glsl"

layout(location = 0) in vec2 v_ndc;
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_aux;

void main()
{
    vec4 far = u.inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 dir = normalize(far.xyz / far.w - u.camera_pos.xyz);
    o_color = vec4(linear_to_srgb(tonemap(sky_radiance(dir))), 0.5);
    o_aux = vec4(-1.0, 0.0, 0.0, 0.0);
}
