#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
// warp.fill: closes the cracks of the warp. Surfaces that meet without
// sharing vertices (T-junctions, overlapping parts of one object) can part
// by a fraction of a pixel once the target disparity moves them
// differently, and a pixel centre may fall in the seam. Where an eye shows
// sky between one surface's pixels (the same depth on both sides) and the
// centre view shows that surface there, the pixel takes its neighbours'
// mean. Everything else is copied. The same test is the capture's hole
// measure (warp_metrics.c), so a crack two pixels wide stays visible there.
#include "shared.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba8) uniform readonly image2D raw_color;
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D raw_aux;
layout(set = 0, binding = 2, r32ui) uniform readonly uimage2D centre_ids;
layout(set = 0, binding = 3, rgba8) uniform writeonly image2D out_color;
layout(set = 0, binding = 4, rgba32f) uniform writeonly image2D out_aux;

bool geometry(vec4 c) { return c.a > 0.75; }

// Sky at p between a and b (on either side) that should be one surface.
bool torn(ivec2 p, ivec2 a, ivec2 b, ivec2 size)
{
    if (any(lessThan(min(a, b), ivec2(0))) || any(greaterThanEqual(max(a, b), size)))
        return false;
    if (!geometry(imageLoad(raw_color, a)) || !geometry(imageLoad(raw_color, b)))
        return false;
    vec4 xa = imageLoad(raw_aux, a), xb = imageLoad(raw_aux, b);
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
    ivec2 p = ivec2(gl_GlobalInvocationID.xy), size = imageSize(raw_color);
    if (any(greaterThanEqual(p, size)))
        return;
    vec4 c = imageLoad(raw_color, p), x = imageLoad(raw_aux, p);
    if (!geometry(c) && c.a > 0.25) { /* sky, not an empty pixel */
        ivec2 pair[2] = ivec2[2](ivec2(1, 0), ivec2(0, 1));
        for (int k = 0; k < 2; k++) {
            ivec2 a = p - pair[k], b = p + pair[k];
            if (torn(p, a, b, size)) {
                c = 0.5 * (imageLoad(raw_color, a) + imageLoad(raw_color, b));
                x = 0.5 * (imageLoad(raw_aux, a) + imageLoad(raw_aux, b));
                x.w = imageLoad(raw_aux, a).w; /* a stage, not a mean */
                c.a = 1.0;
                break;
            }
        }
    }
    imageStore(out_color, p, c);
    imageStore(out_aux, p, x);
}
