/* vergence — the causal window on the CPU (`optimize --look-ahead causal`,
 * docs/method.md "Look-ahead").
 *
 * The engine's window (paper 4.5) slides one keyframe at a time over
 * keyframes [k - past, k + future]; with perfect foresight its future is
 * the sequence itself. A host without the future has keyframes up to k
 * only: here every later keyframe of the window is predicted from k and
 * k - 1 alone by extrapolating the disparity field along its flow (a
 * sample goes on at the image velocity and the rates of change of g, h
 * and depth it had from k - 1 to k, splatted forward to the nearest grid
 * sample, the nearest surface winning; what nothing lands on takes the
 * farther of its row neighbours, as image warping fills holes). Each move
 * solves the window warm-started from the last one and publishes the
 * ratio f / h of keyframe k + 2 (the first window: k .. k + 2), as the
 * GPU's mid.solve does; f at a keyframe is its observed h times the
 * published ratio. So f at keyframe j uses data up to keyframe j - 2:
 * the frames from j - 1 on depend on nothing after them. Without a true
 * future the solve's f does worse than h wherever motion changes within
 * the window, so what is published passes the gate first (mid_shared.h
 * MID_GATE_*, the GPU's publish.gate): the correction shows only where it
 * was measured better than h on the keyframes already shown. Measured in
 * docs/method.md section 15. */
#pragma once
#include "core/status.h"
#include "mid_solver.h"
#include "mid_window.h"

typedef struct mid_causal_desc {
    int past, future;         /* keyframes of the window behind and ahead of k (future >= 2) */
    mid_solve_desc solve;     /* the first window's solve; later ones take MID_GN_WARM_ITERATIONS
                                 (Gauss-Newton) unless solve.iterations is set; f_init is ignored */
    float keyframe_seconds;   /* dt of intervals after the sequence's last keyframe, 0 = its last interval's */
    bool gate;                /* publish h + gain (f - h), the gain measured on realized keyframes
                                 (mid_shared.h MID_GATE_*); false: f as solved */
    float *ungated;           /* optional: all->n values, f as solved (each keyframe's h times the
                                 ratio its solve gave, before the gate), clamped to the range */
} mid_causal_desc;

typedef struct mid_causal_stats {
    int windows;              /* solves (window moves) */
    double ms;                /* wall time of every solve */
    double cost_initial, cost_final; /* the last window's */
} mid_causal_stats;

/* `all` holds every keyframe as observed (inputs only: no build needed). f
 * gets all->n values: each keyframe's h times the ratio published for it,
 * clamped to the range. */
vg_status mid_causal_solve(const mid_window *all, const mid_causal_desc *desc, float *f, mid_causal_stats *stats);

/* Keyframes k + 1 .. k + count of `obs` predicted from k and k - 1 (k = 0:
 * held still) into w's keyframes dst .. dst + count - 1: g, h, depth, id,
 * unknown and both flows. VG_ERR_NOMEM when its scratch cannot be had. */
vg_status mid_causal_predict(const mid_window *obs, int k, int count, mid_window *w, int dst);
