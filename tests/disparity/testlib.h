/* Shared by the disparity tests: synthetic windows and an independent
 * double-precision evaluation of the MID cost (the finite-difference oracle). */
#pragma once
#include "disparity/disp_operator.h"
#include "disparity/mid_solver.h"
#include "disparity/mid_window.h"
#include "stereo/stereo_display.h"

typedef enum synth_motion {
    SYNTH_CONSTANT_SPEED = 0,  /* vergence linear in time */
    SYNTH_CONSTANT_ACCEL,      /* vergence quadratic in time, starting at rest */
} synth_motion;

typedef struct synth_desc {
    int nx, ny, nt;            /* coarse window, 0 = 48 x 27 x 16 */
    synth_motion motion;
    disp_operator_kind op;     /* h from g per keyframe, 0 = lang */
    bool h_equals_g;           /* h = g and every value inside the target range */
    bool salient_ball;         /* saliency 1 on the ball, 0.1 elsewhere */
} synth_desc;

/* A scene of static layers at several depths and a ball crossing them in
 * depth while moving sideways (the paper's Fig. 1/2 situation): the far wall,
 * a band at 3 m, a band at 1.5 m, a post at 0.9 m; the ball goes from about
 * 6.4 m to 0.97 m. Built window (links, targets) with the default display's
 * target range a_s +- 60 arcmin, dt = 1/6 s. Returns NULL on failure. */
mid_window *synth_window(const synth_desc *desc);
/* 1 where the ball is at keyframe k (coarse pixel p). */
bool synth_is_ball(const synth_desc *desc, int k, int x, int y);

/* A random window for derivative checks: random g, h, depth layers that make
 * occlusions, random flows (some out of frame), uneven keyframe intervals. */
mid_window *random_window(int nx, int ny, int nt, unsigned seed);
/* Uniform random float in [lo, hi) from a 32-bit state. */
float rnd_uniform(unsigned *state, float lo, float hi);

/* c(f) in double, written from the equations of Sec. 4.1/4.3 term by term
 * (no adjoints, targets recomputed in double): the oracle for the gradient. */
double reference_cost(const mid_window *w, mid_weights wt, const double *f);
