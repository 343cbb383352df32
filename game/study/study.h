/* vergence — the two studies behind `vergence study` (paper Sec. 5). */
#pragma once
#include <stdint.h>

#include "core/cli.h"
#include "options/game_cli.h"
#include "play/play_session.h"

typedef struct study_opts {
    const vg_cmd *cmd;
    const char *participant, *out, *scene;
    int trials, seed, observer, op;     /* -1: not given; observer 0 human, 1 model */
    bool resume;
    double weber_k, visible_s;
    game_display_cli display;
    play_window_cli win;
} study_opts;

vg_status study_hit_run(const study_opts *o);
vg_status study_preference_run(const study_opts *o);

/* Shared by both: "2026-11-22T01:40:05Z" now. */
void study_utc_now(char *out, size_t cap);

/* The seed of a study: the file's when resuming (every row must agree, and a
 * different --seed is refused), else --seed, else the participant id's. */
struct study_log;
vg_status study_pick_seed(const study_opts *o, const struct study_log *log, int column, uint64_t *seed);
