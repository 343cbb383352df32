#version 450
// The example host's eyes: world-space vertices to the tessellator.
layout(location = 0) in vec3 position;
layout(location = 0) out vec3 v_world;

void main()
{
    v_world = position;
}
