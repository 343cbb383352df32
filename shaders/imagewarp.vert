#version 460
#extension GL_GOOGLE_include_directive : require
// The image-warping baseline: every centre pixel is splatted to where its
// target disparity puts it in this eye; a z-buffer resolves overlaps and
// whatever no pixel reaches stays empty (the disocclusion holes of Fig. 5).
#include "common.glsl"
#include "stereo.glsl"

layout(push_constant, scalar) uniform DrawBlock { vg_draw_push d; };
layout(set = 0, binding = VG_BINDING_DEPTH) uniform sampler2D depth_map;
layout(set = 0, binding = VG_BINDING_TARGET) uniform sampler2D target_map;
layout(set = 0, binding = 5) uniform sampler2D color_map;
layout(set = 0, binding = 6) uniform usampler2D id_map;
layout(location = 0) out vec4 v_color;

void main()
{
    ivec2 size = textureSize(depth_map, 0);
    ivec2 p = ivec2(gl_VertexIndex % size.x, gl_VertexIndex / size.x);
    float z = texelFetch(depth_map, p, 0).r;
    float disparity_px = vgx_px_from_vergence(texelFetch(target_map, p, 0).r);
    float side = (d.flags & VG_DRAW_RIGHT_EYE) != 0u ? 1.0 : -1.0;
    vec2 px = vec2(p) + 0.5 + vec2(side * 0.5 * disparity_px, 0.0);
    gl_Position = vec4(px * u.viewport.zw * 2.0 - 1.0, clamp(z / u.camera_pos.w, 0.0, 1.0), 1.0);
    gl_PointSize = 1.0;
    bool geometry = texelFetch(id_map, p, 0).r != 0u;
    v_color = vec4(texelFetch(color_map, p, 0).rgb, geometry ? 1.0 : 0.5);
}
