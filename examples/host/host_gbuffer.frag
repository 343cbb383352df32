#version 450
// Linear depth (metres along the view axis) and saliency (alpha): what
// vgx_dispatch reads.
layout(push_constant) uniform Push {
    mat4 view_proj;
    vec4 view_z;    // the view matrix's row that gives view-space z
    float saliency;
} pc;
layout(location = 0) in float view_depth;
layout(location = 0) out float depth;
layout(location = 1) out vec4 saliency;

void main()
{
    depth = view_depth;
    saliency = vec4(0.0, 0.0, 0.0, pc.saliency);
}
