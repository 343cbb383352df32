#version 450
// What vgx_dispatch reads: linear depth (metres along the view axis),
// saliency (alpha), motion in pixels to the two other times, object id.
layout(set = 0, binding = 0) uniform View {
    mat4 vp, vp_prev, vp_next;
    vec4 view_z;
    vec4 viewport;
} v;
layout(push_constant) uniform Push {
    float saliency;
    uint id;
} pc;
layout(location = 0) in float view_depth;
layout(location = 1) in vec4 clip_prev;
layout(location = 2) in vec4 clip_next;
layout(location = 0) out float depth;
layout(location = 1) out vec4 saliency;
layout(location = 2) out vec4 motion;
layout(location = 3) out uint id;

vec2 to_pixels(vec4 clip)
{
    return (clip.xy / clip.w * 0.5 + 0.5) * v.viewport.xy;
}

void main()
{
    depth = view_depth;
    saliency = vec4(0.0, 0.0, 0.0, pc.saliency);
    motion = vec4(to_pixels(clip_prev) - gl_FragCoord.xy, to_pixels(clip_next) - gl_FragCoord.xy);
    id = pc.id;
}
