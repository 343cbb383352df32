#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
// compose: packs the two eyes into one output image (DESIGN.md step 10).
// Eyes and output are RGBA8 UNORM holding sRGB-encoded values, so every
// mode but the anaglyphs and the half-size ones copies bytes exactly.
#include "shared.h"
#include "lighting_srgb.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba8) uniform readonly image2D left_image;
layout(set = 0, binding = 1, rgba8) uniform readonly image2D right_image;
layout(set = 0, binding = 2, rgba8) uniform writeonly image2D out_image;
layout(push_constant, scalar) uniform ComposeBlock { vg_compose_push c; };

vec4 L(ivec2 p) { return c.swap != 0u ? imageLoad(right_image, p) : imageLoad(left_image, p); }
vec4 R(ivec2 p) { return c.swap != 0u ? imageLoad(left_image, p) : imageLoad(right_image, p); }

// Dubois' least-squares red-cyan matrices, applied in linear light
// (E. Dubois, "A projection method to generate anaglyph stereo images", 2001).
const mat3 DUBOIS_LEFT = mat3(0.456, -0.040, -0.015,  0.500, -0.038, -0.021,  0.176, -0.016, -0.005);
const mat3 DUBOIS_RIGHT = mat3(-0.043, 0.378, -0.072,  -0.088, 0.734, -0.113,  -0.002, -0.018, 1.226);

void main()
{
    ivec2 o = ivec2(gl_GlobalInvocationID.xy);
    ivec2 size = imageSize(out_image);
    if (any(greaterThanEqual(o, size)))
        return;
    int w = int(c.width), h = int(c.height);
    vec4 v;
    switch (c.mode) {
    case VG_COMPOSE_SBS:
        v = o.x < w ? L(o) : R(ivec2(o.x - w, o.y));
        break;
    case VG_COMPOSE_SBS_HALF: {
        int half_w = w / 2;
        bool right = o.x >= half_w;
        int x = 2 * (right ? o.x - half_w : o.x);
        v = right ? 0.5 * (R(ivec2(x, o.y)) + R(ivec2(min(x + 1, w - 1), o.y)))
                  : 0.5 * (L(ivec2(x, o.y)) + L(ivec2(min(x + 1, w - 1), o.y)));
        break;
    }
    case VG_COMPOSE_TB:
        v = o.y < h ? L(o) : R(ivec2(o.x, o.y - h));
        break;
    case VG_COMPOSE_ROWS:
        v = (o.y & 1) == 0 ? L(o) : R(o);
        break;
    case VG_COMPOSE_COLUMNS:
        v = (o.x & 1) == 0 ? L(o) : R(o);
        break;
    case VG_COMPOSE_CHECKER:
        v = ((o.x + o.y) & 1) == 0 ? L(o) : R(o);
        break;
    case VG_COMPOSE_ANAGLYPH: {
        vec3 l = srgb_to_linear(L(o).rgb), r = srgb_to_linear(R(o).rgb);
        v = vec4(linear_to_srgb(DUBOIS_LEFT * l + DUBOIS_RIGHT * r), 1.0);
        break;
    }
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
    imageStore(out_image, o, vec4(v.rgb, 1.0));
}
