#version 460
#extension GL_GOOGLE_include_directive : require
// warp.fill.EYE.apply (warp_fill.glsl): each crack takes the mean of the
// pair that closes it (geometry, which no step writes).
#include "warp_fill.glsl"

layout(local_size_x = VG_WORKLIST_GROUP) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= fill_header[pc.slot].x)
        return;
    uint e = fill_list[i], k = e >> 30;
    if (k == FILL_NONE)
        return;
    ivec2 p = fill_pixel(e), a = p - fill_step(k), b = p + fill_step(k);
    vec4 xa = imageLoad(eye_aux, a);
    vec4 c = 0.5 * (imageLoad(eye_color, a) + imageLoad(eye_color, b));
    vec4 x = 0.5 * (xa + imageLoad(eye_aux, b));
    x.w = xa.w; /* a stage, not a mean */
    c.a = 1.0;
    imageStore(eye_color, p, c);
    imageStore(eye_aux, p, x);
}
