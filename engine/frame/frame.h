/* vergence — the frame: the scene evaluated at a frame's time and every
 * pass of DESIGN.md's frame in one frame graph (docs/architecture.md has its
 * dump): the G-buffer (render/), the disparity pipeline (disparity/gpu/), the
 * stereo warp (warp/), the composed output and its presentation (output/),
 * and the readback of every map for captures.
 *
 * A frame renders the scene at t = index / fps (absolute frame numbers, so
 * keyframes fall on multiples of the keyframe stride whatever the start
 * time). Headless and windowed runs share this code; time steps are fixed,
 * so a capture is deterministic. */
#pragma once
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "graph/graph.h"
#include "frame_desc.h"
#include "scene/scene.h"

typedef struct frame frame;

vg_status frame_create(gpu *g, const scene *s, const frame_desc *desc, frame **out);
/* Whether a frame of width x height can carry the disparity pipeline (its
 * solver grid needs at least 2 x 2 cells, of at most 192 x 108); when not,
 * *why says what is allowed. */
bool frame_size_ok(uint32_t width, uint32_t height, char *why, size_t cap);
void frame_destroy(frame *f);

/* Renders frame `index` and waits for it (headless). Indices may skip,
 * repeat or jump: each frame shows what rendering every index would
 * (disparity_gpu_prepare). */
vg_status frame_render(frame *f, long index);

const frame_outputs *frame_get_outputs(const frame *f);
const frame_times *frame_get_times(const frame *f);
const vg_camera *frame_get_camera(const frame *f);  /* at the frame's time */
const frame_desc *frame_get_desc(const frame *f);
rg_graph *frame_get_graph(frame *f);

/* Headless frames with desc.overlay: the HUD frame_render draws into each
 * eye from now on (copied). */
vg_status frame_set_hud(frame *f, const frame_hud *hud);

/* Windowed: render frame `index` into an acquired swapchain image and submit
 * without waiting (two frames in flight). The HUD may be NULL. */
vg_status frame_present(frame *f, long index, const frame_target *target, const frame_hud *hud);
/* The scene's future changed (what evaluating it ahead gave is stale: a new
 * throw of the game): the next frame starts the keyframe window afresh. */
void frame_restart(frame *f);
/* Waits until no frame is in flight. */
vg_status frame_wait_idle(frame *f);
/* desc.probe_ids: what the probe measured in the frames completed since the
 * last call, oldest first (at most FRAME_PROBES_KEPT are kept; a
 * headless frame completes in frame_render, a windowed one when its slot
 * is reused or in frame_wait_idle). Returns how many it wrote to out. */
int frame_take_probes(frame *f, frame_probe *out, int cap);

/* The pass clock, the one way passes are timed (every bench, capture.json,
 * the HUD). On a CPU device (lavapipe) each pass is then submitted alone
 * and timed by the wall clock until it completes, so the passes add up to
 * the frame (it costs the overlap between passes: 5-10 % of a frame there);
 * off, such a device reports no passes. Other devices time every frame
 * with GPU timestamps, on or off. */
void frame_time_passes(frame *f, bool on);
/* ms of each pass of the last completed frame (the pass clock); returns the
 * number of passes, 0 when none were timed. The last entry is the host's
 * part, FRAME_PASS_HOST: the CPU's ms from the frame's start (its slot free)
 * to its submission (the scene's evaluation, the constants, the SDK's plan,
 * recording, vkQueueSubmit2; on a CPU device with the clock on, each pass's
 * recording is in that pass's ms instead). The GPU works after it, so the
 * passes and the host part add up to a headless frame's wall time. */
#define FRAME_PASS_HOST "host"
uint32_t frame_pass_timings(frame *f, const char **names, double *ms, uint32_t cap);

/* What the frame resolved beyond its desc (frame_get_desc: every default
 * resolved), for reports and metrics. */
typedef struct frame_info {
    bool disparity;                          /* the disparity pipeline runs (stereo frames) */
    uint32_t grid_stride, grid_nx, grid_ny;  /* the solver's coarse grid */
    int window_past, window_future;          /* keyframes of the window behind and ahead */
    double range_lo, range_hi;               /* target range, arcmin (f stays inside) */
    bool saliency_computed;                  /* the G-buffer computes saliency (none authored, or asked) */
} frame_info;
void frame_get_info(const frame *f, frame_info *out);
/* g of the paper at view depth z (metres) in the frame last rendered: its
 * original rig (the render camera's field of view, the image width) through
 * the display model, arcmin. */
double frame_original_vergence(const frame *f, double z_m);
/* A keyframe as the solve sees it (readback frames; disparity_gpu_keyframe_read). */
struct disparity_gpu_keyframe;
vg_status frame_solved_keyframe(const frame *f, long keyframe, struct disparity_gpu_keyframe *out);


