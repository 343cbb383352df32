/* vergence study — the paper's two studies (Sec. 5) with their CSV logs.
 *
 *   vergence study hit --participant ID --out FILE.csv [--trials N] [--seed S]
 *   vergence study preference --participant ID --out FILE.csv [--trials N]
 *
 * Trials follow a balanced, randomised schedule fixed by the seed (the
 * participant id's hash unless --seed is given); each finished trial is one
 * CSV line, fsync'd at once; --resume checks the file and continues at the
 * next trial; nothing is ever overwritten. --observer model plays without a
 * person (the simulated observer, docs/game.md). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "commands.h"
#include "core/log.h"
#include "options/game_cli.h"
#include "options/gpu_cli.h"
#include "observer/observer.h"
#include "play/play_session.h"
#include "study/pref_trial.h"
#include "study/study.h"
#include "study/study_log.h"

/* ------------------------------------------------------------------------- */
/* Options                                                                   */
/* ------------------------------------------------------------------------- */

static study_opts o = {
    .trials = -1, .seed = -1, .op = DISP_OPERATOR_LANG, .weber_k = 0,
    .win = {.size = {1280, 720}, .compose = FRAME_COMPOSE_ANAGLYPH, .gpu = {.device = -1}},
};

static const char *const k_observer_names[] = {"human", "model", NULL};
static const char *const k_view_names[] = {"engine", "cpu", NULL};
static const char *const k_cue_names[] = {"disparity", "both", NULL};

#define STUDY_COMMON_OPTIONS                                                                            \
    {"--participant", VG_OPT_STRING, &o.participant, "ID", "participant id (letters, digits, - _ .); "   \
     "written on every line", NULL, 0, 0},                                                              \
    {"--out", VG_OPT_STRING, &o.out, "FILE.csv", "the CSV log (created; never overwritten)", NULL, 0, 0}, \
    {"--trials", VG_OPT_INT, &o.trials, "N", "number of trials", NULL, 1, 1000000},                      \
    {"--seed", VG_OPT_INT, &o.seed, "S", "schedule and throw seed (default: from the participant id)",   \
     NULL, 0, 2147483647},                                                                              \
    {"--resume", VG_OPT_FLAG, &o.resume, NULL, "continue FILE.csv after its last finished trial", NULL, 0, 0}, \
    {"--observer", VG_OPT_CHOICE, &o.observer, "WHO", "human (a window) or model (the simulated "       \
     "observer, headless)", k_observer_names, 0, 0},                                                    \
    {"--operator", VG_OPT_ENUM, &o.op, "OP", "the manipulation h (default lang, study preset)",        \
     disp_operator_names, 0, 0},                                                                        \
    {"--observer-view", VG_OPT_CHOICE, &o.observer_view, "VIEW", "model: engine (the frames a person "  \
     "would see, their maps read back; slow on a CPU device) or cpu (a CPU model of g, h and f: fast; "  \
     "docs/game.md)", k_view_names, 0, 0},                                                              \
    {"--weber-k", VG_OPT_FLOAT, &o.weber_k, "K", "model: Weber fraction of its velocity noise "          \
     "(default 0.08; negative = no noise)", NULL, -1, 1},                                               \
    {"--scene", VG_OPT_STRING, &o.scene, "FILE", "the arena (default content/arena.gltf)", NULL, 0, 0},  \
    DISPLAY_CLI_OPTIONS(o.display),                                                                    \
    PLAY_WINDOW_OPTIONS(o.win)

static const vg_opt k_hit_opts[] = {
    STUDY_COMMON_OPTIONS,
    {"--visible", VG_OPT_FLOAT, &o.visible_s, "S", "seconds the ball is shown after launch (default 0.6)",
     NULL, 0.1, 3},
    {"--observer-cues", VG_OPT_CHOICE, &o.observer_cues, "CUES", "model: disparity (its changing "
     "disparity only) or both (changing disparity and changing size, one motion-in-depth stage; "
     "docs/game.md)", k_cue_names, 0, 0},
    {"--allow-missed-frames", VG_OPT_FLAG, &o.allow_missed, NULL, "run even when the window cannot show the "
     "flight at 60 Hz (demonstrations; every row records the frames missed)", NULL, 0, 0},
};

static const vg_opt k_pref_opts[] = {
    STUDY_COMMON_OPTIONS,
};

const vg_cmd vg_cmd_study_hit = {
    .name = "study hit",
    .summary = "the hit-prediction study (paper Sec. 5, Fig. 7)",
    .usage = "vergence study hit --participant ID --out FILE.csv [--trials N] [--seed S] [--resume] "
             "[--observer human|model]",
    .details = "Conditions original / manipulated / optimized x near-to-far / far-to-near x\n"
               "straight / ballistic, balanced in blocks of 12 and randomised (default 48\n"
               "trials). A human player sees each throw in a window and clicks where it will\n"
               "land (no feedback, so nothing is learnt per condition). Each flight is rendered\n"
               "ahead and shown from memory at 60 Hz, one frame per refresh; the CSV records\n"
               "the frames shown and missed, and a window that cannot hold the rate refuses to\n"
               "start (exit 7). --observer model plays headless. One CSV line per finished\n"
               "trial (docs/game.md); analyse with tools/analyze_study.py.",
    .opts = k_hit_opts,
    .opt_count = sizeof k_hit_opts / sizeof k_hit_opts[0],
};

const vg_cmd vg_cmd_study_preference = {
    .name = "study preference",
    .summary = "the preference study (paper Sec. 5)",
    .usage = "vergence study preference --participant ID --out FILE.csv [--trials N] [--seed S] [--resume] "
             "[--observer human|model]",
    .details = "Each trial shows one scene three times side by side: compressed (h) and\n"
               "optimized (f) on the two sides, sides randomised, the unmodified reference (g)\n"
               "in the middle. Press Left or Right (or click a side) for the one whose motion\n"
               "is more like the reference. Scenes balloon, cubes, arena x saliency on the\n"
               "moving or the static objects x sides, balanced in blocks of 12 (default 24).",
    .opts = k_pref_opts,
    .opt_count = sizeof k_pref_opts / sizeof k_pref_opts[0],
};

/* ------------------------------------------------------------------------- */
/* Command                                                                   */
/* ------------------------------------------------------------------------- */

static void print_usage(FILE *out)
{
    fprintf(out, "usage: vergence study hit|preference [options]\n\n"
                 "  hit          %s\n  preference   %s\n\n"
                 "Run 'vergence study hit --help' or 'vergence study preference --help' for the options.\n",
            vg_cmd_study_hit.summary, vg_cmd_study_preference.summary);
}

static int run(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        print_usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    bool hit = !strcmp(argv[1], "hit");
    if (!hit && strcmp(argv[1], "preference")) {
        vg_error("study: '%s' is not a study (hit or preference; see 'vergence study --help')", argv[1]);
        return 2;
    }
    const vg_cmd *cmd = hit ? &vg_cmd_study_hit : &vg_cmd_study_preference;
    bool help;
    if (vg_cli_parse(cmd, argc - 1, argv + 1, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    if (vg_cli_require(cmd, "--participant", o.participant) || vg_cli_require(cmd, "--out", o.out))
        return 2;
    vg_status dst = display_cli_load(&o.display);
    if (dst != VG_OK)
        return vg_status_exit_code(dst);
    o.win.display_file = o.display.file;
    if (!study_participant_valid(o.participant)) {
        vg_error("%s --participant: '%s' is not a valid id (1-64 letters, digits, '-', '_', '.')", cmd->name,
                 o.participant);
        return 2;
    }
    /* The preference study shows the three scenes of --scene's folder: a
     * scene of another folder is named with the one found missing. */
    for (int k = 0; !hit && o.scene && k < PREF_SCENES; k++) {
        char path[4096];
        if (pref_scene_path(o.scene, k, path, sizeof path) == VG_OK && access(path, F_OK) != 0) {
            vg_error("study preference --scene %s: the study shows balloon, cubes and arena from the folder of "
                     "--scene (it names that folder's arena.gltf), and %s is not there", o.scene, path);
            return vg_status_exit_code(VG_ERR_IO);
        }
    }
    o.cmd = cmd;
    return vg_status_exit_code(hit ? study_hit_run(&o) : study_preference_run(&o));
}

const vg_cmd vg_cmd_study = {
    .name = "study",
    .summary = "run the hit-prediction or the preference study and log it as CSV",
    .usage = "vergence study hit|preference --participant ID --out FILE.csv [options]",
    .run = run,
};
