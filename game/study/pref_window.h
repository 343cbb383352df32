/* vergence — the preference study's window (paper Sec. 5).
 *
 * A trial shows one scene three times side by side: the compressed (h) and
 * the optimized (f) version on the two sides, the unmodified reference (g)
 * in the middle. The clips are rendered ahead (pref_trial.h) and then played
 * back frame-accurately at 60 Hz and looped, so the motion the participant
 * judges does not depend on how fast the device renders. Left / Right (or a
 * click on a side) answers. */
#pragma once
#include <stddef.h>

#include "disparity/disp_operator.h"
#include "play/play_session.h"
#include "pref_trial.h"
#include "scene/scene.h"

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
