#version 450
// The example host's G-buffer: world-space positions at the render's time
// and at the two times its motion goes to.
layout(set = 0, binding = 0) uniform View {
    mat4 vp, vp_prev, vp_next;
    vec4 view_z;   // the view matrix's row that gives view-space z
    vec4 viewport; // the render target's viewport, pixels
} v;
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 position_prev;
layout(location = 2) in vec3 position_next;
layout(location = 0) out float view_depth;
layout(location = 1) out vec4 clip_prev;
layout(location = 2) out vec4 clip_next;
layout(location = 3) out vec3 world;

void main()
{
    gl_Position = v.vp * vec4(position, 1.0);
    clip_prev = v.vp_prev * vec4(position_prev, 1.0);
    clip_next = v.vp_next * vec4(position_next, 1.0);
    view_depth = -dot(v.view_z, vec4(position, 1.0));
    world = position;
}
