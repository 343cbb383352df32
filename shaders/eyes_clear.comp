#version 460
#extension GL_GOOGLE_include_directive : require
// vgx.eyes.clear: nothing has landed in either eye.
#include "eyes.glsl"

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(pc.width))
        return;
    nearest[eyes_index(gl_GlobalInvocationID.z, p)] = EYES_EMPTY;
}
