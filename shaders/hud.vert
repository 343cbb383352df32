#version 460
#extension GL_EXT_scalar_block_layout : require
// Overlay text and panels (quads from stb_easy_font in font pixels, scaled
// to eye pixels and shifted by the eye's half of the overlay's parallax).
layout(push_constant, scalar) uniform HudBlock { vec2 inv_half_extent; float scale; float shift; } hud;
layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec4 in_color;
layout(location = 0) out vec4 v_color;
void main()
{
    vec2 p = in_pos.xy * hud.scale + vec2(hud.shift, 0.0);
    gl_Position = vec4(p * hud.inv_half_extent - 1.0, 0.0, 1.0);
    v_color = in_color;
}
