/* vergence — the ball's own figures (issue 39): what the game's manipulation
 * and optimisation do to the thing a player judges, measured on the ball's
 * pixels in the engine's frames, not on the frame's average.
 *
 * At each keyframe of a throw's visible flight (the launch on), the ball's
 * displayed vergence under h and f is the exact g of its centre (through
 * the frame's rig) plus the mean of (map - g) over the pixels whose
 * instance id is the ball's (observer_engine's displacement). Its MID
 * distortion is the paper's measure on that one track (docs/method.md §11:
 * RMS over the keyframes where g moves in depth of the perceived
 * acceleration's difference from g's, JND). The keyframe before the launch
 * is in the solver's window (the ball rests there, as in play) but not in
 * the measure: from rest the perceived acceleration is p(v) - p(0), and p's
 * slope at 0 (1 / k JND per arcmin/s) would count an imperceptible drift of
 * the resting ball, a tenth of an arcmin, as JNDs.
 *
 * Where every frame of the flight was rendered (a capture, or
 * ball_measure_desc.every_frame), the same measure at the frame rate too:
 * what a player sees between keyframes, where the upsampling in time makes
 * f (docs/method.md §8). */
#pragma once
#include "frame/frame.h"
#include "rules/game.h"

#define BALL_MEASURE_MAX_KEYS 16
#define BALL_MEASURE_MAX_FRAMES 256

typedef struct ball_figures {
    double h_jnd, f_jnd;         /* MID distortion of the ball's h and f against g at the keyframes, JND */
    int keys;                    /* keyframes of the flight measured */
    double g[BALL_MEASURE_MAX_KEYS], h[BALL_MEASURE_MAX_KEYS], f[BALL_MEASURE_MAX_KEYS]; /* arcmin */
    double max_f_minus_h;        /* largest |f - h| of the ball at a keyframe, arcmin */
    int min_pixels;              /* fewest ball pixels at a keyframe */
    int min_samples;             /* fewest solver grid samples on the ball at a keyframe */
    /* Every frame from the launch on, while each was added in turn: */
    int frames;                  /* frames of the flight measured (0: not every frame was rendered) */
    double h_frame_jnd, f_frame_jnd; /* the MID distortions at the frame rate (NAN: under 3 frames) */
    double max_f_minus_h_frame;  /* largest |f - h| of the ball at any frame, arcmin */
    double fg[BALL_MEASURE_MAX_FRAMES], fh[BALL_MEASURE_MAX_FRAMES], ff[BALL_MEASURE_MAX_FRAMES]; /* arcmin */
    int next_frame;              /* the flight's frame the next one must be (-1: the run broke) */
    bool started;                /* a frame of the flight was added */
} ball_figures;

/* Adds frame fr's outputs (readback, just rendered) to b when it is a frame
 * of th's visible flight (launched at t_launch seconds); the ball's
 * instance ids are `ids` (0-terminated; observer_node_ids). Keyframes count
 * in the keyframe figures; every frame, while they come in turn from the
 * launch, in the frame-rate figures. False when it was not added (not in
 * the flight, the frame made no maps g, h and f, or the ball covers no
 * pixel there). b starts zeroed. */
bool ball_figures_add(ball_figures *b, const frame *fr, const game_throw *th, double t_launch, const uint32_t *ids);
/* The MID distortions of what was added. */
void ball_figures_finish(ball_figures *b, double keyframe_seconds, double fps);

typedef struct ball_measure_desc {
    gpu *gpu;
    const scene *scene;          /* the caller's, with game_ball_attach(scene, ball) done */
    game_ball *ball;             /* its throw and launch are set by ball_measure_throw */
    frame_desc frame;            /* the game's frame (mode, readback and maps_only are set here) */
    bool every_frame;            /* render every frame of the flight, not only its keyframes (10x the work) */
} ball_measure_desc;

typedef struct ball_measure ball_measure;

vg_status ball_measure_create(const ball_measure_desc *desc, ball_measure **out);
void ball_measure_destroy(ball_measure *m);
/* Throws th at frame `launch` (a keyframe), renders headless (maps only)
 * the keyframe before it and every keyframe (every_frame: every frame) of
 * its visible flight after a restart of the window, and measures the ball. */
vg_status ball_measure_throw(ball_measure *m, const game_throw *th, long launch, ball_figures *out);
