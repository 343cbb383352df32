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

// Linear in inverse depth between consecutive bin centroids, and continued
// linearly past the covered range (vertices off screen or nearer than any
// pixel): the original g is affine in 1/z, so the continuation is exact for it.
const int CURVE_REACH = 16; // bins between the two points of an end slope

float curve_between(int a, int b, float q)
{
    float dq = curve.inv_depth[b] - curve.inv_depth[a];
    float t = abs(dq) > 1e-12 ? (q - curve.inv_depth[a]) / dq : 0.0;
    return mix(curve.vergence[a], curve.vergence[b], t);
}

// The segment of the curve that holds inverse depth q: (first bin, second bin).
ivec2 curve_segment(float q)
{
    const int last = VG_CURVE_BINS - 1;
    if (q <= curve.inv_depth[0])
        return ivec2(0, CURVE_REACH);
    if (q >= curve.inv_depth[last])
        return ivec2(last - CURVE_REACH, last);
    float span = curve.inv_depth_near - curve.inv_depth_far;
    int i = clamp(int((q - curve.inv_depth_far) / max(span, 1e-12) * float(VG_CURVE_BINS)), 0, last);
    // The centroid of bin i may lie on either side of q.
    if (q < curve.inv_depth[i])
        i = max(i - 1, 0);
    while (i < last - 1 && q > curve.inv_depth[i + 1])
        i++;
    return ivec2(i, i + 1);
}

float curve_vergence(float z)
{
    float q = 1.0 / max(z, 1e-6);
    ivec2 s = curve_segment(q);
    return curve_between(s.x, s.y, q);
}

// d vergence / d (1/z) of the curve around depth z.
float curve_slope(float z)
{
    ivec2 s = curve_segment(1.0 / max(z, 1e-6));
    float dq = curve.inv_depth[s.y] - curve.inv_depth[s.x];
    return abs(dq) > 1e-12 ? (curve.vergence[s.y] - curve.vergence[s.x]) / dq : 0.0;
}

// d(z) * z in image pixels for points nearer than anything the depth map
// holds, including points behind the camera: the curve's near end continued
// linearly in inverse depth, d = d0 + s (1/z - q0), times z. Affine in z, so
// it stays finite through z = 0, and exact for the original g (affine in 1/z).
float near_disparity_times_depth(float z)
{
    const int last = VG_CURVE_BINS - 1;
    float q0 = curve.inv_depth[last], q1 = curve.inv_depth[last - CURVE_REACH];
    float d0 = px_from_vergence(curve.vergence[last]), d1 = px_from_vergence(curve.vergence[last - CURVE_REACH]);
    float slope = (d0 - d1) / max(q0 - q1, 1e-12);
    return d0 * z + slope * (1.0 - q0 * z);
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

float carried(ivec2 q, float z)
{
    return texelFetch(target_map, q, 0).r + curve_vergence(z) - curve_vergence(texelFetch(depth_map, q, 0).r);
}

// x: vergence (arcmin), y: stage (VG_STAGE_*). Without `halton` a point the
// 3x3 neighbourhood does not resolve goes straight to the curve.
vec2 cascade_stages(vec2 px, float z, bool halton)
{
    ivec2 size = textureSize(depth_map, 0);
    ivec2 p = clamp(ivec2(floor(px)), ivec2(0), size - 1);
    if (same_surface(texelFetch(depth_map, p, 0).r, z)) {
        // Depth-aware bilinear: only taps of this surface, each carried to
        // this point's depth along the curve's local slope (a tap within
        // epsilon may still sit a few centimetres in front or behind, e.g. a
        // window in a wall).
        vec2 t = px - 0.5;
        ivec2 b = ivec2(floor(t));
        vec2 fr = t - vec2(b);
        float slope = curve_slope(z), q = 1.0 / z, wsum = 0.0, vsum = 0.0;
        for (int k = 0; k < 4; k++) {
            ivec2 o = ivec2(k & 1, k >> 1);
            ivec2 tap = clamp(b + o, ivec2(0), size - 1);
            float w = (o.x == 1 ? fr.x : 1.0 - fr.x) * (o.y == 1 ? fr.y : 1.0 - fr.y);
            float zq = texelFetch(depth_map, tap, 0).r;
            if (w > 0.0 && same_surface(zq, z)) {
                wsum += w;
                vsum += w * (texelFetch(target_map, tap, 0).r + slope * (q - 1.0 / zq));
            }
        }
        float direct = wsum > 0.0 ? vsum / wsum : carried(p, z);
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
    // A nearby pixel of the same surface sits at a slightly different depth:
    // carry its vergence over to this depth along the global curve's slope.
    if (best < u.warp.z * z)
        return vec2(carried(best_q, z), float(VG_STAGE_NEIGHBORHOOD));
    if (!halton)
        return vec2(curve_vergence(z), float(VG_STAGE_CURVE));
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
        return vec2(carried(best_q, z), float(VG_STAGE_HALTON));
    return vec2(curve_vergence(z), float(VG_STAGE_CURVE));
}

vec2 cascade(vec2 px, float z) { return cascade_stages(px, z, true); }

vec2 centre_pixel(vec4 clip)
{
    return (clip.xy / clip.w * 0.5 + 0.5) * u.viewport.xy;
}

// The warp of one vertex (paper 4.6): the centre-view clip position moved
// horizontally by half the cascade's disparity, away from the other eye.
// NDC spans 2 over W pixels, so x moves by side * d / W * w. `precise`: the
// vertex shader of flat triangles and the tessellation evaluation shader run
// this on the same corners, and must give the same bits (no contraction
// into fused multiply-adds in one stage and not the other).
vec4 warp_vertex(vec3 world, bool right_eye, out vec4 centre_clip, out vec4 stage_one_hot)
{
    precise vec4 clip = u.view_proj * vec4(world, 1.0);
    centre_clip = clip;
    stage_one_hot = vec4(0.0);
    precise float d_times_w;
    if (clip.w * curve.inv_depth_near > 1.0) {
        vec2 c = cascade(centre_pixel(clip), clip.w);
        d_times_w = px_from_vergence(c.x) * clip.w;
        stage_one_hot[int(c.y) - 1] = 1.0;
    } else {
        // Nearer than every pixel, or behind the camera: only the curve knows.
        d_times_w = near_disparity_times_depth(clip.w);
        stage_one_hot[VG_STAGE_CURVE - 1] = 1.0;
    }
    clip.x += (right_eye ? 1.0 : -1.0) * d_times_w * u.viewport.z;
    return clip;
}
