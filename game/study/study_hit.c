/* vergence — the hit-prediction study (paper Sec. 5, Fig. 7): schedule,
 * CSV rows, resume checks, and the two players (a person, the model). */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "observer/observer.h"
#include "observer/observer_engine.h"
#include "play/flight.h"
#include "study.h"
#include "study_log.h"

static const char *const k_columns[] = {
    "participant", "study", "trial", "seed", "condition", "direction", "path", "operator", "observer",
    "visible_s", "start_x", "start_y", "start_z", "velocity_x", "velocity_y", "velocity_z", "gravity",
    "flight_s", "ground_x", "ground_y", "ground_z", "click_u", "click_v", "error_m", "response_s", "utc",
    STUDY_DISPLAY_COLUMNS, "flight_frames", "frames_shown", "frames_missed", "shown_s", "ball_mid_jnd",
};
enum { COL_STUDY = 1, COL_TRIAL, COL_SEED, COL_CONDITION, COL_DIRECTION, COL_PATH, COL_DISPLAY = 26,
       COL_FLIGHT = COL_DISPLAY + STUDY_DISPLAY_COUNT, COL_BALL = COL_FLIGHT + 4, COL_COUNT = COL_BALL + 1 };
_Static_assert(sizeof k_columns / sizeof k_columns[0] == COL_COUNT, "one name per column");

typedef struct hit_run {
    const study_opts *o;
    study_session ss;
    const char *who;              /* "human" or "model" */
} hit_run;

/* ------------------------------------------------------------------------- */
/* Rows                                                                      */
/* ------------------------------------------------------------------------- */

static vg_status log_trial(hit_run *r, const play_trial *t)
{
    char buf[COL_COUNT][64];
    const char *f[COL_COUNT];
    const game_throw *th = t->th;
    snprintf(buf[0], 64, "%s", r->o->participant);
    snprintf(buf[1], 64, "hit");
    snprintf(buf[2], 64, "%d", t->trial);
    snprintf(buf[3], 64, "%" PRIu64, r->ss.seed);
    snprintf(buf[4], 64, "%s", frame_mode_names[t->mode]);
    snprintf(buf[5], 64, "%s", game_direction_names[th->direction]);
    snprintf(buf[6], 64, "%s", game_path_names[th->path]);
    snprintf(buf[7], 64, "%s", disp_operator_kind_name((disp_operator_kind)r->o->op));
    snprintf(buf[8], 64, "%s", r->who);
    snprintf(buf[9], 64, "%.3f", th->visible_s);
    for (int k = 0; k < 3; k++) {
        snprintf(buf[10 + k], 64, "%.4f", th->start[k]);
        snprintf(buf[13 + k], 64, "%.4f", th->velocity[k]);
        snprintf(buf[18 + k], 64, "%.4f", th->ground[k]);
    }
    snprintf(buf[16], 64, "%.2f", th->gravity);
    snprintf(buf[17], 64, "%.4f", th->flight_s);
    snprintf(buf[21], 64, "%.5f", t->click_u);
    snprintf(buf[22], 64, "%.5f", t->click_v);
    snprintf(buf[23], 64, "%.4f", t->error_m);
    snprintf(buf[24], 64, "%.3f", t->response_s);
    study_utc_now(buf[25], 64);
    char display[STUDY_DISPLAY_COUNT][32];
    study_display_fields(r->o, display);
    for (int k = 0; k < STUDY_DISPLAY_COUNT; k++)
        memcpy(buf[COL_DISPLAY + k], display[k], sizeof display[k]);
    /* The presentation record: the flight's frames, how many were presented
     * and how many late (flight.h), and how long it was on screen. */
    snprintf(buf[COL_FLIGHT], 64, "%d", t->flight.frames);
    snprintf(buf[COL_FLIGHT + 1], 64, "%d", t->flight.shown);
    snprintf(buf[COL_FLIGHT + 2], 64, "%d", t->flight.missed);
    snprintf(buf[COL_FLIGHT + 3], 64, "%.4f", t->flight.shown_s);
    /* What the condition did to the ball as shown (docs/game.md). */
    buf[COL_BALL][0] = '\0'; /* empty: a flight too short to measure */
    if (isfinite(t->ball_mid_jnd))
        snprintf(buf[COL_BALL], 64, "%.3f", t->ball_mid_jnd);
    for (int i = 0; i < COL_COUNT; i++)
        f[i] = buf[i];
    return study_log_append(&r->ss.log, f);
}

static vg_status on_trial(void *user, const play_trial *t)
{
    hit_run *r = user;
    vg_status st = log_trial(r, t);
    if (st == VG_OK)
        vg_progress("study hit", t->trial + 1, r->ss.trials);
    return st;
}

/* Every row read back must be the trial the schedule puts there. */
static vg_status check_rows(hit_run *r)
{
    const study_log *l = &r->ss.log;
    for (int i = 0; i < l->rows_read; i++) {
        game_cell c = game_hit_cell(r->ss.cells[i]);
        char want[32];
        snprintf(want, sizeof want, "%d", i);
        const char *problem = NULL;
        if (strcmp(study_log_cell(l, i, COL_STUDY), "hit"))
            problem = "is not a hit-study trial";
        else if (strcmp(study_log_cell(l, i, COL_TRIAL), want))
            problem = "does not hold the next trial number";
        else if (strcmp(study_log_cell(l, i, COL_CONDITION), frame_mode_names[FRAME_MODE_ORIGINAL + c.condition]) ||
                 strcmp(study_log_cell(l, i, COL_DIRECTION), game_direction_names[c.direction]) ||
                 strcmp(study_log_cell(l, i, COL_PATH), game_path_names[c.path]))
            problem = "does not match the schedule of its seed";
        if (problem) {
            vg_error("%s: line %d %s: the file is corrupt (left as it is)", l->path, i + 2, problem);
            return VG_ERR_FORMAT;
        }
    }
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Players                                                                   */
/* ------------------------------------------------------------------------- */

/* Launched at frame 60 (a keyframe, as play launches), the window
 * restarted there as at every throw. */
#define MODEL_LAUNCH_FRAME 60

static vg_status run_model(hit_run *r, const char *scene_path)
{
    const study_opts *o = r->o;
    scene *s;
    vg_status st = scene_load(scene_path, &s);
    if (st != VG_OK)
        return st;
    game_ball ball = {.node = scene_find_node(s, "ball"), .t_launch = MODEL_LAUNCH_FRAME / FLIGHT_HZ};
    observer *obs = NULL;
    gpu *g = NULL;
    observer_engine *eng = NULL;
    if (ball.node < 0) {
        vg_error("%s has no node named 'ball' to throw (see docs/content.md)", scene_path);
        st = VG_ERR_FORMAT;
    }
    if (st == VG_OK)
        st = observer_create(&(observer_desc){
            .view = {.scene = s, .moving_node = ball.node, .display = display_cli_desc(&o->display),
                     .op = (disp_operator_kind)o->op, .preset = DISP_PRESET_STUDY},
            .weber_k = o->weber_k, .size_cue = o->observer_cues != 0}, &obs);
    /* The engine's view: the frame a person's study shows at these settings
     * (play_session's flight frames), its maps read back. */
    if (st == VG_OK && o->observer_view == STUDY_VIEW_ENGINE) {
        memcpy(ball.scale, s->nodes[ball.node].scale, sizeof ball.scale);
        scene_set_pose_hook(s, game_ball_pose, &ball);
        st = gpu_cli_open(&o->win.gpu, false, &g);
        uint32_t w = (uint32_t)o->win.render[0], h = (uint32_t)o->win.render[1];
        if (st == VG_OK && !(w > 0 && h > 0))
            game_render_size(g, (frame_compose)o->win.compose, (uint32_t)o->win.size[0], (uint32_t)o->win.size[1],
                             &w, &h);
        if (st == VG_OK) {
            frame_desc fd = game_frame_desc(g, o->win.tess_error, FRAME_MODE_OPTIMIZED, w, h,
                                            (frame_compose)o->win.compose, (disp_operator_kind)o->op, true,
                                            observer_camera(obs));
            fd.display = display_cli_desc(&o->display);
            st = observer_engine_create(&(observer_engine_desc){.gpu = g, .scene = s, .moving_node = ball.node,
                                                                .frame = fd, .lead_keyframes = 1}, &eng);
        }
        if (st == VG_OK)
            vg_info("study hit: the model sees the engine's frames, %ux%u per eye", w, h);
    }
    for (int i = r->ss.log.rows; i < r->ss.trials && st == VG_OK; i++) {
        game_cell c = game_hit_cell(r->ss.cells[i]);
        game_rng rt = game_rng_make(r->ss.seed, 2 * (uint64_t)i + 1), rn = game_rng_make(r->ss.seed, 2 * (uint64_t)i + 2);
        game_throw th;
        game_throw_make(&(game_throw_desc){.path = c.path, .direction = c.direction, .visible_s = o->visible_s},
                        observer_camera(obs), &rt, &th);
        frame_mode mode = (frame_mode)(FRAME_MODE_ORIGINAL + c.condition);
        observer_shown shown, *sp = NULL;
        if (eng) {
            ball.th = th;
            int n = (int)ceil(th.visible_s * FLIGHT_HZ - 1e-9);
            st = observer_engine_track(eng, mode, MODEL_LAUNCH_FRAME, 1, n < 2 ? 2 : n, &shown);
            sp = &shown;
        }
        observer_result res;
        if (st == VG_OK)
            st = observer_play(obs, &th, mode, sp, &rn, &res);
        if (st == VG_OK)
            st = on_trial(r, &(play_trial){.trial = i, .th = &th, .mode = mode, .click_u = res.click_u,
                                            .click_v = res.click_v, .error_m = res.error_m,
                                            /* the model sees every frame of the flight, by construction */
                                            .flight = {.frames = res.frames_seen, .shown = res.frames_seen,
                                                       .shown_s = res.frames_seen / FLIGHT_HZ},
                                            .ball_mid_jnd = res.ball_mid_jnd});
    }
    observer_engine_destroy(eng);
    observer_destroy(obs);
    if (g)
        st = gpu_cli_release(g, st);
    scene_destroy(s);
    return st;
}

vg_status study_hit_run(const study_opts *o)
{
    char buf[1024];
    const char *scene_path = game_scene_path(o->scene, buf, sizeof buf);
    if (!scene_path)
        return VG_ERR_IO;
    hit_run r = {.o = o, .who = study_observer_name(o)};
    char visible[32];
    snprintf(visible, sizeof visible, "%.3f", o->visible_s > 0 ? o->visible_s : GAME_VISIBLE_S);
    char display[STUDY_DISPLAY_COUNT][32];
    study_display_fields(o, display);
    const study_setting settings[] = {
        {7, "--operator", disp_operator_kind_name((disp_operator_kind)o->op)},
        {8, "--observer", r.who},
        {9, "--visible", visible},
        {COL_DISPLAY, "--screen-width-m", display[0]},
        {COL_DISPLAY + 1, "--screen-resolution", display[1]},
        {COL_DISPLAY + 2, "--distance-m", display[2]},
        {COL_DISPLAY + 3, "--ipd-m", display[3]},
    };
    static const int numeric[] = {10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24};
    const study_kind kind = {
        .name = "hit", .columns = k_columns, .column_count = COL_COUNT, .col_seed = COL_SEED,
        .settings = settings, .setting_count = 7, .numeric = numeric, .numeric_count = 15,
        .cells = GAME_HIT_CELLS, .default_trials = 48,
    };
    vg_status st = play_check_outputs(&o->win, &scene_path, 1, "--out", o->out);
    if (st == VG_OK)
        st = study_begin(o, &kind, &r.ss);
    if (st == VG_OK)
        st = check_rows(&r);
    if (st == VG_OK && r.ss.log.rows < r.ss.trials) {
        if (o->observer)
            st = run_model(&r, scene_path);
        else
            st = play_session_run(&(play_session_desc){
                .win = &o->win, .scene_path = scene_path, .op = (disp_operator_kind)o->op,
                .display = display_cli_desc(&o->display), .visible_s = o->visible_s, .seed = r.ss.seed,
                .cells = r.ss.cells, .allow_missed = o->allow_missed, .first_trial = r.ss.log.rows,
                .trial_count = r.ss.trials,
                .on_trial = on_trial, .user = &r});
    }
    return study_end(&r.ss, o, &kind, st);
}
