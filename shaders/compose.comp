#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
// compose: packs the two eyes into one output image (DESIGN.md step 10).
// Eyes and output are RGBA8 UNORM holding sRGB-encoded values, so every
// mode but the anaglyphs and the half-size ones copies bytes exactly (the
// half-size ones average two sRGB values, as a TV's scaler does).
#include "shared.h"
#include "lighting_srgb.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba8) uniform readonly image2D left_image;
layout(set = 0, binding = 1, rgba8) uniform readonly image2D right_image;
layout(set = 0, binding = 2, rgba8) uniform writeonly image2D out_image;
layout(push_constant, scalar) uniform ComposeBlock { vg_compose_push c; };
// The layout is fixed for a frame: specialisation constants, one pipeline
// per layout, no branch on it at run time (a CPU rasteriser would run every
// case of the switch below under masks).
layout(constant_id = 0) const uint MODE = 0u;   // VG_COMPOSE_*
layout(constant_id = 1) const uint PACKED = 0u; // 1: each eye into its rectangle

vec4 L(ivec2 p) { return c.swap != 0u ? imageLoad(right_image, p) : imageLoad(left_image, p); }
vec4 R(ivec2 p) { return c.swap != 0u ? imageLoad(left_image, p) : imageLoad(right_image, p); }

// Dubois' least-squares anaglyph matrices, applied in linear light (output
// = LEFT * left + RIGHT * right; mat3 takes columns: one per input channel).
// Red-cyan: E. Dubois, "A projection method to generate anaglyph stereo
// images", ICASSP 2001. Green-magenta and amber-blue: the matrices Dubois
// published with it for those glasses (E. Dubois, "Anaglyph", University of
// Ottawa, site.uottawa.ca/~edubois/anaglyph).
const mat3 RED_CYAN_LEFT = mat3(0.456, -0.040, -0.015,  0.500, -0.038, -0.021,  0.176, -0.016, -0.005);
const mat3 RED_CYAN_RIGHT = mat3(-0.043, 0.378, -0.072,  -0.088, 0.734, -0.113,  -0.002, -0.018, 1.226);
const mat3 GREEN_MAGENTA_LEFT = mat3(-0.062, 0.284, -0.015,  -0.158, 0.668, -0.027,  -0.039, 0.143, 0.021);
const mat3 GREEN_MAGENTA_RIGHT = mat3(0.529, -0.016, 0.009,  0.705, -0.015, 0.075,  0.024, -0.065, 0.937);
const mat3 AMBER_BLUE_LEFT = mat3(1.062, -0.026, -0.038,  -0.205, 0.908, -0.173,  0.299, 0.068, 0.022);
const mat3 AMBER_BLUE_RIGHT = mat3(-0.016, 0.006, 0.094,  -0.123, 0.062, 0.185,  -0.017, -0.017, 0.911);

vec4 anaglyph(ivec2 o, mat3 left, mat3 right)
{
    vec3 l = srgb_to_linear(L(o).rgb), r = srgb_to_linear(R(o).rgb);
    return vec4(linear_to_srgb(left * l + right * r), 1.0);
}

// A packed layout: the eye whose rectangle holds o, averaged over the eye
// pixels one output pixel covers (two where the layout halves the eye);
// black outside both (frame packing's active space).
vec4 packed(ivec2 o)
{
    for (int e = 0; e < 2; e++) {
        ivec4 r = ivec4(c.rect[4 * e], c.rect[4 * e + 1], c.rect[4 * e + 2], c.rect[4 * e + 3]);
        ivec2 q = o - r.xy;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, r.zw)))
            continue;
        ivec2 size = ivec2(int(c.width), int(c.height)), step = size / r.zw, p = q * step;
        vec4 sum = vec4(0.0);
        for (int y = 0; y < step.y; y++)
            for (int x = 0; x < step.x; x++) {
                ivec2 t = min(p + ivec2(x, y), size - 1);
                sum += e == 0 ? imageLoad(left_image, t) : imageLoad(right_image, t);
            }
        return sum / float(step.x * step.y);
    }
    return vec4(0.0, 0.0, 0.0, 1.0);
}

void main()
{
    ivec2 o = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(out_image);
    if (any(greaterThanEqual(o, size)))
        return;
    vec4 v;
    if (PACKED != 0u) {
        v = packed(o);
    } else {
        switch (MODE) {
        case VG_COMPOSE_ROWS:
            v = (o.y & 1) == 0 ? L(o) : R(o);
            break;
        case VG_COMPOSE_COLUMNS:
            v = (o.x & 1) == 0 ? L(o) : R(o);
            break;
        case VG_COMPOSE_CHECKER:
            v = ((o.x + o.y) & 1) == 0 ? L(o) : R(o);
            break;
        case VG_COMPOSE_ANAGLYPH:
            v = anaglyph(o, RED_CYAN_LEFT, RED_CYAN_RIGHT);
            break;
        case VG_COMPOSE_ANAGLYPH_GREEN_MAGENTA:
            v = anaglyph(o, GREEN_MAGENTA_LEFT, GREEN_MAGENTA_RIGHT);
            break;
        case VG_COMPOSE_ANAGLYPH_AMBER_BLUE:
            v = anaglyph(o, AMBER_BLUE_LEFT, AMBER_BLUE_RIGHT);
            break;
        case VG_COMPOSE_ANAGLYPH_PLAIN:
            v = vec4(L(o).r, R(o).g, R(o).b, 1.0);
            break;
        case VG_COMPOSE_RIGHT:
            v = R(o);
            break;
        default: /* VG_COMPOSE_LEFT */
            v = L(o);
            break;
        }
    }
    imageStore(out_image, o, vec4(v.rgb, 1.0));
}
