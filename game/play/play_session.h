/* vergence — the hit game in a window (paper Fig. 6), for `vergence play`
 * and the human side of `vergence study hit`.
 *
 * A throw: the ball rests at its launch point ("get ready"), flies for the
 * visible interval, vanishes; the player clicks where it will land; free
 * play then shows the ball on its true landing spot with the miss distance
 * and points (a study shows nothing, so no condition is learnt). The ball is
 * the arena's `ball` node, moved through the scene's pose hook as a function
 * of game time, so the frame's look-ahead keyframes see its motion.
 *
 * Keys: M cycles original / manipulated / optimized, 1-3 pick one (free
 * play), H the technical HUD (mode, operator, fps, GPU ms per pass), L the
 * next output layout, E swaps the eyes, P or Space pause, R restart, Esc or
 * Q quit. A mode the build cannot render yet
 * is announced on screen and skipped. */
#pragma once
#include <stdint.h>

#include "disparity/disp_operator.h"
#include "rules/game.h"
#include "options/gpu_cli.h"
#include "flight.h"
#include "frame/frame.h"

/* Window options of `play` and of a human `study`. */
typedef struct play_window_cli {
    int size[2];                 /* window, default 1280x720 */
    int render[2];               /* eye image; 0 = from the window (smaller on a CPU device) */
    bool fullscreen;
    int compose;                 /* frame_compose */
    bool swap_eyes;              /* the right eye where the layout puts the left */
    const char *replay, *record;
    const char *display_file;    /* --display FILE (an input: never an output) */
    int ticks;                   /* quit after this many ticks (1/60 s), 0 = never */
    int frame_ticks;             /* replay: ticks per frame (tests: a device at 60 / N fps), 0 = 1 */
    const char *dump_f;          /* write f of every frame shown in the optimized mode (tests) */
    int seed;                    /* free play throws, -1 = from the clock */
    double tess_error;           /* 0 = the engine's default, 0.5 px on a CPU device */
    gpu_cli gpu;
} play_window_cli;

#define PLAY_WINDOW_OPTIONS(w)                                                                          \
    {"--output", VG_OPT_ENUM, &(w).compose, "LAYOUT", "how the eyes are shown (default anaglyph; "      \
     "rows for passive polarised panels)", frame_compose_names, 0, 0},                              \
    {"--swap-eyes", VG_OPT_FLAG, &(w).swap_eyes, NULL, "exchange left and right (E while playing)",    \
     NULL, 0, 0},                                                                                       \
    {"--size", VG_OPT_SIZE, (w).size, "WxH", "window size (default 1280x720)", NULL, 0, 0},             \
    {"--render-size", VG_OPT_SIZE, (w).render, "WxH", "eye image size (default: fit the window; "      \
     "at most 480 wide on a CPU device)", NULL, 0, 0},                                                  \
    {"--fullscreen", VG_OPT_FLAG, &(w).fullscreen, NULL, "full screen on the primary monitor", NULL, 0, 0}, \
    {"--tess-error", VG_OPT_FLOAT, &(w).tess_error, "PX", "warp tessellation tolerance (default: the "  \
     "engine's; 0.5 on a CPU device)", NULL, 0.001, 100},                                               \
    {"--replay", VG_OPT_STRING, &(w).replay, "FILE", "feed recorded key and mouse events at a fixed "    \
     "time step (docs/game.md)", NULL, 0, 0},                                                           \
    {"--record", VG_OPT_STRING, &(w).record, "FILE", "write key and mouse events for --replay", NULL, 0, 0}, \
    {"--ticks", VG_OPT_INT, &(w).ticks, "N", "quit after N ticks of 1/60 s (tests)", NULL, 1, 100000000}, \
    {"--frame-ticks", VG_OPT_INT, &(w).frame_ticks, "N", "with --replay: N ticks per frame, as a device at " \
     "60/N fps advances (tests)", NULL, 1, 6},                                                          \
    {"--dump-f", VG_OPT_STRING, &(w).dump_f, "DIR", "write f of every frame shown in the optimized mode " \
     "to DIR/f_INDEX.pfm (tests)", NULL, 0, 0},                                                         \
    GPU_CLI_OPTIONS((w).gpu)

/* A finished study trial, handed to the study's logger. */
typedef struct play_trial {
    int trial;
    const game_throw *th;
    frame_mode mode;
    double click_u, click_v, error_m;
    double response_s;           /* from the ball's disappearance to the click */
    flight_record flight;        /* how the flight was shown (a person's study; the model's: exact) */
    double ball_mid_jnd;         /* MID distortion of the ball as shown against g over the flight, JND
                                    (ball_trace.h on the flight's frames; the model's: observer_result) */
} play_trial;

typedef vg_status (*play_trial_fn)(void *user, const play_trial *t);

typedef struct play_session_desc {
    const play_window_cli *win;
    const char *scene_path;
    frame_mode mode;             /* free play: the first mode (0 = original) */
    disp_operator_kind op;
    frame_look_ahead look_ahead; /* the optimized mode's window future (0: the scene's own) */
    bool full_solve;             /* live frames catch up on the solve of skipped ticks (frame_desc
                                    budgeted_solve off); a study's frames always do */
    stereo_display_desc display;
    double visible_s;            /* 0 = GAME_VISIBLE_S */
    uint64_t seed;               /* the throws */
    /* A study when cells != NULL: trials first_trial .. trial_count - 1 with
     * the conditions of the schedule, each reported to on_trial. Its
     * throws' flights are rendered ahead and shown frame-exactly (flight.h);
     * a window that cannot hold 60 Hz refuses to start unless allow_missed. */
    const int *cells;
    bool allow_missed;
    int first_trial, trial_count;
    play_trial_fn on_trial;
    void *user;
} play_session_desc;

vg_status play_session_run(const play_session_desc *desc);

/* Before any work: no file a game run writes (--record, --dump-f's
 * f_*.pfm, a study's --out named by out_label) is one it reads (the scenes
 * and every file they reference, --replay). One line and VG_ERR_ARG when one
 * is; the scenes' own errors as scene_load reports them. */
vg_status play_check_outputs(const play_window_cli *w, const char *const *scene_paths, int scene_count,
                             const char *out_label, const char *out_path);

