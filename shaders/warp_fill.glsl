// vergence — warp.fill: closes the cracks of the warp, in place. Surfaces
// that meet without sharing vertices (T-junctions, overlapping parts of one
// object) can part by a fraction of a pixel once the target disparity moves
// them differently, and a pixel centre may fall in the seam. Where an eye
// shows sky between one surface's pixels (the same depth on both sides) and
// the centre view shows that surface there, the pixel takes its neighbours'
// mean. The same test is the capture's hole measure (warp_metrics.c), so a
// crack two pixels wide stays visible there.
//
// Three kernels, so that nothing but the cracks costs more than a few loads
// (llvmpipe runs every branch for every lane: a test behind an `if` costs
// all pixels):
//   warp_fill_find   (RESET: one invocation zeroes the eye's count) every
//                    pixel: sky with geometry on both sides, across or down,
//                    is a candidate (appended to the list)
//   warp_fill_test   each candidate: the whole test, on the eye as drawn
//   warp_fill_apply  each crack: the mean of its two neighbours
// Only sky pixels are written, and only after every test has read the eye,
// so each decision sees the eye as drawn (the order of the list is free).
#extension GL_EXT_scalar_block_layout : require
#include "shared.h"

layout(set = 0, binding = 0, rgba8) uniform image2D eye_color;
layout(set = 0, binding = 1, rgba32f) uniform image2D eye_aux;
layout(set = 0, binding = 2, r32ui) uniform readonly uimage2D centre_ids;
// Per eye, the candidates' work-list header (shared.h: warp_fill_find
// empties it with RESET set, then appends).
layout(set = 0, binding = 3, scalar) buffer FillHeader { uvec4 fill_header[]; };
// Candidates: x in bits 0-15, y in bits 16-29 (Vulkan images are at most
// 16384 high here), and from warp_fill_test the pair that closes the crack
// in bits 30-31 (0 across, 1 down, 2 none).
layout(set = 0, binding = 4, scalar) buffer FillList { uint fill_list[]; };
layout(push_constant) uniform FillPush { uint slot; } pc; // the eye's header

#define FILL_NONE 2u

bool geometry(vec4 c) { return c.a > 0.75; }

ivec2 fill_step(uint k) { return k == 0u ? ivec2(1, 0) : ivec2(0, 1); }

ivec2 fill_pixel(uint e) { return ivec2(int(e & 0xffffu), int((e >> 16) & 0x3fffu)); }

bool fill_inside(ivec2 a, ivec2 b, ivec2 size)
{
    return all(greaterThanEqual(min(a, b), ivec2(0))) && all(lessThan(max(a, b), size));
}
