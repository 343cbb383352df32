#version 460
#extension GL_GOOGLE_include_directive : require
// mid.upsample.time: the ratio f / h at the coarse samples of this frame,
// from the two nearest keyframes along the motion (the G-buffer's exact
// motion to the previous and next keyframe), each keyframe's correction
// m = f / g and its slope sampled bilinearly over the taps on the sample's
// surface as the solver's links decide it (its instance, and its depth or
// its trajectory), interpolated by cubic Hermite in time (C1 at keyframes)
// and applied to this frame's g (mid_ratio_to_h); a keyframe that fails
// (occluded, out of frame) drops out (disp_upsample_temporal()).
#include "mid_upsample.glsl"
layout(local_size_x = 64) in;
layout(set = 0, binding = 0, r32f) uniform readonly image2D depth_image;
layout(set = 0, binding = 1, rgba32f) uniform readonly image2D motion_image;
layout(set = 0, binding = 2) readonly buffer StoreBlock { float store[]; };
layout(set = 0, binding = 3, scalar) readonly buffer PublishedBlock { mid_published pub; float pub_ratio[]; };
layout(set = 0, binding = 4, r32f) uniform writeonly image2D ratio_image; // the coarse grid
layout(set = 0, binding = 5, r32ui) uniform readonly uimage2D id_image;
layout(set = 0, binding = 6, r32f) uniform readonly image2D g_image;
layout(set = 0, binding = 7, r32f) uniform readonly image2D h_image;

const float LOST = -1.0e30;

// One step of disp_flow_advect() from a pixel centre: lost (LOST) when the
// target leaves the frame by more than half a pixel, else clamped into it.
vec2 advect(ivec2 x, vec2 m)
{
    vec2 p = vec2(x) + m;
    if (!(p.x >= -0.5 && p.x <= float(up.full_w) - 0.5 && p.y >= -0.5 && p.y <= float(up.full_h) - 0.5))
        return vec2(LOST);
    return vec2(min(max(p.x, 0.0), float(up.full_w - 1u)), min(max(p.y, 0.0), float(up.full_h - 1u)));
}

float key_ratio(uint slot, int q) { return pub_ratio[slot * up.nx * up.ny + uint(q)]; }
float key_slope(uint slot, int q) { return pub_ratio[(up.store_cap + slot) * up.nx * up.ny + uint(q)]; }
float key_depth(uint slot, int q)
{
    return store[slot * MID_STORE_FLOATS * up.nx * up.ny + MID_STORE_DEPTH * up.nx * up.ny + uint(q)];
}

float key_field(uint slot, uint field, uint i)
{
    return store[slot * MID_STORE_FLOATS * up.nx * up.ny + field * up.nx * up.ny + i];
}

// The keyframe's ratio f / h at tap q (its correction through its own g and
// h; the correction itself under the causal gate).
float key_ratio_to_h(uint slot, int q)
{
    return pub.of_h != 0u ? key_ratio(slot, q)
                          : mid_ratio_to_h(key_ratio(slot, q), key_field(slot, MID_STORE_G, uint(q)),
                                           key_field(slot, MID_STORE_H, uint(q)));
}

// The keyframe's correction f / g, weight, slope of f / g and ratio f / h
// at a full-resolution position: bilinear over the coarse samples, keeping
// only taps on the sample's surface: its instance id, and its depth or its
// trajectory (its own flow to the interval's other keyframe, forward from
// k0, backward from k1, lands at `other`, the sample's position there; LOST:
// none) (sample_keyframe()).
vec4 sample_keyframe(vec2 pos, float z, float id, vec2 other, uint slot, bool forward, bool test)
{
    if (pos.x == LOST)
        return vec4(1.0, 0.0, 0.0, 1.0);
    float s2 = float(up.stride / 2u);
    float cx = min(max((pos.x - s2) / float(up.stride), 0.0), float(up.nx - 1u));
    float cy = min(max((pos.y - s2) / float(up.stride), 0.0), float(up.ny - 1u));
    int x0 = int(cx), y0 = int(cy);
    float fx = cx - float(x0), fy = cy - float(y0);
    float acc = 0.0, wsum = 0.0, sacc = 0.0, racc = 0.0;
    for (int t = 0; t < 4; t++) {
        int x = x0 + (t & 1), y = y0 + (t >> 1);
        float w = ((t & 1) != 0 ? fx : 1.0 - fx) * ((t >> 1) != 0 ? fy : 1.0 - fy);
        if (w <= 0.0 || x >= int(up.nx) || y >= int(up.ny))
            continue;
        int q = y * int(up.nx) + x;
        if (test) {
            float d = key_depth(slot, q);
            bool same_depth = z > 0.0 && d > 0.0 && abs(log(d / z)) <= up.log_tol;
            uint fl = forward ? MID_STORE_FLOW_F : MID_STORE_FLOW_B;
            bool on_path = other.x != LOST &&
                           mid_on_trajectory(float(x), float(y), key_field(slot, fl, 2u * uint(q)),
                                             key_field(slot, fl, 2u * uint(q) + 1u), (other.x - s2) / float(up.stride),
                                             (other.y - s2) / float(up.stride)) != 0u;
            bool keep = up.depth_only != 0u ? same_depth
                                             : key_field(slot, MID_STORE_ID, uint(q)) == id && (same_depth || on_path);
            if (!keep)
                continue;
        }
        acc += w * key_ratio(slot, q);
        sacc += w * key_slope(slot, q);
        racc += w * key_ratio_to_h(slot, q);
        wsum += w;
    }
    return wsum > 0.0 ? vec4(acc / wsum, wsum, sacc / wsum, racc / wsum) : vec4(1.0, 0.0, 0.0, 1.0);
}

// The ratio f / h of this frame at the sample, from the correction m (f / g;
// f / h already under the causal gate).
void store_ratio(ivec2 c, ivec2 x, float m)
{
    float r = pub.of_h != 0u ? m : mid_ratio_to_h(m, imageLoad(g_image, x).r, imageLoad(h_image, x).r);
    imageStore(ratio_image, c, vec4(r));
}

void main()
{
    int q = int(gl_GlobalInvocationID.x);
    if (q >= int(up.nx * up.ny))
        return;
    ivec2 c = ivec2(q % int(up.nx), q / int(up.nx)), x = ivec2(grid_px(c.x), grid_py(c.y));
    float z = imageLoad(depth_image, x).r, id = float(imageLoad(id_image, x).r);
    vec4 m = imageLoad(motion_image, x);
    // At a keyframe only k0 counts, at the sample itself.
    vec2 pos0 = up.at_key != 0u ? vec2(x) : advect(x, m.xy);
    vec2 pos1 = up.at_key != 0u ? vec2(LOST) : advect(x, m.zw);
    bool has1 = up.has1 != 0u && up.at_key == 0u;
    // At a keyframe (no k1) the sample itself: depth and id alone.
    vec2 other1 = has1 && up.tau > 0.0 ? pos1 : vec2(LOST);
    vec4 a = sample_keyframe(pos0, z, id, other1, up.slot0, true, true);
    vec4 b = vec4(1.0, 0.0, 0.0, 1.0);
    if (has1 && up.tau > 0.0)
        b = sample_keyframe(pos1, z, id, pos0, up.slot1, false, true);
    // Fig. 4: interpolate f / g along the flow in time and apply it to this
    // frame's g; one keyframe alone when the other fails (none of its taps
    // is the sample's surface, or it is out of frame), its f / h (a constant
    // f / g would hold the manipulation's change over the interval).
    bool ok0 = a.y > 0.0 && up.tau < 1.0, ok1 = b.y > 0.0 && up.tau > 0.0;
    if (ok0 && ok1) {
        store_ratio(c, x, mid_hermite(a.x, a.z, b.x, b.z, up.tau, up.span));
        return;
    }
    if (ok0 && up.tau == 0.0) { // at the keyframe itself: its f / g on this frame's g, as either side
        store_ratio(c, x, a.x);
        return;
    }
    if (ok0 || ok1) {
        imageStore(ratio_image, c, vec4(ok0 ? a.w : b.w));
        return;
    }
    // Both lost (disocclusion, or out of frame for both): the temporally
    // nearer keyframe's ratio f / h at the tracked position, else at the
    // sample itself, whatever surface it shows there.
    bool near0 = up.tau < 0.5 || !has1;
    vec2 pos = near0 ? pos0 : pos1;
    if (pos.x == LOST)
        pos = vec2(x);
    vec4 k = sample_keyframe(pos, z, id, vec2(LOST), near0 ? up.slot0 : up.slot1, near0, false);
    imageStore(ratio_image, c, vec4(k.w));
}
