/* vergence — the hit game in a window: throws, input, HUD, frames per mode. */
#include "play_session.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/clock.h"
#include "core/io.h"
#include "core/log.h"
#include "core/manifest.h"
#include "ball_trace.h"
#include "window.h"

#define READY_S 1.0      /* the ball rests at its launch point before a throw */
#define FEEDBACK_S 3.0   /* free play: how long the true landing spot is shown */
#define NOTICE_S 2.5     /* on-screen notices (a mode that is not available) */

typedef enum phase {
    PHASE_DEFAULT = 0,
    PHASE_READY,         /* ball at its launch point */
    PHASE_FLIGHT,        /* visible interval */
    PHASE_AIM,           /* ball gone: waiting for the click */
    PHASE_FEEDBACK,      /* ball on its true landing spot (free play) */
    PHASE_DONE,          /* study finished */
} phase;

typedef struct session {
    const play_session_desc *d;
    bool study;
    window *win;
    scene *scene;
    int ball;
    float ball_scale[3];
    vg_camera cam;               /* the centre camera at the eye image's aspect */
    vg_camera cam_ref;           /* 16:9: throws do not depend on the window's shape */
    frame *frames[FRAME_MODE_OPTIMIZED + 1];
    /* A study: each throw's flight rendered ahead by a headless frame of its
     * condition, shown from memory (flight.h). */
    flight *fl;
    frame *flight_frames[FRAME_MODE_OPTIMIZED + 1];
    bool flight_ready;
    flight_record shown;
    bool unavailable[FRAME_MODE_OPTIMIZED + 1];
    frame_mode mode;
    uint32_t rw, rh;             /* eye image size */
    frame_compose compose;       /* the output layout (L cycles it) */
    bool swap_eyes;              /* E */
    /* game */
    double clock;                /* game seconds */
    bool paused, quit, hud_tech;
    phase ph;
    game_throw th;
    double t_launch, t_hide, t_landed, t_phase;
    int throw_no, trial, throws_scored, score;
    double miss_sum, last_miss;
    double picked_m, landed_m;   /* feedback: ground distances of the click and of the landing spot */
    double click_u, click_v;     /* feedback: where the player clicked (centre image) */
    /* The ball as shown (free play): its trace over the throw's flight, from
     * the probe of the frames shown (ball_trace.h). */
    uint32_t ball_ids[FRAME_PROBE_MAX_IDS];
    ball_trace trace;
    frame_mode trace_mode;
    bool trace_mixed;            /* the mode changed during the flight */
    bool trace_said;
    /* display */
    frame_hud hud;
    char notice[FRAME_HUD_LINE];
    double notice_until, fps;
    bool replay_done_said;
} session;

static const char *const k_mode_text[] = {"", "original (g)", "manipulated (h)", "optimized (f)"};
/* The mode badge (free play; a study shows no condition). */
static const char *const k_mode_badge[] = {"", "ORIGINAL  g", "MANIPULATED  h", "OPTIMIZED  f"};
static const uint8_t k_mode_rgb[][3] = {{0, 0, 0}, {150, 200, 255}, {255, 182, 92}, {124, 230, 150}};

/* ------------------------------------------------------------------------- */
/* The ball (scene pose hook)                                                */
/* ------------------------------------------------------------------------- */

static void ball_pose(void *user, const scene *s, float t, float *local)
{
    (void)s;
    const session *ss = user;
    bool shown = ss->ph != PHASE_DEFAULT && ss->ph != PHASE_DONE;
    if (t >= ss->t_hide && t < ss->t_landed)
        shown = false; /* the paper's "shown only for a short initial interval" */
    game_ball_local(&ss->th, ss->t_launch, t, shown, ss->ball_scale, local + (size_t)ss->ball * 10);
}

/* ------------------------------------------------------------------------- */
/* Throws                                                                    */
/* ------------------------------------------------------------------------- */

static void throw_next(session *ss)
{
    const play_session_desc *d = ss->d;
    if (ss->study) {
        game_cell c = game_hit_cell(d->cells[ss->trial]);
        game_throw_desc td = {.path = c.path, .direction = c.direction, .visible_s = d->visible_s};
        ss->mode = (frame_mode)(FRAME_MODE_ORIGINAL + c.condition);
        game_rng r = game_rng_make(d->seed, 2 * (uint64_t)ss->trial + 1); /* as the simulated observer's */
        game_throw_make(&td, &ss->cam_ref, &r, &ss->th);
    } else {
        game_throw_free_play(d->seed, ss->throw_no, d->visible_s, &ss->cam_ref, &ss->th);
    }
    ss->throw_no++;
    /* The ball's future changed: keyframes predicted for it are stale. */
    for (int m = 0; m <= FRAME_MODE_OPTIMIZED; m++)
        frame_restart(ss->frames[m]);
    /* Launch on a keyframe (paper 4.4: every 10th frame), a second from now. */
    long launch = (long)ceil((ss->clock + READY_S) * 60.0 / 10.0) * 10;
    ss->t_launch = launch / 60.0;
    ss->t_hide = ss->t_launch + ss->th.visible_s;
    ss->t_landed = INFINITY;
    ss->flight_ready = false;
    ss->trace.count = 0;
    ss->trace_mode = ss->mode;
    ss->trace_mixed = ss->trace_said = false;
    ss->ph = PHASE_READY;
    ss->t_phase = ss->clock;
}

static void restart(session *ss)
{
    ss->throw_no = ss->throws_scored = ss->score = 0;
    ss->miss_sum = ss->last_miss = 0;
    vg_info("play: restart");
    throw_next(ss);
}

static vg_status on_click(session *ss, double x, double y)
{
    VkExtent2D e = window_extent(ss->win);
    double u, v;
    if (ss->ph == PHASE_FEEDBACK) {
        throw_next(ss);
        return VG_OK;
    }
    if (ss->ph != PHASE_AIM || ss->paused ||
        !game_click_to_image(ss->compose, ss->rw, ss->rh, e.width, e.height, x, y, &u, &v))
        return VG_OK;
    double err = game_click_error(&ss->cam, u, v, ss->th.ground);
    vg_info("play: click at (%.3f, %.3f) of the picture: missed by %.2f m (%s, %s, %s)", u, v, err,
            k_mode_text[ss->mode], game_direction_names[ss->th.direction], game_path_names[ss->th.path]);
    if (ss->study) {
        ball_trace_figures fig;
        const frame_desc *fd = frame_get_desc(ss->flight_frames[ss->mode]);
        ball_trace_figures_of(&ss->trace, fd->keyframe_stride / fd->fps, &fig);
        play_trial t = {.trial = ss->trial, .th = &ss->th, .mode = ss->mode, .click_u = u, .click_v = v,
                        .error_m = err, .response_s = ss->clock - ss->t_hide, .flight = ss->shown,
                        .ball_mid_jnd = fig.mid_jnd};
        vg_status st = ss->d->on_trial(ss->d->user, &t);
        if (st != VG_OK)
            return st;
        if (++ss->trial >= ss->d->trial_count) {
            ss->ph = PHASE_DONE;
            return VG_OK;
        }
        throw_next(ss);
        return VG_OK;
    }
    ss->click_u = u, ss->click_v = v;
    /* Where the click meets the ground (the sky: nowhere) and where the ball landed. */
    double o[3], dir[3];
    game_ray(&ss->cam, u, v, o, dir);
    ss->picked_m = dir[1] < -1e-6 ? -o[1] / dir[1] * hypot(dir[0], dir[2]) : INFINITY;
    ss->landed_m = hypot(ss->th.ground[0] - o[0], ss->th.ground[2] - o[2]);
    int pts = game_points(err);
    ss->score += pts;
    ss->throws_scored++;
    ss->miss_sum += err;
    ss->last_miss = err;
    ss->ph = PHASE_FEEDBACK;
    ss->t_phase = ss->clock;
    /* From the frame being shown on (frames render at whole 1/60 s). */
    ss->t_landed = floor(ss->clock * 60.0) / 60.0;
    return VG_OK;
}

static vg_status flight_play(session *ss);

static vg_status update_phase(session *ss)
{
    if (ss->ph == PHASE_READY && ss->clock >= ss->t_launch) {
        ss->ph = PHASE_FLIGHT;
        if (ss->study)
            return flight_play(ss);
    }
    if (ss->ph == PHASE_FLIGHT && ss->clock >= ss->t_hide)
        ss->ph = PHASE_AIM;
    if (ss->ph == PHASE_FEEDBACK && ss->clock >= ss->t_phase + FEEDBACK_S)
        throw_next(ss);
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Frames: one per mode, made when first shown, dropped on resize            */
/* ------------------------------------------------------------------------- */

static void frames_drop(session *ss)
{
    for (int m = 0; m <= FRAME_MODE_OPTIMIZED; m++) {
        if (ss->frames[m]) {
            frame_wait_idle(ss->frames[m]);
            frame_destroy(ss->frames[m]);
            ss->frames[m] = NULL;
        }
        frame_destroy(ss->flight_frames[m]);
        ss->flight_frames[m] = NULL;
    }
    ss->flight_ready = false;
}

/* The eye size that fills the window in this layout; a CPU rasteriser gets
 * at most 480 pixels across (interleaved layouts need 1:1 pixels). */
static void choose_render_size(session *ss, bool announce)
{
    const play_window_cli *w = ss->d->win;
    frame_compose c = ss->compose;
    VkExtent2D e = window_extent(ss->win);
    bool interleaved = c == FRAME_COMPOSE_ROWS || c == FRAME_COMPOSE_COLUMNS || c == FRAME_COMPOSE_CHECKER;
    bool cpu = window_gpu(ss->win)->is_cpu;
    if (w->render[0] > 0) {
        ss->rw = (uint32_t)fmax(16, w->render[0]);
        ss->rh = (uint32_t)fmax(16, w->render[1]);
    } else {
        game_render_size(window_gpu(ss->win), c, e.width, e.height, &ss->rw, &ss->rh);
    }
    frame_desc fd = {0};
    game_frame_defaults(window_gpu(ss->win), w->tess_error, &fd);
    if (announce && cpu)
        vg_warn("play: %s is a CPU rasteriser: rendering %ux%u per eye%s, error-driven tessellation to %.2g px, "
                "to stay interactive (--render-size and --tess-error override)",
                window_gpu(ss->win)->props.deviceName, ss->rw, ss->rh,
                interleaved ? " (1:1 for the interleaved output: slow)" : "", fd.tess_error);
    scene_state st;
    if (scene_state_init(ss->scene, &st) == VG_OK) {
        scene_evaluate(ss->scene, 0.0f, &st);
        scene_camera_resolve(ss->scene, &st, 0, (float)ss->rw / (float)ss->rh, &ss->cam);
        scene_camera_resolve(ss->scene, &st, 0, 16.0f / 9.0f, &ss->cam_ref);
        scene_state_free(&st);
    }
}

/* The frame of a mode as the session shows it (the live frames and a
 * study's flight frames add what they need). */
static frame_desc session_frame_desc(const session *ss, frame_mode mode)
{
    const play_session_desc *d = ss->d;
    frame_desc fd = game_frame_desc(window_gpu(ss->win), d->win->tess_error, mode, ss->rw, ss->rh, ss->compose,
                                    d->op, ss->study, &ss->cam_ref);
    fd.display = d->display;
    fd.swap_eyes = ss->swap_eyes;
    fd.look_ahead = d->look_ahead;
    fd.budgeted_solve = !ss->study && !d->full_solve;
    return fd;
}

static vg_status frame_for(session *ss, frame_mode mode, frame **out)
{
    if (ss->frames[mode]) {
        *out = ss->frames[mode];
        return VG_OK;
    }
    const play_session_desc *d = ss->d;
    gpu *g = window_gpu(ss->win);
    VkExtent2D e = window_extent(ss->win);
    frame_desc fd = session_frame_desc(ss, mode);
    fd.present_format = window_format(ss->win);
    fd.present_width = e.width;
    fd.present_height = e.height;
    fd.readback = d->win->dump_f && mode == FRAME_MODE_OPTIMIZED;
    if (!ss->study)
        memcpy(fd.probe_ids, ss->ball_ids, sizeof fd.probe_ids);
    vg_status st = frame_create(g, ss->scene, &fd, &ss->frames[mode]);
    *out = ss->frames[mode];
    return st;
}

static void notice(session *ss, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void notice(session *ss, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(ss->notice, sizeof ss->notice, fmt, ap);
    va_end(ap);
    ss->notice_until = ss->clock + NOTICE_S;
}

/* L and E: the frames are made again for the new layout or eye order (the
 * eye size follows the layout). */
static void layout_pick(session *ss, frame_compose c, bool swap)
{
    frames_drop(ss);
    ss->compose = c;
    ss->swap_eyes = swap;
    memset(ss->unavailable, 0, sizeof ss->unavailable);
    choose_render_size(ss, false);
    notice(ss, "output %s%s   (L layout, E swap eyes)", frame_compose_names[c], swap ? ", eyes swapped" : "");
    vg_info("play: output %s%s, %ux%u per eye", frame_compose_names[c], swap ? " with the eyes swapped" : "",
            ss->rw, ss->rh);
}

/* Switches mode, or says on screen why not. */
static void mode_pick(session *ss, frame_mode mode)
{
    if (ss->study || mode == ss->mode)
        return;
    frame *f;
    vg_status st = ss->unavailable[mode] ? VG_ERR_UNSUPPORTED : frame_for(ss, mode, &f);
    if (st != VG_OK) {
        ss->unavailable[mode] = true;
        notice(ss, "%s is not available in this build", k_mode_text[mode]);
        vg_info("play: mode %s not available: staying with %s", k_mode_text[mode], k_mode_text[ss->mode]);
        return;
    }
    ss->trace_mixed |= ss->ph == PHASE_FLIGHT; /* the trace would join two modes */
    if (ss->ph == PHASE_READY)
        ss->trace_mode = mode;
    ss->mode = mode;
    vg_info("play: mode %s", k_mode_text[mode]);
}

/* ------------------------------------------------------------------------- */
/* Input and HUD                                                             */
/* ------------------------------------------------------------------------- */

static vg_status handle(session *ss, const window_event *ev)
{
    if (ev->kind == WINDOW_EVENT_CLICK)
        return on_click(ss, ev->x, ev->y);
    switch (ev->key) {
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: ss->quit = true; break;
    case GLFW_KEY_P:
    case GLFW_KEY_SPACE:
        if (ss->study && ss->ph == PHASE_FLIGHT && !ss->paused)
            break; /* a frozen ball would be seen longer than the visible interval */
        ss->paused = !ss->paused;
        vg_info("play: %s", ss->paused ? "paused" : "resumed");
        break;
    case GLFW_KEY_H:
        ss->hud_tech = !ss->hud_tech;
        for (int m = 0; m <= FRAME_MODE_OPTIMIZED; m++)
            if (ss->frames[m])
                frame_time_passes(ss->frames[m], ss->hud_tech);
        vg_info("play: technical HUD %s", ss->hud_tech ? "on" : "off");
        break;
    case GLFW_KEY_R:
        if (!ss->study)
            restart(ss);
        break;
    case GLFW_KEY_M:
        for (int k = 1; k <= 3; k++) { /* the next mode that renders */
            frame_mode m = (frame_mode)(FRAME_MODE_ORIGINAL + (ss->mode - FRAME_MODE_ORIGINAL + k) % 3);
            if (!ss->unavailable[m] || k == 3) {
                mode_pick(ss, m);
                break;
            }
        }
        break;
    case GLFW_KEY_L: /* the next layout; "default" is sbs again */
        layout_pick(ss, (frame_compose)(ss->compose % (FRAME_COMPOSE_COUNT - 1) + 1), ss->swap_eyes);
        break;
    case GLFW_KEY_E: layout_pick(ss, ss->compose, !ss->swap_eyes); break;
    case GLFW_KEY_1:
    case GLFW_KEY_2:
    case GLFW_KEY_3: mode_pick(ss, (frame_mode)(FRAME_MODE_ORIGINAL + ev->key - GLFW_KEY_1)); break;
    default: break;
    }
    return VG_OK;
}

static void hud_add(session *ss, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void hud_add(session *ss, const char *fmt, ...)
{
    if (ss->hud.line_count >= FRAME_HUD_MAX_LINES)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(ss->hud.lines[ss->hud.line_count++], FRAME_HUD_LINE, fmt, ap);
    va_end(ap);
}

/* What f's probe measured of the ball since the last call, into its trace. */
static void trace_take(session *ss, frame *f)
{
    frame_probe probes[FRAME_PROBES_KEPT];
    int n = frame_take_probes(f, probes, FRAME_PROBES_KEPT);
    for (int i = 0; i < n; i++)
        ball_trace_add(&ss->trace, f, &ss->cam, &ss->th, ss->t_launch, &probes[i]);
}

/* The ball's trace after a throw (free play): the chart under the badge,
 * and once a throw its figures in the log. */
static void trace_chart(session *ss, const frame *f)
{
    ball_trace_figures fig;
    const frame_desc *fd = frame_get_desc(f);
    ball_trace_figures_of(&ss->trace, fd->keyframe_stride / fd->fps, &fig);
    frame_hud_chart *c = &ss->hud.chart;
    static const char *const label[] = {"", "(g)", "(h)", "(f)"};
    ball_trace_chart(&fig, ss->th.visible_s, label[ss->trace_mode], k_mode_rgb[ss->trace_mode], c);
    if (ss->trace_mixed)
        snprintf(c->caption, sizeof c->caption, "the mode changed during the flight");
    if (ss->trace_said)
        return;
    ss->trace_said = true;
    char pg[FRAME_HUD_LINE * 2] = "", ps[FRAME_HUD_LINE * 2] = "";
    for (int i = 0; i < fig.speeds && i < 16; i++) {
        snprintf(pg + strlen(pg), sizeof pg - strlen(pg), "%s%.2f", i ? " " : "", fig.p_g[i]);
        snprintf(ps + strlen(ps), sizeof ps - strlen(ps), "%s%.2f", i ? " " : "", fig.p_shown[i]);
    }
    vg_info("play: throw %d as shown in %s%s: %d frames of the flight, %d a keyframe apart; MID %.3f JND "
            "against g, largest |shown - g| %.4f arcmin; speed in depth (JND) g [%s] shown [%s]",
            ss->throw_no, k_mode_text[ss->trace_mode], ss->trace_mixed ? " (mixed: the mode changed)" : "",
            ss->trace.count, fig.samples, fig.mid_jnd, fig.max_shown_minus_g, pg, ps);
}

static void hud_build(session *ss, frame *f)
{
    frame_hud *h = &ss->hud;
    memset(h, 0, sizeof *h);
    h->visible = true; /* at screen depth, at the scale of the eye image (overlay_gpu.c) */
    if (!ss->study) {
        snprintf(h->badge, sizeof h->badge, "%s", k_mode_badge[ss->mode]);
        memcpy(h->badge_rgb, k_mode_rgb[ss->mode], 3);
    }
    if (ss->ph == PHASE_FEEDBACK) {
        /* Where the player clicked, and the true landing spot (the ball lies there). */
        double lu, lv;
        h->markers[h->marker_count++] = (frame_hud_marker){(float)ss->click_u, (float)ss->click_v, FRAME_HUD_CROSS,
                                                            {255, 255, 255}, "you"};
        if (game_project(&ss->cam, ss->th.ground, &lu, &lv) > 0)
            h->markers[h->marker_count++] = (frame_hud_marker){(float)lu, (float)lv, FRAME_HUD_BOX, {255, 96, 64},
                                                                "landed"};
    }
    if (ss->ph == PHASE_FEEDBACK && !ss->study)
        trace_chart(ss, f);
    if (ss->study)
        hud_add(ss, "VERGENCE STUDY  |  trial %d of %d", ss->trial + 1, ss->d->trial_count);
    else if (ss->throws_scored)
        hud_add(ss, "VERGENCE  |  throw %d  |  score %d  |  mean miss %.2f m", ss->throw_no, ss->score,
                ss->miss_sum / ss->throws_scored);
    else
        hud_add(ss, "VERGENCE  |  throw %d  |  score 0", ss->throw_no);
    static const char *const prompt[] = {"", "Get ready ...   (H: HUD and keys)", "Watch the ball!",
                                         "Click where the ball will land", "", "All trials done: thank you! (Q quits)"};
    if (ss->ph == PHASE_FEEDBACK) {
        hud_add(ss, "Missed by %.2f m: +%d points. Click: next throw.", ss->last_miss, game_points(ss->last_miss));
        if (isfinite(ss->picked_m))
            hud_add(ss, "It landed %.1f m away; you picked %.1f m.", ss->landed_m, ss->picked_m);
        else
            hud_add(ss, "It landed %.1f m away; you picked the sky.", ss->landed_m);
    } else
        hud_add(ss, "%s", prompt[ss->ph]);
    if (ss->hud_tech) {
        hud_add(ss, "mode: %s%s", k_mode_text[ss->mode], ss->study ? "   (set by the study)" : "   M cycles, 1-3 pick");
        hud_add(ss, "operator: %s   look-ahead: %s   output: %s %ux%u", disp_operator_kind_name(ss->d->op),
                frame_look_ahead_names[ss->d->look_ahead], frame_compose_names[ss->compose], ss->rw, ss->rh);
        const char *names[RG_MAX_PASSES];
        double ms[RG_MAX_PASSES], total = 0;
        frame_time_passes(f, true); /* from the next frame on; off with the HUD (it costs the overlap) */
        uint32_t n = frame_pass_timings(f, names, ms, RG_MAX_PASSES);
        for (uint32_t i = 0; i < n; i++)
            total += ms[i];
        hud_add(ss, "fps %.1f   passes %.1f ms", ss->fps, total);
        char line[FRAME_HUD_LINE] = "";
        int small = 0;
        for (uint32_t i = 0; i < n; i++) {
            char item[48];
            if (!(ms[i] >= 0.05)) { /* amortised or idle this frame: counted, not listed */
                small++;
                continue;
            }
            snprintf(item, sizeof item, "%s %.1f", names[i], ms[i]);
            if (strlen(line) + strlen(item) + 3 > 64) {
                hud_add(ss, "  %s", line);
                line[0] = '\0';
            }
            if (line[0])
                strcat(line, "   ");
            strcat(line, item);
        }
        if (line[0])
            hud_add(ss, "  %s", line);
        if (small)
            hud_add(ss, "  (%d more passes under 0.05 ms)", small);
        hud_add(ss, "H hud   P pause   %sL layout   E swap eyes   Q quit", ss->study ? "" : "R restart   ");
    }
    if (ss->paused)
        snprintf(h->banner, sizeof h->banner, "PAUSED  -  P to continue");
    else if (ss->clock < ss->notice_until)
        snprintf(h->banner, sizeof h->banner, "%s", ss->notice);
    else if (ss->ph == PHASE_READY)
        snprintf(h->banner, sizeof h->banner, ss->study ? "Trial %d: watch the ball" : "Throw %d: watch the ball",
                 ss->study ? ss->trial + 1 : ss->throw_no);
    else if (ss->ph == PHASE_DONE)
        snprintf(h->banner, sizeof h->banner, "Thank you! All %d trials are done.", ss->d->trial_count);
}

/* ------------------------------------------------------------------------- */
/* Loop                                                                      */
/* ------------------------------------------------------------------------- */

/* --dump-f: f of the frame just shown (waits for it). */
static vg_status dump_f(session *ss, frame *f, long index)
{
    vg_status st = frame_wait_idle(f);
    const frame_outputs *o = frame_get_outputs(f);
    const frame_desc *d = frame_get_desc(f);
    char name[64], path[1100];
    snprintf(name, sizeof name, "f_%06ld.pfm", index);
    if (st == VG_OK)
        st = vg_path_join(path, sizeof path, ss->d->win->dump_f, name);
    if (st == VG_OK)
        st = vg_pfm_write(path, &(vg_imagef){(int)d->width, (int)d->height, 1, (float *)o->f});
    return st;
}

/* ------------------------------------------------------------------------- */
/* A study's flight: rendered ahead, shown frame-exactly (flight.h)          */
/* ------------------------------------------------------------------------- */

static vg_status flight_progress(void *user, int done, int count)
{
    session *ss = user;
    trace_take(ss, ss->flight_frames[ss->mode]);
    window_pump(ss->win); /* the window stays responsive; input waits for the next tick */
    vg_progress("study hit: rendering the flight ahead", done, count);
    return VG_OK;
}

/* Before the first trial: a window that cannot present a stored frame per
 * 1/60 s cannot show a flight frame-exactly. */
static vg_status flight_check_rate(session *ss)
{
    enum { FRAMES = 30, MISSED_MAX = 3 };
    flight_record r;
    vg_status st = flight_rate_check(ss->fl, FRAMES, &r);
    if (st != VG_OK)
        return st;
    vg_info("study hit: the window presented %d test frames at %.0f Hz: %d late, worst %.1f ms between frames",
            r.shown, FLIGHT_HZ, r.missed, r.worst_ms);
    if (r.missed <= MISSED_MAX)
        return VG_OK;
    if (ss->d->allow_missed) {
        vg_warn("study hit: this window cannot hold %.0f Hz (%d of %d test frames late): flights will miss "
                "frames (--allow-missed-frames; every row records them)", FLIGHT_HZ, r.missed, r.shown);
        return VG_OK;
    }
    vg_error("study hit: this window cannot hold %.0f Hz (%d of %d test frames late, worst %.1f ms between "
             "frames): a throw's flight would not be shown frame-exactly (--allow-missed-frames runs anyway, "
             "for demonstrations)", FLIGHT_HZ, r.missed, r.shown, r.worst_ms);
    return VG_ERR_DEVICE;
}

static vg_status flight_prepare(session *ss)
{
    gpu *g = window_gpu(ss->win);
    frame **fr = &ss->flight_frames[ss->mode];
    vg_status st = VG_OK;
    if (!*fr) {
        frame_desc fd = session_frame_desc(ss, ss->mode);
        fd.readback = true; /* the composed image comes back to be kept */
        fd.overlay = true;  /* with the HUD the live frame would show */
        memcpy(fd.probe_ids, ss->ball_ids, sizeof fd.probe_ids); /* the ball as shown, for the log */
        st = frame_create(g, ss->scene, &fd, fr);
    }
    for (int m = 0; m <= FRAME_MODE_OPTIMIZED && st == VG_OK; m++)
        if (ss->frames[m])
            st = frame_wait_idle(ss->frames[m]);
    if (st != VG_OK)
        return st;
    frame_restart(*fr);
    phase keep = ss->ph;
    ss->ph = PHASE_FLIGHT; /* the HUD of the flight ("Watch the ball!") */
    hud_build(ss, *fr);
    ss->ph = keep;
    if ((st = frame_set_hud(*fr, &ss->hud)) != VG_OK)
        return st;
    long first = lround(ss->t_launch * FLIGHT_HZ);
    int count = (int)lround(ss->th.visible_s * FLIGHT_HZ);
    ss->trace.count = 0;
    /* The window holds the keyframe before the launch (the ball resting at
     * its start), as the live game's window does: the launch is motion. */
    st = frame_render(*fr, first - frame_get_desc(*fr)->keyframe_stride);
    if (st == VG_OK)
        st = flight_render(ss->fl, *fr, first, count, flight_progress, ss);
    ss->flight_ready = st == VG_OK;
    return st;
}

static vg_status flight_play(session *ss)
{
    vg_status st = VG_OK;
    for (int m = 0; m <= FRAME_MODE_OPTIMIZED && st == VG_OK; m++)
        if (ss->frames[m])
            st = frame_wait_idle(ss->frames[m]);
    if (st == VG_OK && !ss->flight_ready)
        st = flight_prepare(ss); /* resized while the ball waited */
    bool quit = false;
    if (st == VG_OK)
        st = flight_show(ss->fl, &ss->shown, &quit);
    if (st != VG_OK)
        return st;
    vg_info("study hit: trial %d: flight of %d frames shown in %.3f s, %d missed, worst %.1f ms between frames",
            ss->trial, ss->shown.frames, ss->shown.shown_s, ss->shown.missed, ss->shown.worst_ms);
    ss->quit = quit;
    ss->clock = ss->t_hide;
    ss->ph = PHASE_AIM;
    return VG_OK;
}

static vg_status present(session *ss)
{
    frame *f;
    vg_status st = frame_for(ss, ss->mode, &f);
    if (st != VG_OK)
        return st;
    hud_build(ss, f);
    frame_target target;
    bool stale;
    if ((st = window_acquire(ss->win, &target, &stale)) != VG_OK)
        return st;
    if (!stale) {
        long index = lround(ss->clock * 60.0);
        st = frame_present(f, index, &target, &ss->hud);
        if (st == VG_OK)
            st = window_present(ss->win, &stale);
        if (st == VG_OK)
            trace_take(ss, f);
        if (st == VG_OK && ss->d->win->dump_f && ss->mode == FRAME_MODE_OPTIMIZED)
            st = dump_f(ss, f, index);
    }
    if (st == VG_OK && stale) {
        /* The frames present at the old size: make them again. */
        frames_drop(ss);
        st = window_rebuild(ss->win);
        if (st == VG_OK)
            choose_render_size(ss, false);
    }
    return st;
}

static vg_status run_loop(session *ss)
{
    vg_status st = VG_OK;
    double last_ms = 0;
    while (st == VG_OK && !ss->quit) {
        window_event ev[32];
        int n;
        long tick = window_tick(ss->win, ev, 32, &n);
        if (window_closed(ss->win) || (ss->d->win->ticks && tick >= ss->d->win->ticks))
            break;
        for (int i = 0; i < n && st == VG_OK; i++)
            st = handle(ss, &ev[i]);
        double dt = window_tick_seconds(ss->win), now = vg_now_ms();
        /* Frames shown per second of wall time (a replay's game time is fixed-step). */
        double wall = last_ms > 0 ? fmax(now - last_ms, 1e-3) * 1e-3 : 0;
        if (wall > 0)
            ss->fps = ss->fps > 0 ? 0.9 * ss->fps + 0.1 / wall : 1.0 / wall;
        last_ms = now;
        if (!ss->paused && ss->ph != PHASE_DONE) {
            ss->clock += dt;
            st = update_phase(ss);
        }
        if (st == VG_OK && !ss->quit)
            st = present(ss);
        /* A study renders the throw's flight while the ball waits at its
         * launch point (game time stands still meanwhile). */
        if (st == VG_OK && ss->study && ss->ph == PHASE_READY && !ss->flight_ready)
            st = flight_prepare(ss);
        if (ss->d->win->replay && !window_replaying(ss->win) && !ss->replay_done_said) {
            vg_info("play: replay finished at tick %ld", tick);
            ss->replay_done_said = true;
        }
    }
    return st;
}

static bool writes_dump_f(const char *name)
{
    return strncmp(name, "f_", 2) == 0 && strlen(name) > 6 && strcmp(name + strlen(name) - 4, ".pfm") == 0;
}

vg_status play_check_outputs(const play_window_cli *w, const char *const *scene_paths, int scene_count,
                             const char *out_label, const char *out_path)
{
    vg_inputs in = {0};
    vg_status st = VG_OK;
    for (int i = 0; i < scene_count && st == VG_OK; i++) {
        scene *s;
        if ((st = scene_load(scene_paths[i], &s)) != VG_OK)
            break;
        for (int k = 0; k < s->file_count && st == VG_OK; k++)
            st = vg_inputs_add(&in, "--scene", s->files[k]);
        scene_destroy(s);
    }
    if (st == VG_OK && w->replay)
        st = vg_inputs_add(&in, "--replay", w->replay);
    if (st == VG_OK && w->display_file)
        st = vg_inputs_add(&in, "--display", w->display_file);
    if (st == VG_OK && w->record)
        st = vg_inputs_check(&in, "--record", w->record);
    if (st == VG_OK && out_path)
        st = vg_inputs_check(&in, out_label, out_path);
    if (st == VG_OK && w->dump_f)
        st = vg_inputs_check_dir(&in, "--dump-f", w->dump_f, NULL, writes_dump_f);
    /* The recording and the study log are two files. */
    if (st == VG_OK && out_path && w->record) {
        vg_inputs out = {0};
        st = vg_inputs_add(&out, out_label, out_path);
        if (st == VG_OK)
            st = vg_inputs_check(&out, "--record", w->record);
        vg_inputs_free(&out);
    }
    vg_inputs_free(&in);
    return st;
}

vg_status play_session_run(const play_session_desc *d)
{
    session *ss = calloc(1, sizeof *ss);
    if (!ss)
        return VG_ERR_NOMEM;
    ss->d = d;
    ss->study = d->cells != NULL;
    ss->trial = d->first_trial;
    ss->mode = d->mode ? d->mode : FRAME_MODE_ORIGINAL;
    ss->compose = (frame_compose)d->win->compose;
    ss->swap_eyes = d->win->swap_eyes;
    /* A study has checked its outputs before it opened its log. */
    vg_status st = ss->study ? VG_OK : play_check_outputs(d->win, &d->scene_path, 1, NULL, NULL);
    if (st == VG_OK)
        st = scene_load(d->scene_path, &ss->scene);
    if (st == VG_OK && d->win->frame_ticks > 1 && !d->win->replay) {
        vg_error("--frame-ticks %d needs --replay (live play advances by the wall clock)", d->win->frame_ticks);
        st = VG_ERR_ARG;
    }
    if (st == VG_OK && d->win->dump_f)
        st = vg_dir_prepare(d->win->dump_f);
    if (st == VG_OK && (ss->ball = scene_find_node(ss->scene, "ball")) < 0) {
        vg_error("%s has no node named 'ball' to throw (see docs/content.md)", d->scene_path);
        st = VG_ERR_FORMAT;
    }
    if (st == VG_OK) {
        scene_node_instance_ids(ss->scene, ss->ball, ss->ball_ids, FRAME_PROBE_MAX_IDS - 1);
        memcpy(ss->ball_scale, ss->scene->nodes[ss->ball].scale, sizeof ss->ball_scale);
        scene_set_pose_hook(ss->scene, ball_pose, ss);
        st = window_create(&(window_desc){.title = ss->study ? "vergence study" : "vergence",
                                          .width = d->win->size[0], .height = d->win->size[1],
                                          .fullscreen = d->win->fullscreen, .gpu = &d->win->gpu,
                                          .replay = d->win->replay, .record = d->win->record,
                                          .frame_ticks = d->win->frame_ticks}, &ss->win);
    }
    gpu *g = ss->win ? window_gpu(ss->win) : NULL;
    if (st == VG_OK) {
        choose_render_size(ss, true);
        /* The first mode must render (a study needs all three). */
        for (int m = FRAME_MODE_ORIGINAL; m <= FRAME_MODE_OPTIMIZED && st == VG_OK; m++) {
            frame *f;
            if (ss->study || m == (int)ss->mode)
                st = frame_for(ss, (frame_mode)m, &f);
        }
    }
    if (st == VG_OK && ss->study && (st = flight_create(ss->win, &ss->fl)) == VG_OK)
        st = flight_check_rate(ss);
    if (st == VG_OK) {
        if (ss->study && ss->trial >= d->trial_count)
            ss->ph = PHASE_DONE;
        else
            throw_next(ss);
        st = run_loop(ss);
    }
    if (!ss->study && ss->throws_scored)
        vg_info("play: %d throw(s), score %d, mean miss %.2f m", ss->throws_scored, ss->score,
                ss->miss_sum / ss->throws_scored);
    frames_drop(ss);
    flight_destroy(ss->fl);
    if (ss->win)
        window_destroy(ss->win);
    if (g) {
        int code = gpu_cli_close(g, st);
        if (code && st == VG_OK)
            st = VG_ERR_VALIDATION;
    }
    scene_destroy(ss->scene);
    free(ss);
    return st;
}
