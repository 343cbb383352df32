#version 460
// warp.stereo: vertices go to the tessellator untransformed (world space).
layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec3 in_normal;
layout(location = 4) in vec2 in_uv;
layout(location = 5) in vec4 in_color;
layout(location = 0) out vec3 v_pos;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec2 v_uv;
layout(location = 3) out vec4 v_color;
layout(location = 4) out uint v_first_patch; /* the draw's firstInstance (warp.compact) */
void main()
{
    v_pos = in_pos;
    v_normal = in_normal;
    v_uv = in_uv;
    v_color = in_color;
    v_first_patch = uint(gl_InstanceIndex);
}
