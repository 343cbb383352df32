#version 460
#extension GL_GOOGLE_include_directive : require
// warp.fill.EYE.find, after .reset (warp_fill.glsl): the candidates, five loads a pixel.
#include "warp_fill.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
// 1: only zero the eye's count and dispatch size (one invocation, before the
// pass counts).
layout(constant_id = 0) const uint RESET = 0u;

bool between_geometry(ivec2 p, ivec2 d, ivec2 size)
{
    ivec2 a = p - d, b = p + d;
    return fill_inside(a, b, size) && geometry(imageLoad(eye_color, a)) && geometry(imageLoad(eye_color, b));
}

void main()
{
    if (RESET != 0u) {
        if (gl_LocalInvocationIndex == 0u)
            fill_header[pc.slot] = VG_WORKLIST_EMPTY;
        return;
    }
    ivec2 p = ivec2(gl_GlobalInvocationID.xy), size = imageSize(eye_color);
    if (any(greaterThanEqual(p, size)))
        return;
    vec4 c = imageLoad(eye_color, p);
    if (geometry(c) || c.a <= 0.25) // only sky, not an empty pixel
        return;
    if (between_geometry(p, ivec2(1, 0), size) || between_geometry(p, ivec2(0, 1), size)) {
        uint i;
        VG_WORKLIST_APPEND(fill_header[pc.slot], i);
        fill_list[i] = uint(p.x) | uint(p.y) << 16;
    }
}
