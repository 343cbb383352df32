#version 460
layout(location = 0) in vec4 v_color;
layout(location = 0) out vec4 o_color;
layout(location = 1) out vec4 o_aux;
void main()
{
    o_color = v_color;
    o_aux = vec4(-1.0, 0.0, 0.0, 0.0);
}
