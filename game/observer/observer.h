/* vergence — the simulated observer (docs/game.md "The simulated observer").
 *
 * A player of the hit game: it sees where the ball is on the screen and the
 * depth its displayed vergence implies (no shading or shadow cues) and,
 * with .size_cue, the ball's changing angular size too: the two feed one
 * motion-in-depth stage as their sum in angular units (Regan and Beverley
 * 1979; the sum of looming and changing disparity, Duke and Rushton 2012),
 * so each weighs by how fast it changes. Per shown frame it takes the ball's image
 * position and displayed vergence a (g, h or f: observer_view), perceives
 * the vergence velocity with Weber noise (paper Sec. 4.2: one JND of noise
 * in p(v) = sign(v) ln(1 + |v|) / k per 100 ms integration window), turns
 * vergence into distance through the display model and the original stereo
 * camera (it is calibrated to unmodified stereo), fits the visible path
 * (straight: linear in t; ballistic: linear plus known gravity), follows
 * the fit until its lowest point meets the ground as it is displayed (the
 * surround's vergence through the same decoding) and clicks there. The
 * click is scored like a player's (game_click_error). Deterministic for a
 * seed: all noise comes from the trial's random stream. */
#pragma once
#include "rules/game.h"
#include "observer_view.h"

typedef struct observer_desc {
    observer_view_desc view;     /* .moving_node = the ball */
    double weber_k;              /* Weber fraction k, 0 = STEREO_WEBER_K; < 0: no noise */
    double window_s;             /* temporal integration window, 0 = 0.1 s */
    bool size_cue;               /* hit: also the ball's angular size (the two-cue observer) */
} observer_desc;

typedef struct observer observer;

typedef struct observer_result {
    double click_u, click_v;     /* centre image, [0, 1] */
    double error_m;              /* the paper's error (game_click_error) */
    double perceived_ground[3];  /* where the fit met the displayed ground (decoded world space) */
    int frames_seen;
    double ball_mid_jnd;         /* the paper's MID distortion of the ball's shown vergence against g over
                                    the visible flight, at the keyframes (0 under g; NAN: fewer than 3) */
} observer_result;

vg_status observer_create(const observer_desc *desc, observer **out);
void observer_destroy(observer *o);
const vg_camera *observer_camera(const observer *o);

/* Watches the throw's visible interval under `mode` and clicks: the
 * ball's vergence from `shown` (the engine's frames of the throw,
 * observer_engine) or, NULL, from the CPU view (observer_view). */
vg_status observer_play(observer *o, const game_throw *th, frame_mode mode, const observer_shown *shown,
                        game_rng *noise, observer_result *out);

/* Preference (two-alternative forced choice): which of two tracks of the
 * same motion, shown as modes[0] (a) and modes[1] (b), moves more like the
 * reference shown as modes[2]? Compares perceived velocity changes in JND
 * (paper Sec. 4.2: per 100 ms window, with the same Weber noise); each
 * track from shown[s] (the engine's frames) or, NULL, the CPU view. */
typedef struct observer_choice {
    int side;             /* 0: a, 1: b */
    double compared[2];   /* what it compared: the sum of squared differences of its (noisy) perceived
                             velocity changes from the reference's, JND^2; the smaller one wins */
    double mid_jnd[2];    /* the paper's measure, noiseless: MID distortion of the side against the
                             reference over the keyframes (docs/method.md §11), JND */
} observer_choice;
/* The paper's measure on a track of n frames at fps, noiseless
 * (docs/method.md §11 on one sample): RMS over the keyframes (every
 * `stride` frames) where `ref` moves in depth (>= 1 arcmin/s) of
 * [p(v+(x)) - p(v-(x))] - [p(v+(ref)) - p(v-(ref))], JND for Weber k. */
double observer_track_mid_distortion(const double *x, const double *ref, int n, int stride, double fps, double k);
vg_status observer_prefer(observer *o, const double (*pos)[3], int count, const frame_mode modes[3],
                          const observer_shown *const shown[3], game_rng *noise, observer_choice *out);
