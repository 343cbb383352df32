#include "common.glsl"
#include "lighting.glsl"
#include "disparity/mid_shared.h"

layout(push_constant, scalar) uniform DrawBlock { vg_draw_push d; };
// 1: no authored saliency, the G-buffer computes it (scene_gpu's
// computed_saliency). A specialisation constant: a CPU rasteriser would run
// the computation under masks for every fragment of a scene that has its own.
layout(constant_id = 0) const uint SALIENCY_COMPUTED = 0u;
layout(set = 0, binding = VG_BINDING_SHADOW) uniform sampler2DShadow shadow_map;
layout(set = 1, binding = 0) uniform sampler2D textures[VG_MAX_TEXTURES];

#include "shade.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec2 v_uv;
layout(location = 3) in vec4 v_color;
layout(location = 4) in vec4 v_clip_prev;
layout(location = 5) in vec4 v_clip_next;
layout(location = 6) in float v_view_depth;

layout(location = VG_GBUFFER_COLOR) out vec4 o_color;
layout(location = VG_GBUFFER_DEPTH) out float o_depth;
layout(location = VG_GBUFFER_ID) out uint o_id;
layout(location = VG_GBUFFER_MOTION) out vec4 o_motion;

vec2 to_pixels(vec4 clip)
{
    return (clip.xy / clip.w * 0.5 + 0.5) * u.viewport.xy;
}

void main()
{
    vec2 here = gl_FragCoord.xy;
    o_motion = vec4(to_pixels(v_clip_prev) - here, to_pixels(v_clip_next) - here);
    o_depth = v_view_depth;
    o_id = d.instance_id;
    float saliency = d.saliency;
    if (SALIENCY_COMPUTED != 0u) {
        // No authored saliency: computed from the surface's colour, motion
        // and depth (mid_shared.h, the CPU's formula). Speed: the larger of
        // the motions to the neighbouring keyframes, over the image width
        // (a keyframe tile's width is its own: the same fraction).
        vec3 c = surface_base_color(v_color, v_uv).rgb;
        float de = disp_delta_e(c.r, c.g, c.b, u.saliency.r, u.saliency.g, u.saliency.b);
        float speed = max(length(o_motion.xy), length(o_motion.zw)) * u.viewport.z;
        saliency = disp_saliency_computed(de, speed, v_view_depth, u.saliency.w);
    }
#ifdef GBUFFER_UNLIT
    // The stereo frame's centre pass: the eyes shade themselves, so only
    // depth, ids, saliency and motion matter here (paper 4.6: the first pass
    // "creates only a linear depth map").
    o_color = vec4(0.0, 0.0, 0.0, saliency);
#else
    vec4 base = surface_base_color(v_color, v_uv);
    o_color = vec4(shade_surface(v_world, v_normal, gl_FrontFacing, base), saliency);
#endif
}
