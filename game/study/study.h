/* vergence — the two studies behind `vergence study` (paper Sec. 5). */
#pragma once
#include <stdint.h>

#include "core/cli.h"
#include "options/game_cli.h"
#include "play/play_session.h"
#include "study_log.h"

/* What the simulated observer sees (--observer-view). */
enum { STUDY_VIEW_ENGINE = 0, STUDY_VIEW_CPU };

typedef struct study_opts {
    const vg_cmd *cmd;
    const char *participant, *out, *scene;
    int trials, seed, observer, op;     /* -1: not given; observer 0 human, 1 model */
    int observer_view;                  /* model: STUDY_VIEW_ENGINE (its frames) or _CPU (observer_view) */
    int observer_cues;                  /* hit model: 0 disparity, 1 both (disparity and size) */
    bool resume;
    bool allow_missed;                  /* hit: run on a window that cannot hold 60 Hz */
    double weber_k, visible_s;
    display_cli display;
    play_window_cli win;
} study_opts;

vg_status study_hit_run(const study_opts *o);
/* The observer column: "human", "model" (the engine's frames) or
 * "model-cpu" (the CPU view); the two-cue observer is "model-2cue" or
 * "model-2cue-cpu"; files of different observers never mix. */
const char *study_observer_name(const study_opts *o);
vg_status study_preference_run(const study_opts *o);

/* Shared by both: "2026-11-22T01:40:05Z" now. */
void study_utc_now(char *out, size_t cap);
/* The display every row records (after utc), as the settings a resumed file
 * must share: visible width (m), panel pixels, viewing and interocular
 * distance (m). */
#define STUDY_DISPLAY_COLUMNS "display_width_m", "display_px", "distance_m", "ipd_m"
#define STUDY_DISPLAY_COUNT 4
void study_display_fields(const study_opts *o, char out[STUDY_DISPLAY_COUNT][32]);

/* What a study's CSV is: its columns, where the seed is, the settings every
 * row must share with this run (a resumed file's rows were run with them:
 * trials of another condition must not join it), the measured numbers
 * (finite), its design's cells per block and its default length. */
typedef struct study_setting {
    int column;
    const char *flag;            /* "--operator", ... */
    const char *value;           /* as this run writes it */
} study_setting;

typedef struct study_kind {
    const char *name;            /* "hit", "preference" */
    const char *const *columns;
    int column_count, col_seed;
    const study_setting *settings;
    int setting_count;
    const int *numeric;
    int numeric_count;
    int cells, default_trials;
} study_kind;

/* A study's log (created or resumed), its seed and schedule. */
typedef struct study_session {
    study_log log;
    uint64_t seed;
    int trials;
    int *cells;                  /* the schedule: trials cells */
} study_session;

/* Opens --out (creating it, or resuming it: the seed, the settings and the
 * numbers of every row read back are checked, and --trials must cover it)
 * and makes the schedule. */
vg_status study_begin(const study_opts *o, const study_kind *k, study_session *out);
/* Closes the log (a file this run created and filled with nothing goes when
 * st fails); returns st. */
vg_status study_end(study_session *s, const study_opts *o, const study_kind *k, vg_status st);
