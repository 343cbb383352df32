/* vergence — mid.keyframes: the keyframes of the MID window rendered at the
 * solver's coarse resolution (paper 4.5: "a prediction of future frames").
 * Every animation is a function of time, so the keyframe the window needs
 * next (several seconds ahead) is the scene evaluated at that time (causal
 * look-ahead: predicted from the past, scene_gpu_known); its
 * depth, saliency and motion to the neighbouring keyframes come from the
 * G-buffer shaders (exact for rigid, skinned and morphed meshes), rendered
 * into a tile of an atlas with a projection that puts each coarse pixel's
 * centre on the ray of its full-resolution sample (disp_grid). Keyframes
 * are rendered once, when they enter the window; the store keeps them. */
#pragma once
#include <stdint.h>

#include "disparity/gpu/disparity_gpu.h"
#include "pass/frame_ctx.h"

typedef struct keyframe_gpu keyframe_gpu;

typedef struct keyframe_gpu_desc {
    uint32_t nx, ny, stride;   /* coarse grid of the full-resolution frame */
    uint32_t max_tiles;        /* keyframes rendered in one frame */
} keyframe_gpu_desc;

vg_status keyframe_gpu_create(frame_ctx *fc, const keyframe_gpu_desc *desc, keyframe_gpu **out);
void keyframe_gpu_destroy(keyframe_gpu *k);
/* Adds "mid.keyframes": the frame's renderer of the atlas disparity_gpu
 * reads (a host of the SDK draws it with its own); fills the atlas. */
void keyframe_gpu_add(keyframe_gpu *k, rg_graph *g, const frame_resources *res, disparity_gpu_atlas *atlas);
/* One keyframe to render, as the SDK plans it (vgx_get_keyframe): the scene
 * at t with its motion to t_prev and t_next, placed in its tile by
 * atlas_from_clip (column-major). */
typedef struct keyframe_gpu_tile {
    double t, t_prev, t_next;
    float atlas_from_clip[16];
} keyframe_gpu_tile;
/* This frame renders tiles[0 .. count - 1] into atlas tiles 0 .. count - 1
 * (count 0: none): evaluates the scene at their times and fills the slot's
 * streams. */
void keyframe_gpu_prepare(keyframe_gpu *k, const keyframe_gpu_tile *tiles, int count);
int keyframe_gpu_tiles(const keyframe_gpu *k);
