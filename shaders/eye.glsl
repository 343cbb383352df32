// vergence — shading of either eye (warp or two cameras), plus what the tests
// measure: the centre-view position of the surface, the disparity error
// against the cascade at that position (EYE_MEASURE only: it binds the
// depth, target and curve), and the cascade stage of the vertices.
// Included by eye.frag and eye_measure.frag.
#include "common.glsl"
#include "lighting.glsl"
#include "stereo.glsl"

layout(push_constant, scalar) uniform DrawBlock { vg_draw_push d; };
layout(set = 0, binding = VG_BINDING_SHADOW) uniform sampler2DShadow shadow_map;
layout(set = 1, binding = 0) uniform sampler2D textures[VG_MAX_TEXTURES];

#ifdef EYE_MEASURE
#include "cascade.glsl"
#endif
#include "shade.glsl"

layout(location = 0) in vec3 e_world;
layout(location = 1) in vec3 e_normal;
layout(location = 2) in vec2 e_uv;
layout(location = 3) in vec4 e_color;
layout(location = 4) in vec4 e_centre_clip;
layout(location = 5) in vec4 e_stage;

layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_aux;

void main()
{
    vec2 centre = vgx_centre_pixel(e_centre_clip);
    vec3 shaded = shade_surface(e_world, e_normal, gl_FrontFacing, surface_base_color(e_color, e_uv));
    o_color = vec4(shaded, 1.0);
    float side = (d.flags & VG_DRAW_RIGHT_EYE) != 0u ? 1.0 : -1.0;
    // Achieved disparity: twice this eye's horizontal offset from the centre view.
    float achieved = 2.0 * side * (gl_FragCoord.x - centre.x);
    float error = 0.0;
#ifdef EYE_MEASURE
    if (u.warp2.z > 0.0)
        error = achieved - vgx_px_from_vergence(vgx_cascade(centre, e_centre_clip.w).x);
#endif
    float stage = 0.0, best = 0.0;
    for (int i = 0; i < 4; i++)
        if (e_stage[i] > best) {
            best = e_stage[i];
            stage = float(i + 1);
        }
    // Eyes move points only horizontally: the centre-view row is this row,
    // so the second channel holds the view depth instead.
    o_aux = vec4(centre.x, e_centre_clip.w, error, stage);
}
