/* vergence — the ball's own figures (issue 39). */
#include "ball_measure.h"

#include <math.h>
#include <stdlib.h>

#include "core/log.h"
#include "observer.h"
#include "observer_engine.h"
#include "stereo/stereo_perception.h"

bool ball_figures_add(ball_figures *b, const frame *fr, const game_throw *th, double t_launch, const uint32_t *ids)
{
    const frame_desc *fd = frame_get_desc(fr);
    const frame_times *t = frame_get_times(fr);
    long launch = lround(t_launch * fd->fps), stride = fd->keyframe_stride;
    long k = t->index - launch;
    if (k < 0 || k >= lround(th->visible_s * fd->fps))
        return false;
    if (!b->started)
        *b = (ball_figures){.min_pixels = -1, .min_samples = -1, .started = true};
    const frame_outputs *o = frame_get_outputs(fr);
    if (!o->ids || !o->g || !o->h || !o->f)
        return false; /* a frame without the maps (no stereo render, two cameras showing g): nothing to measure */
    bool key = k % stride == 0 && b->keys < BALL_MEASURE_MAX_KEYS;
    bool in_turn = b->next_frame == k && b->frames < BALL_MEASURE_MAX_FRAMES;
    frame_info info;
    frame_get_info(fr, &info);
    uint32_t w = fd->width, h = fd->height, s = info.grid_stride;
    double dh = 0, df = 0;
    int px = 0, samples = 0;
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            if (!observer_is_node_id(ids, o->ids[i]))
                continue;
            dh += (double)o->h[i] - o->g[i], df += (double)o->f[i] - o->g[i], px++;
            /* A grid sample is the pixel q s + floor(s / 2) (docs/method.md
             * §4; the clamped last column or row is not counted). */
            samples += s && x % s == s / 2 && y % s == s / 2;
        }
    if (!px) {
        b->next_frame = -1;
        return false;
    }
    double g = game_ball_vergence(fr, frame_get_camera(fr), th, (double)k / fd->fps);
    if (in_turn) {
        int n = b->frames++;
        b->fg[n] = g, b->fh[n] = g + dh / px, b->ff[n] = g + df / px;
        b->next_frame = (int)k + 1;
    } else if (b->next_frame != k)
        b->next_frame = -1;
    if (!key)
        return true;
    int n = b->keys++;
    b->g[n] = g, b->h[n] = g + dh / px, b->f[n] = g + df / px;
    b->min_pixels = b->min_pixels < 0 || px < b->min_pixels ? px : b->min_pixels;
    b->min_samples = b->min_samples < 0 || samples < b->min_samples ? samples : b->min_samples;
    return true;
}

void ball_figures_finish(ball_figures *b, double keyframe_seconds, double fps)
{
    b->h_jnd = observer_track_mid_distortion(b->h, b->g, b->keys, 1, 1.0 / keyframe_seconds, STEREO_WEBER_K);
    b->f_jnd = observer_track_mid_distortion(b->f, b->g, b->keys, 1, 1.0 / keyframe_seconds, STEREO_WEBER_K);
    b->max_f_minus_h = b->max_f_minus_h_frame = 0;
    for (int i = 0; i < b->keys; i++)
        b->max_f_minus_h = fmax(b->max_f_minus_h, fabs(b->f[i] - b->h[i]));
    /* Only a run of every frame from the launch: a capture that starts
     * later, or a measure of keyframes alone, has none. */
    if (b->frames < 2 * (int)lround(keyframe_seconds * fps))
        b->frames = 0;
    bool run = b->frames >= 3;
    b->h_frame_jnd = run ? observer_track_mid_distortion(b->fh, b->fg, b->frames, 1, fps, STEREO_WEBER_K) : NAN;
    b->f_frame_jnd = run ? observer_track_mid_distortion(b->ff, b->fg, b->frames, 1, fps, STEREO_WEBER_K) : NAN;
    for (int i = 0; i < b->frames; i++)
        b->max_f_minus_h_frame = fmax(b->max_f_minus_h_frame, fabs(b->ff[i] - b->fh[i]));
}

struct ball_measure {
    ball_measure_desc d;
    frame *frame;
    uint32_t *ids;
};

vg_status ball_measure_create(const ball_measure_desc *desc, ball_measure **out)
{
    *out = NULL;
    ball_measure *m = calloc(1, sizeof *m);
    if (!m || !(m->ids = observer_node_ids(desc->scene, desc->ball->node))) {
        free(m);
        return VG_ERR_NOMEM;
    }
    m->d = *desc;
    /* Optimized: g, h and f all come back from one frame. */
    frame_desc fd = observer_maps_frame(&desc->frame, FRAME_MODE_OPTIMIZED);
    vg_status st = frame_create(desc->gpu, desc->scene, &fd, &m->frame);
    if (st != VG_OK) {
        ball_measure_destroy(m);
        return st;
    }
    *out = m;
    return VG_OK;
}

void ball_measure_destroy(ball_measure *m)
{
    if (!m)
        return;
    frame_destroy(m->frame);
    free(m->ids);
    free(m);
}

vg_status ball_measure_throw(ball_measure *m, const game_throw *th, long launch, ball_figures *out)
{
    const frame_desc *fd = frame_get_desc(m->frame);
    long stride = fd->keyframe_stride;
    m->d.ball->th = *th;
    m->d.ball->t_launch = launch / fd->fps;
    *out = (ball_figures){0};
    frame_restart(m->frame);
    vg_status st = VG_OK;
    long step = m->d.every_frame ? 1 : stride;
    for (long index = launch - stride; index < launch + lround(th->visible_s * fd->fps) && st == VG_OK;
         index += index < launch ? stride : step)
        if ((st = frame_render(m->frame, index)) == VG_OK && index >= launch &&
            !ball_figures_add(out, m->frame, th, m->d.ball->t_launch, m->ids)) {
            vg_error("ball measure: the ball covers no pixel at frame %ld", index);
            st = VG_ERR_ARG;
        }
    if (st == VG_OK)
        ball_figures_finish(out, stride / fd->fps, fd->fps);
    return st;
}
