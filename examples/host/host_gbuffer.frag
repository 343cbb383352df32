#version 450
// What vgx_dispatch reads: linear depth (metres along the view axis),
// saliency (alpha), motion in pixels to the two other times, object id;
// and the shaded centre view the SDK's own eyes move (VGX_CONTEXT_EYES),
// shaded as host_eye.frag shades the warped eyes.
layout(set = 0, binding = 0) uniform View {
    mat4 vp, vp_prev, vp_next;
    vec4 view_z;
    vec4 viewport;
} v;
layout(push_constant) uniform Push {
    vec4 color;
    float saliency;
    uint id;
} pc;
layout(location = 0) in float view_depth;
layout(location = 1) in vec4 clip_prev;
layout(location = 2) in vec4 clip_next;
layout(location = 3) in vec3 world;
layout(location = 0) out float depth;
layout(location = 1) out vec4 saliency;
layout(location = 2) out vec4 motion;
layout(location = 3) out uint id;
layout(location = 4) out vec4 shaded;

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
    vec3 n = normalize(cross(dFdx(world), dFdy(world)));
    vec3 sun = normalize(vec3(0.4, 0.8, 0.3));
    float light = 0.35 + 0.65 * abs(dot(n, sun));
    float fog = 1.0 - exp(-0.01 * view_depth);
    shaded = vec4(mix(pc.color.rgb * light, vec3(0.78, 0.86, 0.95), fog), 1.0);
}
