/* vergence — a synthetic keyframe window for the solver benchmark
 * (`vergence bench solver`, and `vergence bench`): the paper's 1:5 / 1:10
 * subsampling of 960x540 at 60 Hz over 5.3 s. Static layers at several
 * depths and six balls crossing them in depth while moving sideways
 * (alternately at constant speed and constant acceleration in depth); h from
 * the lang operator. */
#pragma once
#include "mid_window.h"

#define MID_SYNTH_NX 192
#define MID_SYNTH_NY 108
#define MID_SYNTH_NT 32

/* The built window (mid_window_build done), or NULL when out of memory. */
mid_window *mid_synth_window(void);
