#version 460
#extension GL_GOOGLE_include_directive : require
// vgx.eyes.color: the centre pixel that is nearest in an eye pixel gives it
// its colour (alpha 1: a surface).
#include "eyes.glsl"

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(pc.width))
        return;
    uint eye = gl_GlobalInvocationID.z;
    float z = imageLoad(depth_map, p).r;
    uint key = floatBitsToUint(max(z, 0.0));
    ivec2 s = eyes_span(p, eye == 1u ? 1.0 : -1.0, z);
    vec3 c = texelFetch(color_map, p, 0).rgb;
    for (int x = s.x; x < s.y; x++)
        if (nearest[eyes_index(eye, ivec2(x, p.y))] == key)
            eyes_store(eye, ivec2(x, p.y), vec4(c, 1.0));
}
