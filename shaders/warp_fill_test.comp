#version 460
#extension GL_GOOGLE_include_directive : require
// warp.fill.EYE.test (warp_fill.glsl): the whole test on each candidate.
#include "warp_fill.glsl"

layout(local_size_x = VG_WORKLIST_GROUP) in;

// Sky at p between a and b that should be one surface.
bool torn(ivec2 p, ivec2 a, ivec2 b, ivec2 size)
{
    if (!fill_inside(a, b, size) || !geometry(imageLoad(eye_color, a)) || !geometry(imageLoad(eye_color, b)))
        return false;
    vec4 xa = imageLoad(eye_aux, a), xb = imageLoad(eye_aux, b);
    if (abs(xa.y - xb.y) >= 0.02 * max(xa.y, xb.y))
        return false;
    int xc = int(round(0.5 * (xa.x + xb.x) - 0.5));
    if (xc < 1 || xc + 1 >= size.x)
        return false;
    return imageLoad(centre_ids, ivec2(xc - 1, p.y)).r != 0u && imageLoad(centre_ids, ivec2(xc, p.y)).r != 0u &&
           imageLoad(centre_ids, ivec2(xc + 1, p.y)).r != 0u;
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= fill_header[pc.slot].x)
        return;
    uint e = fill_list[i];
    ivec2 p = fill_pixel(e), size = imageSize(eye_color);
    uint k = FILL_NONE;
    for (uint j = 0u; j < 2u && k == FILL_NONE; j++)
        if (torn(p, p - fill_step(j), p + fill_step(j), size))
            k = j;
    fill_list[i] = e | k << 30;
}
