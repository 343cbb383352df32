/* vergence bench MODE — the benchmarks of one part of the engine, each a mode
 * of `vergence bench` with its own options (cmd_bench.c picks the mode by
 * its word: `vergence bench gbuffer --frames 5`). */
#pragma once
#include <stdbool.h>

#include "bench_report.h"
#include "core/cli.h"
#include "core/status.h"

extern const vg_cmd vg_cmd_bench_gbuffer;   /* bench_gbuffer.c: shadow and G-buffer ms at two sizes */
extern const vg_cmd vg_cmd_bench_solver;    /* bench_solver.c: the CPU MID solver, speed and quality */
extern const vg_cmd vg_cmd_bench_disparity; /* bench_disparity.c: the GPU disparity passes at two sizes */
extern const vg_cmd vg_cmd_bench_warp;      /* bench_warp.c: warp ms per eye against tessellation */

/* The CPU solver's tables (the one solver benchmark: `vergence bench solver`,
 * and `vergence bench` without --no-solver): the STREAM triad and each
 * solver's ms per window with 1 and all threads, medians of `runs` (1..15);
 * with `quality`, the cost and MID distortion each reaches against a long
 * reference solve. */
vg_status bench_solver_tables(bench_report *r, int runs, bool quality);
