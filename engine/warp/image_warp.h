/* vergence — forward image warping with a z-buffer, on the CPU: the
 * reference of the GPU pass imagewarp.left/right (warp/gpu, shaders/
 * imagewarp.vert) and the way `vergence optimize --image` renders a new
 * stereo pair from f (docs/method.md "A new stereo pair").
 *
 * Every source pixel (x, y) moves along its row to the pixel that contains
 * x + 0.5 + shift (the point the GPU pass rasterises); where several land on
 * one pixel the smallest z wins, the first in row order on a tie (the GPU's
 * LESS depth test in vertex order). What no pixel reaches is a hole. */
#pragma once
#include <stdbool.h>
#include <stdint.h>

/* Warps src (w x h, `channels` bytes per pixel) into dst; shift and z are
 * per source pixel (pixels; any unit of distance, smaller = nearer).
 * z_out (optional) receives the winning z per destination pixel, +inf at
 * holes; hole (optional) 1 at holes. Returns the number of holes. */
long image_warp(const uint8_t *src, int w, int h, int channels, const float *shift, const float *z, uint8_t *dst,
                float *z_out, uint8_t *hole);

/* The hole fill: each run of holes in a row takes the colour of whichever
 * neighbour of the run is farther (larger z_out), since a disocclusion
 * uncovers what lies behind the occluder; a run at the border takes its one
 * neighbour; a row with no pixel stays as it is. */
void image_warp_fill(uint8_t *dst, int w, int h, int channels, const float *z_out, const uint8_t *hole);
