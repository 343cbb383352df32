#version 460
#extension GL_GOOGLE_include_directive : require
// vgx.eyes.depth: each centre pixel's depth into the eye pixels it covers,
// the nearest kept.
#include "eyes.glsl"

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(pc.width))
        return;
    uint eye = gl_GlobalInvocationID.z;
    float z = imageLoad(depth_map, p).r;
    ivec2 s = eyes_span(p, eye == 1u ? 1.0 : -1.0, z);
    for (int x = s.x; x < s.y; x++)
        atomicMin(nearest[eyes_index(eye, ivec2(x, p.y))], floatBitsToUint(max(z, 0.0)));
}
