/* vergence — a preference trial (paper Sec. 5): its cell of the design
 * (scene x saliency x side of f), the scene with its moving object and its
 * saliency variant, and its clips, rendered ahead and headless: every
 * PREF_CLIP_STEP-th frame of the scene's duration in one mode, with the
 * study's frame (its operator preset, the warp, the CPU defaults). The
 * window plays them back frame-accurately (pref_window.c), the study logs
 * the answers (study_pref.c); tests render the same clips (tests/game). */
#pragma once
#include <stdbool.h>
#include <stddef.h>

#include "disparity/disp_operator.h"
#include "frame/frame_desc.h"
#include "scene/scene.h"

#define PREF_SCENES 3
#define PREF_CELLS 12            /* scene (3) x saliency (2) x side of f (2) */

typedef struct pref_cell {
    int scene;                   /* pref_scene_names */
    int saliency;                /* 0: on the moving object (as authored), 1: on the static ones */
    int optimized_right;         /* f on the right (h on the left), else the other way */
} pref_cell;

extern const char *const pref_scene_names[PREF_SCENES];
extern const char *const pref_saliency_names[2];
pref_cell pref_cell_of(int cell);
int pref_moving_node(const scene *s);
void pref_saliency_apply(scene *s, int moving, int variant);
/* content/<name>.gltf beside the arena. */
vg_status pref_scene_path(const char *arena_path, int scene_index, char *out, size_t cap);

#define PREF_GAP 8              /* eye pixels between the panels */
/* A panel's size in an eye of ew x eh: three side by side, 16:9, at most
 * 320 x 180 on a CPU device (pre-rendering there: keep it short); even. */
void pref_panel_size(bool cpu, int ew, int eh, int *pw, int *ph);

#define PREF_CLIP_STEP 2        /* clips hold every 2nd frame: 30 Hz, each shown twice at 60 Hz */

/* The frame a clip of one version is rendered with. */
typedef struct pref_clip_desc {
    uint32_t width, height;     /* one panel's eye image */
    frame_mode mode;
    frame_compose compose;
    bool swap_eyes;
    disp_operator_kind op;
    stereo_display_desc display;
    double tess_error;          /* 0 = game_frame_defaults' */
} pref_clip_desc;
frame_desc pref_clip_frame_desc(const gpu *g, const pref_clip_desc *d);

/* Frames of a clip of the scene (its duration at 60 / PREF_CLIP_STEP Hz). */
int pref_clip_frames(const scene *s);

/* Each rendered frame k (index k * PREF_CLIP_STEP); *stop ends the clip. */
typedef vg_status (*pref_clip_fn)(void *user, int k, const frame_outputs *o, bool *stop);
vg_status pref_clip_render(gpu *g, const scene *s, const frame_desc *fd, pref_clip_fn on_frame, void *user);
