/* vergence play — the hit-prediction game in a window (paper Sec. 5, Fig. 6).
 *
 * A ball is thrown from near to far or far to near, on a straight line or a
 * ballistic arc, and shown only for its first 0.6 s; click where it will
 * land. M (or 1-3) switches the disparity between original, manipulated
 * and optimized while playing. See play_session.h and docs/game.md. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "commands.h"
#include "core/log.h"
#include "options/game_cli.h"
#include "play/play_session.h"
#include "rules/game.h"

typedef struct play_opts {
    const char *scene;
    int mode, op, look_ahead, solve;
    double visible_s;
    display_cli display;
    play_window_cli win;
} play_opts;

static play_opts o = {
    .mode = FRAME_MODE_ORIGINAL, .op = DISP_OPERATOR_LANG,
    .win = {.size = {GAME_WINDOW_W, GAME_WINDOW_H}, .compose = GAME_LAYOUT, .seed = -1, .gpu = {.device = -1}},
};

static const char *const k_solve_names[] = {"budget", "full", NULL};

static const vg_opt k_opts[] = {
    {"--mode", VG_OPT_ENUM, &o.mode, "MODE", "disparity shown first: original (g), manipulated (h) or "
     "optimized (f); default original", frame_mode_names, 0, 0},
    {"--operator", VG_OPT_ENUM, &o.op, "OP", "the manipulation h (default lang)", disp_operator_names, 0, 0},
    {"--look-ahead", VG_OPT_CHOICE, &o.look_ahead, "HOW", "the optimized mode's keyframe window future: "
     "foresight (the game's own future; default) or causal (predicted from the past frames only)",
     frame_look_ahead_names, 0, 0},
    {"--solve", VG_OPT_CHOICE, &o.solve, "HOW", "the optimized mode's window solve: budget (default: one "
     "frame's share of it each frame, a keyframe published from it as it stands when due, after two iterations "
     "at least; paper 4.5) or full "
     "(a frame that skips ticks runs their share too: f as if every tick were rendered)", k_solve_names, 0, 0},
    {"--visible", VG_OPT_FLOAT, &o.visible_s, "S", "seconds the ball is shown after launch (default 0.6)",
     NULL, 0.1, 3},
    {"--seed", VG_OPT_INT, &o.win.seed, "S", "seed of the throws (default: the clock)", NULL, 0, 2147483647},
    {"--scene", VG_OPT_STRING, &o.scene, "FILE", "the arena (default content/arena.gltf); it needs a node "
     "named 'ball'", NULL, 0, 0},
    DISPLAY_CLI_OPTIONS(o.display),
    PLAY_WINDOW_OPTIONS(o.win),
};

static int run(int argc, char **argv)
{
    bool help;
    if (vg_cli_parse(&vg_cmd_play, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    vg_status dst = display_cli_load(&o.display);
    if (dst != VG_OK)
        return vg_status_exit_code(dst);
    o.win.display_file = o.display.file;
    char buf[1024];
    const char *scene_path = game_scene_path(o.scene, buf, sizeof buf);
    if (!scene_path)
        return vg_status_exit_code(VG_ERR_IO);
    uint64_t seed = o.win.seed >= 0 ? (uint64_t)o.win.seed : (uint64_t)time(NULL);
    vg_status st = play_session_run(&(play_session_desc){
        .win = &o.win, .scene_path = scene_path, .mode = (frame_mode)o.mode,
        .op = (disp_operator_kind)o.op, .look_ahead = (frame_look_ahead)o.look_ahead, .full_solve = o.solve == 1,
        .display = display_cli_desc(&o.display),
        .visible_s = o.visible_s, .seed = seed,
    });
    return vg_status_exit_code(st);
}

const vg_cmd vg_cmd_play = {
    .name = "play",
    .summary = "the hit-prediction game in a window (anaglyph by default)",
    .usage = "vergence play [--output LAYOUT] [--mode MODE] [--operator OP] [--look-ahead HOW] [--solve HOW] [--fullscreen] [--size WxH]",
    .details = "Watch the ball for its first moments, then click where it will land on the\n"
               "ground; the miss is the distance from the true landing spot to the ray through\n"
               "your click (paper Sec. 5). Keys: M cycles original / manipulated / optimized,\n"
               "1-3 pick one, H the technical HUD (mode, operator, fps, GPU ms per pass),\n"
               "P or Space pause, R restart, Esc or Q quit. The window is resizable; --replay\n"
               "plays recorded input at a fixed time step (docs/game.md).",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
