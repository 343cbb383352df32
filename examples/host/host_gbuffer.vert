#version 450
// The example host's G-buffer: world-space positions, one push block.
layout(location = 0) in vec3 position;
layout(push_constant) uniform Push {
    mat4 view_proj;
    vec4 view_z;    // the view matrix's row that gives view-space z
    float saliency;
} pc;
layout(location = 0) out float view_depth;

void main()
{
    gl_Position = pc.view_proj * vec4(position, 1.0);
    view_depth = -dot(pc.view_z, vec4(position, 1.0));
}
