#version 460
#extension GL_GOOGLE_include_directive : require
// mid.upsample.space: joint bilateral upsampling (Kopf et al. 2007) of the
// frame's coarse ratio, guided by the full-resolution h: tent weights over
// the 2 x 2 coarse samples around each pixel (exact at the samples), the
// 4 x 4 Gaussian when none of them is on the pixel's surface; f = clamp(h R,
// the solve's range) (disp_upsample_spatial()). Every detail of h finer than
// the grid stays.
#include "mid_upsample.glsl"
layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D h_image;
layout(set = 0, binding = 1, scalar) readonly buffer PublishedBlock { mid_published pub; float pub_ratio[]; };
// An image, not a buffer: a CPU rasteriser loads a storage buffer at a
// varying index lane by lane, an image with one gather (docs/PERFORMANCE.md).
layout(set = 0, binding = 2, r32f) uniform readonly image2D ratio_image; // the coarse grid
layout(set = 0, binding = 3, r32f) uniform writeonly image2D f_image;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(up.full_w) || p.y >= int(up.full_h))
        return;
    float hv = imageLoad(h_image, p).r;
    float s2 = float(up.stride / 2u), inv_s = 1.0 / float(up.stride);
    float cx = (float(p.x) - s2) * inv_s, cy = (float(p.y) - s2) * inv_s;
    float tx = min(max(cx, 0.0), float(up.nx - 1u)), ty = min(max(cy, 0.0), float(up.ny - 1u));
    int x0 = int(floor(tx)), y0 = int(floor(ty));
    int x1 = x0 + 1 < int(up.nx) ? x0 + 1 : x0, y1 = y0 + 1 < int(up.ny) ? y0 + 1 : y0;
    float fx = tx - float(x0), fy = ty - float(y0), tacc = 0.0, tsum = 0.0;
    for (int t = 0; t < 4; t++) {
        int qx = (t & 1) != 0 ? x1 : x0, qy = (t & 2) != 0 ? y1 : y0;
        float b = ((t & 1) != 0 ? fx : 1.0 - fx) * ((t & 2) != 0 ? fy : 1.0 - fy);
        float dr = hv - imageLoad(h_image, ivec2(grid_px(qx), grid_py(qy))).r;
        float w = b * exp(-dr * dr * up.inv_2sr);
        tacc += w * imageLoad(ratio_image, ivec2(qx, qy)).r;
        tsum += w;
    }
    int bx = int(floor(cx)) - 1, by = int(floor(cy)) - 1;
    float acc = 0.0, wsum = 0.0, best_d = 1e30, best_r = 1.0;
    for (int j = 0; j < 4 && tsum < MID_TENT_MIN_WEIGHT; j++) {
        int qy = by + j;
        if (qy < 0 || qy >= int(up.ny))
            continue;
        for (int k = 0; k < 4; k++) {
            int qx = bx + k;
            if (qx < 0 || qx >= int(up.nx))
                continue;
            float dx = cx - float(qx), dy = cy - float(qy), d2 = dx * dx + dy * dy;
            // The guide of a coarse sample is h at its full-resolution pixel.
            float dr = hv - imageLoad(h_image, ivec2(grid_px(qx), grid_py(qy))).r;
            float w = exp(-d2 * up.inv_2ss - dr * dr * up.inv_2sr);
            float r = imageLoad(ratio_image, ivec2(qx, qy)).r;
            acc += w * r;
            wsum += w;
            if (d2 < best_d) {
                best_d = d2;
                best_r = r;
            }
        }
    }
    // No neighbour on this surface (a structure thinner than the grid): the
    // nearest sample's correction.
    float f = hv * (tsum >= MID_TENT_MIN_WEIGHT ? tacc / tsum : wsum > 1e-20 ? acc / wsum : best_r);
    if (pub.range_hi > pub.range_lo)
        f = min(max(f, pub.range_lo), pub.range_hi);
    imageStore(f_image, p, vec4(f));
}
