// vergence — warp.curve: the global depth -> vergence curve (paper 4.6) from
// the (depth, target vergence) pairs of the frame's geometry pixels, with
// bins uniform in inverse depth. Three passes, all in a fixed order so the
// curve is the same on every run and every device:
//   range    the inverse-depth range: per 64x64 tile, then over the tiles
//   bins     per 64x64 tile: count and fixed-point sums of vergence and of
//            the position inside the bin, per bin
//   resolve  per bin: centroid over tiles; empty bins take the bin centre and
//            the value linear between their populated neighbours (the hat
//            reconstruction of the paper); constant beyond the ends.
#extension GL_EXT_scalar_block_layout : require
#include "shared.h"

#define CURVE_TILE 64
#define CURVE_FIXED 256.0   // vergence fixed point: 1/256 arcmin
#define CURVE_OFFSET_FIXED 65536.0 // position inside a bin, fixed point

layout(set = 0, binding = 0, r32f) uniform readonly image2D depth_image;
layout(set = 0, binding = 1, r32f) uniform readonly image2D target_image;
layout(set = 0, binding = 2, scalar) buffer CurveBlock { vgx_curve_data curve; };
layout(set = 0, binding = 3, scalar) buffer TileBlock { uint tile_count[]; };
layout(set = 0, binding = 4, scalar) buffer TileSumBlock { uint tile_sum[]; };
layout(set = 0, binding = 5, scalar) buffer TileOffsetBlock { uint tile_offset[]; };
layout(push_constant, scalar) uniform CurvePush {
    float far_depth;   // background depth: pixels at or beyond it are not geometry
    uint tiles_x, tiles_y, pad;
} pc;

bool is_geometry(float z)
{
    return z > 0.0 && z < pc.far_depth * 0.999;
}
