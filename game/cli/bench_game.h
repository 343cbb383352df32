/* vergence bench --game: the game's frame rate in each mode at its
 * defaults, with the same replay every run (bench_game.c). */
#pragma once
#include "bench_report.h"
#include "core/status.h"
#include "gpu/gpu.h"
#include "scene/scene.h"
#include "stereo/stereo_display.h"

/* `frames` frames a mode after a warm-up frame, the clock advanced `ticks`
 * 1/60 s ticks a frame; the table goes to `rep`. The scene (play's arena)
 * needs a node named 'ball'; its pose hook is the bench's until it returns. */
vg_status bench_game(gpu *g, scene *sc, const char *scene_path, stereo_display_desc display, int frames, int ticks,
                     bench_report *rep);
/* The ball's own MID distortion under h and f (issue 39): per_kind throws of
 * each kind (path x direction) as free play draws them, at the game's
 * defaults, at its keyframes (every_frame: at the frame rate, every frame of
 * the flight rendered); each: a line per throw too. */
vg_status bench_ball(gpu *g, scene *sc, const char *scene_path, stereo_display_desc display, int per_kind,
                     bool every_frame, bool each, bench_report *rep);
