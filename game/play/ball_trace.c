/* vergence — the ball as the player was shown it (ball_trace.h). */
#include "ball_trace.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "stereo/stereo_perception.h"

bool ball_trace_add(ball_trace *tr, const frame *fr, const vg_camera *cam, const game_throw *th, double t_launch,
                    const frame_probe *probe)
{
    double fps = frame_get_desc(fr)->fps, t = probe->index / fps - t_launch;
    if (tr->count >= BALL_TRACE_MAX || !probe->pixels || t < -1e-9 || t >= th->visible_s - 1e-9 ||
        (tr->count && t <= tr->t[tr->count - 1]))
        return false;
    int n = tr->count++;
    tr->t[n] = t;
    tr->g[n] = game_ball_vergence(fr, cam, th, t);
    tr->shown[n] = tr->g[n] + probe->shown_minus_g;
    tr->pixels[n] = probe->pixels;
    return true;
}

void ball_trace_figures_of(const ball_trace *tr, double keyframe_s, ball_trace_figures *out)
{
    memset(out, 0, sizeof *out);
    double t[BALL_TRACE_MAX], g[BALL_TRACE_MAX], x[BALL_TRACE_MAX];
    int m = 0;
    for (int i = 0; i < tr->count; i++)
        if (!m || tr->t[i] >= t[m - 1] + keyframe_s - 1e-6) {
            t[m] = tr->t[i], g[m] = tr->g[i], x[m] = tr->shown[i];
            out->max_shown_minus_g = fmax(out->max_shown_minus_g, fabs(x[m] - g[m]));
            m++;
        }
    out->samples = m;
    for (int i = 0; i + 1 < m; i++) {
        double dt = t[i + 1] - t[i];
        out->t[i] = 0.5 * (t[i] + t[i + 1]);
        out->p_g[i] = stereo_p((g[i + 1] - g[i]) / dt, STEREO_WEBER_K);
        out->p_shown[i] = stereo_p((x[i + 1] - x[i]) / dt, STEREO_WEBER_K);
    }
    out->speeds = m > 1 ? m - 1 : 0;
    out->mid_jnd = m >= BALL_TRACE_MIN_SAMPLES ? stereo_track_mid_distortion(x, g, t, m, STEREO_WEBER_K) : NAN;
}

void ball_trace_chart(const ball_trace_figures *f, double visible_s, const char *shown_label, const uint8_t rgb[3],
                      frame_hud_chart *out)
{
    memset(out, 0, sizeof *out);
    out->visible = true;
    /* Speeds (|p|), the direction in the title: a throw keeps its direction. */
    double lo = INFINITY, hi = 0, away = 0;
    for (int i = 0; i < f->speeds; i++) {
        lo = fmin(lo, fmin(fabs(f->p_g[i]), fabs(f->p_shown[i])));
        hi = fmax(hi, fmax(fabs(f->p_g[i]), fabs(f->p_shown[i])));
        away += f->p_g[i];
    }
    snprintf(out->title, sizeof out->title, "ball's speed %s, JND", away < 0 ? "away" : "toward you");
    out->x0 = 0, out->x1 = (float)visible_s;
    out->y0 = f->speeds ? (float)(5 * floor(lo / 5)) : 0, out->y1 = (float)(5 * ceil(hi / 5));
    if (out->y1 < out->y0 + 10)
        out->y1 = out->y0 + 10;
    out->series_count = 2;
    for (int s = 0; s < 2; s++) {
        frame_hud_series *se = &out->series[s];
        se->count = f->speeds < FRAME_HUD_CHART_POINTS ? f->speeds : FRAME_HUD_CHART_POINTS;
        for (int i = 0; i < se->count; i++)
            se->x[i] = (float)f->t[i], se->y[i] = (float)fabs(s ? f->p_shown[i] : f->p_g[i]);
    }
    memcpy(out->series[0].rgb, (uint8_t[3]){235, 235, 235}, 3);
    snprintf(out->series[0].label, sizeof out->series[0].label, "true g");
    memcpy(out->series[1].rgb, rgb, 3);
    snprintf(out->series[1].label, sizeof out->series[1].label, "shown %s", shown_label);
    if (f->samples < BALL_TRACE_MIN_SAMPLES)
        snprintf(out->caption, sizeof out->caption, "%d frames of the flight shown: too few", f->samples);
    else
        snprintf(out->caption, sizeof out->caption, "distortion vs true: %.1f JND", f->mid_jnd);
}
