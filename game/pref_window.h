/* vergence — the preference study's design and its window (paper Sec. 5).
 *
 * A trial shows one scene three times side by side: the compressed (h) and
 * the optimized (f) version on the two sides, the unmodified reference (g)
 * in the middle. The clip is rendered ahead (every frame of each version,
 * headless) and then played back frame-accurately at 60 Hz and looped, so
 * the motion the participant judges does not depend on how fast the device
 * renders. Left / Right (or a click on a side) answers. */
#pragma once
#include <stddef.h>

#include "disparity/disp_operator.h"
#include "play_session.h"
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

typedef vg_status (*pref_choice_fn)(void *user, int trial, int choice_right, double response_s);

typedef struct pref_window_desc {
    const play_window_cli *win;
    const char *arena_path;
    disp_operator_kind op;
    stereo_display_desc display;
    const int *cells;
    int first_trial, trial_count;
    pref_choice_fn on_choice;
    void *user;
} pref_window_desc;

vg_status pref_window_run(const pref_window_desc *d);
