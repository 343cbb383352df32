/* vergence — the frame: scene evaluation, the frame graph and its passes.
 *
 * A frame renders the scene at t = index / fps (absolute frame numbers, so
 * keyframes fall on multiples of the keyframe stride whatever the start
 * time). Passes so far (DESIGN.md, steps 1-2):
 *
 *   shadow   (graphics) sun shadow map
 *   gbuffer  (graphics) centre eye: lit colour + saliency, linear depth,
 *                       instance id, motion to the previous/next keyframe
 *   readback (transfer) copies the G-buffer to host memory (capture only)
 *
 * Headless and windowed runs share this code; time steps are fixed, so a
 * capture is deterministic. */
#pragma once
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "gpu/gpu.h"
#include "graph/graph.h"
#include "scene/scene.h"
#include "stereo/stereo_display.h"

typedef struct frame frame;

typedef struct frame_desc {
    uint32_t width, height;      /* 0 = 960x540 */
    double fps;                  /* 0 = 60 */
    int keyframe_stride;         /* frames between keyframes, 0 = 10 (paper 4.4) */
    int camera;                  /* camera node index (in node order) */
    bool readback;               /* copy the G-buffer to the host every frame */
    uint32_t shadow_size;        /* 0 = 2048 */
    stereo_display_desc display; /* the display model (zero = paper defaults) */
    stereo_camera_desc rig;      /* the original stereo camera (zero = ortho-stereo for the display) */
} frame_desc;

/* Host copies of the G-buffer after frame_render() (readback only). */
typedef struct frame_outputs {
    const uint8_t *color;        /* RGBA8 sRGB, alpha = saliency */
    const float *depth;          /* linear depth, metres; background = far plane */
    const uint32_t *ids;         /* instance id, 0 = background */
    const float *motion;         /* 4 floats per pixel: pixels to prev keyframe (xy), to next (zw) */
} frame_outputs;

/* The times a frame was rendered at. */
typedef struct frame_times {
    long index;                  /* absolute frame number */
    long prev_key, next_key;     /* neighbouring keyframes (frame numbers, strictly before/after) */
    double t, t_prev, t_next;    /* seconds */
} frame_times;

vg_status frame_create(gpu *g, const scene *s, const frame_desc *desc, frame **out);
void frame_destroy(frame *f);

/* Renders frame `index` and waits for it (headless) . */
vg_status frame_render(frame *f, long index);

const frame_outputs *frame_get_outputs(const frame *f);
const frame_times *frame_get_times(const frame *f);
const vg_camera *frame_get_camera(const frame *f);  /* at the frame's time */
const frame_desc *frame_get_desc(const frame *f);
rg_graph *frame_get_graph(frame *f);

/* GPU ms of each pass of the last frame; returns the number of passes. */
uint32_t frame_pass_timings(frame *f, const char **names, double *ms, uint32_t cap);

/* Keyframe times around a frame number (pure: used by tests too). */
frame_times frame_times_at(long index, double fps, int stride);
