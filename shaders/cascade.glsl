// vergence — the warp's disparity cascade (paper 4.6, Fig. 5): which
// vergence a surface point at centre-view pixel position `px` and view depth
// `z` should get. Needs common.glsl, stereo.glsl and the bindings below.
//   1 direct fetch       the depth map at px holds this surface: depth-aware
//                        bilinear of the target map over the 2x2 taps that do
//   2 neighbourhood      the nearest depth in the 3x3 pixels around px
//   3 Halton             64 samples of the 2D Halton sequence at radius r^2 R
//   4 global curve       depth -> vergence, when nothing nearby matches

layout(set = 0, binding = VG_BINDING_DEPTH) uniform sampler2D depth_map;
layout(set = 0, binding = VG_BINDING_TARGET) uniform sampler2D target_map;
layout(set = 0, binding = VG_BINDING_CURVE, scalar) readonly buffer CurveBlock { vg_curve curve; };

bool same_surface(float map_z, float z)
{
    return abs(map_z - z) < u.warp.z * z;
}

// Linear in inverse depth between bin centres, and continued linearly past
// the covered range (vertices off screen or nearer than any pixel): the
// original g is affine in 1/z, so the continuation is exact for it.
float curve_vergence(float z)
{
    float span = curve.inv_depth_near - curve.inv_depth_far;
    float t = (1.0 / max(z, 1e-6) - curve.inv_depth_far) / max(span, 1e-12) * float(VG_CURVE_BINS) - 0.5;
    const int reach = 16;
    if (t < 0.0)
        return curve.vergence[0] + t * (curve.vergence[reach] - curve.vergence[0]) / float(reach);
    const int last = VG_CURVE_BINS - 1;
    if (t > float(last))
        return curve.vergence[last] + (t - float(last)) * (curve.vergence[last] - curve.vergence[last - reach]) / float(reach);
    int i = min(int(t), VG_CURVE_BINS - 2);
    return mix(curve.vergence[i], curve.vergence[i + 1], t - float(i));
}

float radical_inverse(uint i, uint base)
{
    float inv = 1.0 / float(base), f = inv, r = 0.0;
    while (i > 0u) {
        r += f * float(i % base);
        i /= base;
        f *= inv;
    }
    return r;
}

// x: vergence (arcmin), y: stage (VG_STAGE_*).
vec2 cascade(vec2 px, float z)
{
    ivec2 size = textureSize(depth_map, 0);
    ivec2 p = clamp(ivec2(floor(px)), ivec2(0), size - 1);
    if (same_surface(texelFetch(depth_map, p, 0).r, z)) {
        vec2 t = px - 0.5;
        ivec2 b = ivec2(floor(t));
        vec2 fr = t - vec2(b);
        float wsum = 0.0, vsum = 0.0;
        for (int k = 0; k < 4; k++) {
            ivec2 o = ivec2(k & 1, k >> 1);
            ivec2 q = clamp(b + o, ivec2(0), size - 1);
            float w = (o.x == 1 ? fr.x : 1.0 - fr.x) * (o.y == 1 ? fr.y : 1.0 - fr.y);
            if (w > 0.0 && same_surface(texelFetch(depth_map, q, 0).r, z)) {
                wsum += w;
                vsum += w * texelFetch(target_map, q, 0).r;
            }
        }
        float direct = wsum > 0.0 ? vsum / wsum : texelFetch(target_map, p, 0).r;
        return vec2(direct, float(VG_STAGE_DIRECT));
    }
    float best = 1e30;
    ivec2 best_q = p;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), size - 1);
            float diff = abs(texelFetch(depth_map, q, 0).r - z);
            if (diff < best) {
                best = diff;
                best_q = q;
            }
        }
    if (best < u.warp.z * z)
        return vec2(texelFetch(target_map, best_q, 0).r, float(VG_STAGE_NEIGHBORHOOD));
    for (uint i = 1u; i <= 64u; i++) {
        float r = radical_inverse(i, 2u), a = radical_inverse(i, 3u);
        vec2 s = px + r * r * u.warp.w * vec2(cos(6.2831853 * a), sin(6.2831853 * a));
        ivec2 q = clamp(ivec2(floor(s)), ivec2(0), size - 1);
        float diff = abs(texelFetch(depth_map, q, 0).r - z);
        if (diff < best) {
            best = diff;
            best_q = q;
        }
    }
    if (best < u.warp.z * z)
        return vec2(texelFetch(target_map, best_q, 0).r, float(VG_STAGE_HALTON));
    return vec2(curve_vergence(z), float(VG_STAGE_CURVE));
}

vec2 centre_pixel(vec4 clip)
{
    return (clip.xy / clip.w * 0.5 + 0.5) * u.viewport.xy;
}
