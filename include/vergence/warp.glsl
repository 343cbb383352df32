// vergence — the stereo warp for a host's own shaders (paper 4.6; docs/sdk.md
// "The warp"). The stereo pair is the centre view with every vertex moved
// horizontally by half the disparity the target map (f) asks for at it: a
// host tessellates its geometry, displaces each vertex with
// vgx_warp_vertex in its tessellation evaluation (or vertex) shader, and
// draws each eye. The cascade finds a vertex's target (paper Fig. 5):
//   1 direct fetch    the depth map at the vertex's centre-view pixel holds
//                     this surface: depth-aware bilinear of the target map
//   2 neighbourhood   the nearest depth in the 3x3 pixels around it
//   3 Halton          64 samples of the 2D Halton sequence, radius r^2 R
//   4 global curve    depth -> vergence, when nothing nearby matches
//
// Bindings, in set VGX_WARP_SET (define it before including; the SDK fills
// them: vgx_get_warp, vergence.h):
//   VGX_WARP_BINDING_CONSTANTS (0)  uniform block, std140: the centre view's
//                                   view-projection, viewport, rig, display
//                                   and the warp's settings
//   VGX_WARP_BINDING_DEPTH (1)      sampler2D: the centre view's linear depth
//   VGX_WARP_BINDING_TARGET (2)     sampler2D: the target vergence (f), arcmin
//   VGX_WARP_BINDING_CURVE (3)      storage buffer, std430: the global curve
// (the samplers are read with texelFetch only). An includer with its own
// constants defines VGX_CONSTANTS (an instance with the members below) and
// the binding numbers; vergence's engine does.
#ifndef VERGENCE_WARP_GLSL
#define VERGENCE_WARP_GLSL

#ifndef VGX_WARP_BINDING_CONSTANTS
#define VGX_WARP_BINDING_CONSTANTS 0
#endif
#ifndef VGX_WARP_BINDING_DEPTH
#define VGX_WARP_BINDING_DEPTH 1
#endif
#ifndef VGX_WARP_BINDING_TARGET
#define VGX_WARP_BINDING_TARGET 2
#endif
#ifndef VGX_WARP_BINDING_CURVE
#define VGX_WARP_BINDING_CURVE 3
#endif

#ifndef VGX_CONSTANTS
layout(set = VGX_WARP_SET, binding = VGX_WARP_BINDING_CONSTANTS, std140) uniform VgxWarpConstants {
    mat4 view_proj;   // world -> centre-view clip (Vulkan: y down, depth 0..1)
    vec4 viewport;    // width, height, 1 / width, 1 / height: the maps' pixels
    vec4 rig;         // the original rig: gain (image px), convergence (m), interaxial (m), 0
    vec4 display;     // interocular distance (m), viewing distance (m), metres per image pixel, screen vergence
    vec4 warp;        // tessellation: edge length (px, 0 = error-driven), error tolerance (px);
                      // cascade: relative depth difference of one surface, Halton radius (px)
    vec4 warp2;       // largest tessellation level, 0, 0, 0
} vgx_constants;
#define VGX_CONSTANTS vgx_constants
#endif

#include "display.glsl"

#include "warp_shared.h"

layout(set = VGX_WARP_SET, binding = VGX_WARP_BINDING_DEPTH) uniform sampler2D vgx_depth_map;
layout(set = VGX_WARP_SET, binding = VGX_WARP_BINDING_TARGET) uniform sampler2D vgx_target_map;
layout(set = VGX_WARP_SET, binding = VGX_WARP_BINDING_CURVE, std430) readonly buffer VgxCurveBlock {
    vgx_curve_data vgx_curve;
};

#include "curve.h"

bool vgx_same_surface(float map_z, float z)
{
    return abs(map_z - z) < VGX_CONSTANTS.warp.z * z;
}

// The curve's vergence at depth z and its slope there, d vergence / d (1/z),
// from one search.
vec2 vgx_curve_vergence_slope(float z)
{
    float q = 1.0 / max(z, 1e-6);
    vgx_segment s = vgx_curve_segment(q);
    return vec2(vgx_curve_between(s.first, s.second, q), vgx_curve_slope(s));
}

// d(z) * z in image pixels for points nearer than anything the depth map
// holds, including points behind the camera: the curve's near end continued
// linearly in inverse depth, d = d0 + s (1/z - q0), times z. Affine in z, so
// it stays finite through z = 0, and exact for the original g (affine in 1/z).
float vgx_near_disparity_times_depth(float z)
{
    const int last = VGX_CURVE_BINS - 1;
    float q0 = vgx_curve.inv_depth[last], q1 = vgx_curve.inv_depth[last - VGX_CURVE_REACH];
    float d0 = vgx_px_from_vergence(vgx_curve.vergence[last]), d1 = vgx_px_from_vergence(vgx_curve.vergence[last - VGX_CURVE_REACH]);
    float slope = (d0 - d1) / max(q0 - q1, 1e-12);
    return d0 * z + slope * (1.0 - q0 * z);
}

float vgx_radical_inverse(uint i, uint base)
{
    float inv = 1.0 / float(base), f = inv, r = 0.0;
    while (i > 0u) {
        r += f * float(i % base);
        i /= base;
        f *= inv;
    }
    return r;
}

// The Halton search's 64 offsets over its radius: r_i^2 (cos 2 pi a_i,
// sin 2 pi a_i), r_i = vgx_radical_inverse(i, 2), a_i = vgx_radical_inverse(i, 3),
// i = 1 .. 64, to float precision (tests/warp/warp_test.py halton_table
// checks them). A table: a CPU rasteriser runs the search for a whole row
// of lanes when one needs it, and the sines, cosines and radical inverses
// were most of it.
const vec2 VGX_HALTON_OFFSETS[64] = vec2[](
    vec2(-0.125, 0.21650635), vec2(-0.03125, -0.054126587), vec2(0.4309, 0.36156803),
    vec2(-0.014682697, 0.005344065), vec2(0.06783132, -0.38469052), vec2(0.024419274, 0.13848859),
    vec2(-0.71945214, -0.26185918), vec2(0.002992361, -0.0025108892), vec2(0.30787748, 0.072968304),
    vec2(-0.06701578, 0.07103258), vec2(-0.18933494, -0.63242275), vec2(0.020993857, 0.028199643),
    vec2(-0.4694603, 0.05487204), vec2(0.075812146, -0.1757523), vec2(-0.051103853, 0.8774193),
    vec2(-0.00081590604, -0.0005366299), vec2(0.25220686, -0.12666304), vec2(0.07068774, 0.035500716),
    vec2(-0.5099413, 0.33539367), vec2(-0.0014195514, -0.024372758), vec2(0.17057732, 0.39544266),
    vec2(-0.16392313, -0.019159866), vec2(0.49043983, -0.65877503), vec2(-0.0025207317, 0.008419829),
    vec2(-0.24192698, -0.25642762), vec2(0.11497893, -0.027250508), vec2(0.7097733, 0.055167943),
    vec2(-0.027065173, 0.03946199), vec2(-0.22285472, -0.46606112), vec2(0.15686932, 0.15385635),
    vec2(-0.904101, 0.2516737), vec2(6.0898717e-05, -0.00023642334), vec2(0.025739023, 0.2646203),
    vec2(-0.06423215, -0.029197095), vec2(0.47688928, -0.34085998), vec2(0.018831074, 0.0060379407),
    vec2(-0.30391955, 0.2757923), vec2(-0.03230345, -0.14912932), vec2(0.42294464, 0.67104733),
    vec2(-0.0060989256, 0.00023666608), vec2(0.15576503, -0.29571262), vec2(-0.014570582, 0.10667553),
    vec2(-0.54204416, -0.42011595), vec2(0.038195156, -0.015604437), vec2(0.42327586, 0.2554483),
    vec2(-0.1797716, 0.099193774), vec2(0.017616002, -0.90827644), vec2(0.00071132946, 0.0020789388),
    vec2(-0.29346624, -0.057634894), vec2(0.057950493, -0.066403896), vec2(-0.22871637, 0.59239024),
    vec2(-0.018546207, -0.02299369), vec2(0.44599444, -0.06975226), vec2(0.17584097, 0.027501026),
    vec2(-0.53354836, 0.66149616), vec2(-0.0043087667, -0.011159985), vec2(0.2441626, 0.2797793),
    vec2(-0.1267295, 0.024888864), vec2(0.23908573, -0.69875443), vec2(0.0010651976, 0.05492131),
    vec2(-0.47219437, -0.26054582), vec2(0.20087314, -0.12122756), vec2(0.8970211, 0.36647344),
    vec2(-4.824174e-05, 3.739017e-05)
);

// x: vergence (arcmin), y: stage (VGX_STAGE_*). Without `halton` a point the
// 3x3 neighbourhood does not resolve goes straight to the vgx_curve.
//
// Written for CPU rasterisers too, which run every branch under masks and
// every loop at least once: the stages share their work instead of each
// returning early. One curve search gives the vergence and the slope at z,
// the neighbourhood's depths are kept, and one carried value is formed for
// whichever pixel the stages settled on (the direct pixel when no bilinear
// tap qualifies): its target moved to depth z along the curve,
// target + curve(z) - curve(z_pixel). The same operations on the same values
// as stage by stage (equal up to float rounding where a compiler fuses
// multiply-adds differently: docs/warp.md).
vec2 vgx_cascade_stages(vec2 px, float z, bool halton)
{
    ivec2 size = textureSize(vgx_depth_map, 0);
    ivec2 p = clamp(ivec2(floor(px)), ivec2(0), size - 1);
    // The 3x3 neighbourhood's depths (row by row); the centre and the four
    // bilinear taps are among them.
    float zn[9];
    for (int k = 0; k < 9; k++)
        zn[k] = texelFetch(vgx_depth_map, clamp(p + ivec2(k % 3 - 1, k / 3 - 1), ivec2(0), size - 1), 0).r;
    float zp = zn[4];
    bool direct = vgx_same_surface(zp, z);
    vec2 cz = vgx_curve_vergence_slope(z); // vergence, slope
    // Direct: depth-aware bilinear, only taps of this surface, each carried
    // to this point's depth along the curve's local slope (a tap within
    // epsilon may still sit a few centimetres in front or behind, e.g. a
    // window in a wall).
    vec2 t = px - 0.5;
    ivec2 b = ivec2(floor(t));
    vec2 fr = t - vec2(b);
    float q = 1.0 / z, wsum = 0.0, vsum = 0.0;
    for (int k = 0; k < 4; k++) {
        ivec2 o = ivec2(k & 1, k >> 1);
        ivec2 tap = clamp(b + o, ivec2(0), size - 1);
        float w = (o.x == 1 ? fr.x : 1.0 - fr.x) * (o.y == 1 ? fr.y : 1.0 - fr.y);
        // tap - p is in [-1, 1]^2 wherever px is (both are clamped).
        ivec2 c = tap - p + 1;
        vec3 row = c.y == 0 ? vec3(zn[0], zn[1], zn[2]) : c.y == 1 ? vec3(zn[3], zn[4], zn[5])
                                                                  : vec3(zn[6], zn[7], zn[8]);
        float zq = c.x == 0 ? row.x : c.x == 1 ? row.y : row.z;
        if (w > 0.0 && vgx_same_surface(zq, z)) {
            wsum += w;
            vsum += w * (texelFetch(vgx_target_map, tap, 0).r + cz.y * (q - 1.0 / zq));
        }
    }
    // Neighbourhood: a nearby pixel of the same surface sits at a slightly
    // different depth; then (with `halton`) 64 Halton samples within the
    // radius. Either's vergence is carried over to this depth along the
    // global curve.
    float best = 1e30, best_z = zp;
    ivec2 best_q = p;
    for (int k = 0; k < 9; k++) {
        float diff = abs(zn[k] - z);
        if (diff < best) {
            best = diff;
            best_q = clamp(p + ivec2(k % 3 - 1, k / 3 - 1), ivec2(0), size - 1);
            best_z = zn[k];
        }
    }
    bool near = best < VGX_CONSTANTS.warp.z * z;
    for (int i = 0; i < 64 && halton && !direct && !near; i++) {
        vec2 s = px + VGX_CONSTANTS.warp.w * VGX_HALTON_OFFSETS[i];
        ivec2 n = clamp(ivec2(floor(s)), ivec2(0), size - 1);
        float zh = texelFetch(vgx_depth_map, n, 0).r, diff = abs(zh - z);
        if (diff < best) {
            best = diff;
            best_q = n;
            best_z = zh;
        }
    }
    bool found = best < VGX_CONSTANTS.warp.z * z;
    ivec2 from = direct ? p : best_q;
    float carried = texelFetch(vgx_target_map, from, 0).r + cz.x - vgx_curve_vergence(direct ? zp : best_z);
    if (direct)
        return vec2(wsum > 0.0 ? vsum / wsum : carried, float(VGX_STAGE_DIRECT));
    if (found)
        return vec2(carried, float(near ? VGX_STAGE_NEIGHBORHOOD : VGX_STAGE_HALTON));
    return vec2(cz.x, float(VGX_STAGE_CURVE));
}

vec2 vgx_cascade(vec2 px, float z) { return vgx_cascade_stages(px, z, true); }

// vgx_warp_disparity below, with the cascade's Halton search only when
// `halton` (see vgx_cascade_stages). Without it, a point the 3x3
// neighbourhood leaves unresolved comes back at VGX_STAGE_CURVE, as does
// one nearer than the depth map (clip.w * vgx_curve.inv_depth_near <= 1):
// a host can warp the rest, and run the search over only the unresolved
// ones (vergence does: shaders/warp_vertices.comp), with the same bits.
float vgx_warp_disparity_search(vec4 clip, bool halton, out int stage)
{
    precise float d_times_w;
    if (clip.w * vgx_curve.inv_depth_near > 1.0) {
        vec2 c = vgx_cascade_stages(vgx_centre_pixel(clip), clip.w, halton);
        d_times_w = vgx_px_from_vergence(c.x) * clip.w;
        stage = int(c.y);
    } else {
        // Nearer than every pixel, or behind the camera: only the curve knows.
        d_times_w = vgx_near_disparity_times_depth(clip.w);
        stage = VGX_STAGE_CURVE;
    }
    return d_times_w;
}

// The disparity of one vertex as the warp adds it (image pixels times the
// centre view's clip w) and its cascade stage (VGX_STAGE_*), from its
// centre-view clip position: the part of vgx_warp_vertex that is the same
// for both eyes. A host that draws both eyes from one vertex buffer can
// compute it once a frame per vertex (vergence does, in a compute pass) and
// move each eye's copy with vgx_warp_shift: the same bits as
// vgx_warp_vertex. `precise`: the vertex shader of flat triangles, the
// tessellation evaluation shader and a compute pass run this on the same
// corners, and must give the same bits (no contraction into fused
// multiply-adds in one stage and not another).
float vgx_warp_disparity(vec4 clip, out int stage) { return vgx_warp_disparity_search(clip, true, stage); }

// One eye's clip position: the centre view's moved horizontally by half the
// disparity, away from the other eye. NDC spans 2 over W pixels, so x moves
// by side * d / W * w.
vec4 vgx_warp_shift(vec4 centre_clip, float d_times_w, bool right_eye)
{
    precise vec4 clip = centre_clip;
    clip.x += (right_eye ? 1.0 : -1.0) * d_times_w * VGX_CONSTANTS.viewport.z;
    return clip;
}

// The warp of one vertex (paper 4.6): vgx_warp_disparity, then
// vgx_warp_shift for this eye.
vec4 vgx_warp_vertex(vec3 world, bool right_eye, out vec4 centre_clip, out vec4 stage_one_hot)
{
    precise vec4 clip = VGX_CONSTANTS.view_proj * vec4(world, 1.0);
    centre_clip = clip;
    int stage;
    float d_times_w = vgx_warp_disparity(clip, stage);
    stage_one_hot = vec4(0.0);
    stage_one_hot[stage - 1] = 1.0;
    return vgx_warp_shift(clip, d_times_w, right_eye);
}

float vgx_target_px(vec3 world, out bool seen)
{
    vec4 c = VGX_CONSTANTS.view_proj * vec4(world, 1.0);
    seen = false;
    if (c.w * vgx_curve.inv_depth_near <= 1.0)
        return vgx_near_disparity_times_depth(c.w) / max(c.w, 1e-6);
    vec2 px = vgx_centre_pixel(c);
    ivec2 p = ivec2(floor(px)), size = textureSize(vgx_depth_map, 0);
    vec2 v = vgx_cascade_stages(px, c.w, false);
    seen = all(greaterThanEqual(p, ivec2(0))) && all(lessThan(p, size)) && v.y < float(VGX_STAGE_CURVE);
    return vgx_px_from_vergence(v.x);
}

// Samples along a long edge for the error-driven level. Keep the arrays
// small: with 49 samples lavapipe drew long garbage triangles (silently).
const int VGX_EDGE_SAMPLES = 24;

// The part of vgx_edge_level before it samples the edge: the canonical
// endpoint order, the part in front of the camera, the level when no
// sampling decides it (returned, > 0), else 0 and what the sampling needs:
// the clip positions, the largest level and the number of segments m (6, 12
// or VGX_EDGE_SAMPLES). A host that levels many edges at once can sort them
// by m first (vergence does: rows of lanes then sample alike).
float vgx_edge_prepare(inout vec3 a, inout vec3 b, out vec4 ca, out vec4 cb, out float max_level, out int m)
{
    // The same edge seen from both of its triangles must get the same level
    // (no cracks): evaluate it in a canonical endpoint order.
    if (a.x > b.x || (a.x == b.x && (a.y > b.y || (a.y == b.y && a.z > b.z)))) {
        vec3 t = a;
        a = b;
        b = t;
    }
    ca = VGX_CONSTANTS.view_proj * vec4(a, 1.0);
    cb = VGX_CONSTANTS.view_proj * vec4(b, 1.0);
    max_level = 1.0;
    m = 0;
    float near_w = 1e-3;
    if (ca.w < near_w && cb.w < near_w)
        return 1.0;
    // Measure the part in front of the camera (clip space is linear in world space).
    if (ca.w < near_w) {
        float k = (near_w - ca.w) / (cb.w - ca.w);
        ca = mix(ca, cb, k);
        a = mix(a, b, k);
    }
    if (cb.w < near_w) {
        float k = (near_w - cb.w) / (ca.w - cb.w);
        cb = mix(cb, ca, k);
        b = mix(b, a, k);
    }
    float len = distance(vgx_centre_pixel(ca), vgx_centre_pixel(cb));
    if (len <= 1.0)
        return 1.0; /* a pixel or less: nothing to gain */
    max_level = min(ceil(len), VGX_CONSTANTS.warp2.x);
    if (VGX_CONSTANTS.warp.x > 0.0)
        return clamp(ceil(len / VGX_CONSTANTS.warp.x), 1.0, VGX_CONSTANTS.warp2.x);
    m = len <= 12.0 ? 6 : len <= 24.0 ? 12 : VGX_EDGE_SAMPLES;
    return 0.0;
}

// Error-driven: between its vertices the warp interpolates disparity
// linearly in screen space (perspective-correct interpolation of d w over
// w). The target need not be smooth at any scale the mesh knows (operator
// kinks, the solver's coarse grid), so sample the edge about every two
// pixels (m samples, from vgx_edge_prepare) and take the fewest equal
// segments whose vertices, interpolated, stay within the tolerance at every
// sample inside them; m is a multiple of every level tried, so segment ends
// are samples. An edge no level fits gets the 1-pixel level.
float vgx_edge_sampled(vec3 a, vec3 b, vec4 ca, vec4 cb, float max_level, int m)
{
    float d[VGX_EDGE_SAMPLES + 1];
    uint seen = 0u; /* bit i: sample i is on a surface the warp measures */
    for (int i = 0; i <= m; i++) {
        bool s;
        d[i] = vgx_target_px(mix(a, b, float(i) / float(m)), s);
        seen |= s ? 1u << i : 0u;
    }
    const int LEVELS[7] = int[7](1, 2, 3, 4, 6, 8, 12);
    float level = 1.0, err = 0.0;
    for (int k = 0; k < 7; k++) {
        int l = LEVELS[k], step = m / l;
        if (float(l) >= max_level || step < 2)
            break;
        if (m % l != 0)
            continue;
        level = float(l);
        err = 0.0;
        for (int i = 0; i < m; i += step) {
            float w0 = mix(ca.w, cb.w, float(i) / float(m)), w1 = mix(ca.w, cb.w, float(i + step) / float(m));
            for (int j = 1; j < step; j++) {
                float t = float(j) / float(step);
                float s = t * w1 / mix(w0, w1, t); /* screen-space parameter of 3D t */
                if ((seen & (1u << (i + j))) != 0u)
                    err = max(err, abs(d[i + j] - mix(d[i], d[i + step], s)));
            }
        }
        if (err <= VGX_CONSTANTS.warp.y)
            return level;
    }
    // No level fits: past the sampling the error falls about linearly with
    // the segment length (the targets bend sharply: operator kinks).
    return clamp(ceil(level * err / VGX_CONSTANTS.warp.y), level + 1.0, max_level);
}

// The tessellation level of the edge a-b (world positions), the same from
// both triangles that share it.
float vgx_edge_level(vec3 a, vec3 b)
{
    vec4 ca, cb;
    float max_level;
    int m;
    float level = vgx_edge_prepare(a, b, ca, cb, max_level, m);
    return level > 0.0 ? level : vgx_edge_sampled(a, b, ca, cb, max_level, m);
}

bool vgx_patch_outside(vec4 c0, vec4 c1, vec4 c2)
{
    // Keep a margin for the horizontal eye shift.
    float m = 1.3;
    if (c0.w <= 0.0 && c1.w <= 0.0 && c2.w <= 0.0) return true;
    if (c0.x > m * c0.w && c1.x > m * c1.w && c2.x > m * c2.w) return true;
    if (c0.x < -m * c0.w && c1.x < -m * c1.w && c2.x < -m * c2.w) return true;
    if (c0.y > c0.w && c1.y > c1.w && c2.y > c2.w) return true;
    if (c0.y < -c0.w && c1.y < -c1.w && c2.y < -c2.w) return true;
    return false;
}


// A point on an edge of the patch comes from that edge alone: its two
// endpoints in the canonical order of tess_levels.glsl (the order the level
// was decided in) and the exact fraction k / level of equal spacing. The
// triangle on the other side of the edge computes the same bits, so it
// displaces the same vertex by the same disparity: the warp is watertight by
// construction, whatever the level and the target. (From barycentric
// weights the two triangles sum the endpoints in different orders, and the
// last bits differ; where the cascade steps between depth taps, a last bit
// can step the disparity.)
vec3 vgx_edge_point(vec3 a, vec3 b, float weight_b, float level)
{
    float k = round(weight_b * level);
    if (k <= 0.0)
        return a;
    if (k >= level)
        return b;
    if (a.x > b.x || (a.x == b.x && (a.y > b.y || (a.y == b.y && a.z > b.z)))) {
        vec3 t = a;
        a = b;
        b = t;
        k = level - k;
    }
    precise vec3 p = a + (b - a) * (k / level);
    return p;
}


// The point of a tessellated triangle p0 p1 p2 at barycentric b
// (gl_TessCoord, equal_spacing) with the outer levels the control shader
// set (outer[i] is the edge opposite vertex i, as vgx_edge_level gave it):
// on an edge, from that edge alone, so neighbouring patches agree bit for bit.
vec3 vgx_tess_point(vec3 p0, vec3 p1, vec3 p2, vec3 b, float outer0, float outer1, float outer2)
{
    precise vec3 world;
    if (b.x == 0.0)
        world = vgx_edge_point(p1, p2, b.z, outer0);
    else if (b.y == 0.0)
        world = vgx_edge_point(p2, p0, b.x, outer1);
    else if (b.z == 0.0)
        world = vgx_edge_point(p0, p1, b.y, outer2);
    else
        world = b.x * p0 + b.y * p1 + b.z * p2;
    return world;
}

#endif
