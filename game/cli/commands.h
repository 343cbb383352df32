/* vergence — the subcommands of the one executable. */
#pragma once
#include "core/cli.h"

/* Each command module defines one of these (game/cmd_*.c). */
extern const vg_cmd vg_cmd_info;
extern const vg_cmd vg_cmd_capture;
extern const vg_cmd vg_cmd_optimize;
extern const vg_cmd vg_cmd_play, vg_cmd_study;
extern const vg_cmd vg_cmd_bake_curve;
extern const vg_cmd vg_cmd_demo;
extern const vg_cmd vg_cmd_bench;
