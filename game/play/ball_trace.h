/* vergence — the ball as the player was shown it (issue 39): what the
 * in-game toggle did to its motion in depth, measured on the frames the
 * game showed, drawn in the HUD after the throw.
 *
 * Each shown frame of a throw's visible flight adds a sample: the ball's
 * exact g (its centre through the frame's rig) and, from the frame's probe
 * (frame_desc.probe_ids: the ball's instance ids), its shown vergence
 * g + mean(shown map - g) over its pixels. The shown map is the mode's
 * (g, h or f), so the original mode shows g exactly. The chart plots the
 * ball's perceived velocity in depth, p(v) in JND (stereo_perception.h),
 * over the flight for g and for what was shown, with samples at least one
 * keyframe interval apart (the paper's 100 ms windows); its caption gives
 * the paper's MID distortion of the shown track against g on those samples
 * (docs/game.md "What the toggle does to the ball"). */
#pragma once
#include "frame/frame.h"
#include "rules/game.h"

#define BALL_TRACE_MAX 256
#define BALL_TRACE_MIN_SAMPLES 3   /* fewer: no acceleration to measure */

typedef struct ball_trace {
    int count;
    double t[BALL_TRACE_MAX];      /* seconds since the launch */
    double g[BALL_TRACE_MAX];      /* the ball's g, arcmin */
    double shown[BALL_TRACE_MAX];  /* as shown, arcmin */
    uint32_t pixels[BALL_TRACE_MAX];
} ball_trace;

/* The figures of a trace, on its samples a keyframe interval apart. */
typedef struct ball_trace_figures {
    int samples;                   /* used (>= BALL_TRACE_MIN_SAMPLES for a measure) */
    double mid_jnd;                /* MID distortion of shown against g, JND; NAN below the minimum */
    double max_shown_minus_g;      /* largest |shown - g| on them, arcmin */
    int speeds;                    /* perceived velocities in depth: samples - 1 */
    double t[BALL_TRACE_MAX];      /* the middle of each interval, seconds since the launch */
    double p_g[BALL_TRACE_MAX], p_shown[BALL_TRACE_MAX]; /* JND */
} ball_trace_figures;

/* Adds the probe of a frame of fr (already completed; index in probe) when
 * it lies in th's visible flight (launched at t_launch s) and shows the
 * ball; cam is the centre camera the frame renders from. */
bool ball_trace_add(ball_trace *tr, const frame *fr, const vg_camera *cam, const game_throw *th, double t_launch,
                    const frame_probe *probe);
/* The figures, on samples at least keyframe_s - 1e-6 apart. */
void ball_trace_figures_of(const ball_trace *tr, double keyframe_s, ball_trace_figures *out);
/* The HUD chart of the figures: g in white, the shown track in rgb. */
void ball_trace_chart(const ball_trace_figures *f, double visible_s, const char *shown_label, const uint8_t rgb[3],
                      frame_hud_chart *out);
