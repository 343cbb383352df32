/* vergence — the preference study (paper Sec. 5): which of two compressed
 * versions of a scene, h (the operator alone) or f (optimized), moves more
 * like the unmodified reference g shown between them? Two-alternative
 * forced choice; sides randomised; saliency on the moving or on the static
 * objects, as in the paper ("to simulate the artist's intention"). */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "observer/observer.h"
#include "observer/observer_engine.h"
#include "pref_trial.h"
#include "pref_window.h"
#include "study.h"
#include "study_log.h"

static const char *const k_columns[] = {
    "participant", "study", "trial", "seed", "scene", "saliency", "optimized_side", "operator", "observer",
    "choice", "chose_optimized", "response_s", "utc", STUDY_DISPLAY_COLUMNS,
};
enum { COL_STUDY = 1, COL_TRIAL, COL_SEED, COL_SCENE, COL_SALIENCY, COL_SIDE, COL_DISPLAY = 13,
       COL_COUNT = COL_DISPLAY + STUDY_DISPLAY_COUNT };
_Static_assert(sizeof k_columns / sizeof k_columns[0] == COL_COUNT, "one name per column");

static const char *const k_sides[2] = {"left", "right"};

/* ------------------------------------------------------------------------- */
/* The model                                                                 */
/* ------------------------------------------------------------------------- */

typedef struct model_scene {
    scene *scene;
    observer *obs;
    double (*track)[3];
    int frames;
    /* The engine's view: h and f of the clip as shown (every 2nd frame,
     * each held for two refreshes), computed once per scene and saliency. */
    double *offset[2];
    observer_shown shown[2];
} model_scene;

static vg_status model_scene_load(const study_opts *o, gpu *g, const char *arena, int index, int variant,
                                  model_scene *m)
{
    char path[1100];
    vg_status st = pref_scene_path(arena, index, path, sizeof path);
    if (st == VG_OK)
        st = scene_load(path, &m->scene);
    if (st != VG_OK)
        return st;
    int moving = pref_moving_node(m->scene);
    if (moving < 0) {
        vg_error("%s: no animated object to compare", path);
        return VG_ERR_FORMAT;
    }
    pref_saliency_apply(m->scene, moving, variant);
    m->frames = (int)lround(m->scene->duration * 60.0) + 1;
    m->track = malloc((size_t)m->frames * sizeof *m->track);
    scene_state ss;
    if (!m->track || scene_state_init(m->scene, &ss) != VG_OK)
        return VG_ERR_NOMEM;
    for (int i = 0; i < m->frames; i++) {
        scene_evaluate(m->scene, (float)(i / 60.0), &ss);
        for (int k = 0; k < 3; k++)
            m->track[i][k] = ss.world[(size_t)moving * 16 + 12 + (size_t)k];
    }
    scene_state_free(&ss);
    st = observer_create(&(observer_desc){
        .view = {.scene = m->scene, .moving_node = moving, .display = display_cli_desc(&o->display),
                 .op = (disp_operator_kind)o->op, .preset = DISP_PRESET_STUDY},
        .weber_k = o->weber_k}, &m->obs);
    if (st != VG_OK || !g)
        return st;
    /* The panels a person's study shows at these settings (pref_window). */
    double ew, eh;
    int pw, ph;
    frame_compose_eye_size((frame_compose)o->win.compose, (uint32_t)o->win.size[0], (uint32_t)o->win.size[1], &ew, &eh);
    pref_panel_size(g->is_cpu, (int)ew, (int)eh, &pw, &ph);
    frame_desc fd = pref_clip_frame_desc(g, &(pref_clip_desc){
        .width = (uint32_t)pw, .height = (uint32_t)ph, .mode = FRAME_MODE_OPTIMIZED,
        .compose = (frame_compose)o->win.compose, .op = (disp_operator_kind)o->op,
        .display = display_cli_desc(&o->display), .tess_error = o->win.tess_error});
    observer_engine *e;
    st = observer_engine_create(&(observer_engine_desc){.gpu = g, .scene = m->scene, .moving_node = moving,
                                                        .frame = fd}, &e);
    int clip = pref_clip_frames(m->scene);
    vg_info("study preference: the model sees the engine's clips of %s (%s saliency), %dx%d panels",
            pref_scene_names[index], pref_saliency_names[variant], pw, ph);
    for (int v = 0; v < 2 && st == VG_OK; v++) {
        observer_shown sh;
        st = observer_engine_track(e, v ? FRAME_MODE_OPTIMIZED : FRAME_MODE_MANIPULATED, 0, PREF_CLIP_STEP, clip, &sh);
        if (st == VG_OK && !(m->offset[v] = malloc((size_t)m->frames * sizeof(double))))
            st = VG_ERR_NOMEM;
        for (int i = 0; st == VG_OK && i < m->frames; i++) {
            int k = i / PREF_CLIP_STEP; /* the clip frame on screen at refresh i */
            m->offset[v][i] = sh.offset[k < clip ? k : clip - 1];
        }
        m->shown[v] = (observer_shown){.offset = m->offset[v], .count = m->frames};
    }
    observer_engine_destroy(e);
    return st;
}

static void model_scene_free(model_scene *m)
{
    observer_destroy(m->obs);
    scene_destroy(m->scene);
    free(m->track);
    free(m->offset[0]), free(m->offset[1]);
    *m = (model_scene){0};
}

/* ------------------------------------------------------------------------- */
/* Study                                                                     */
/* ------------------------------------------------------------------------- */

typedef struct pref_run {
    const study_opts *o;
    study_session ss;
} pref_run;

static vg_status log_choice(void *user, int trial, int choice_right, double response_s)
{
    pref_run *r = user;
    pref_cell c = pref_cell_of(r->ss.cells[trial]);
    char buf[COL_COUNT][64];
    const char *f[COL_COUNT];
    snprintf(buf[0], 64, "%s", r->o->participant);
    snprintf(buf[1], 64, "preference");
    snprintf(buf[2], 64, "%d", trial);
    snprintf(buf[3], 64, "%" PRIu64, r->ss.seed);
    snprintf(buf[4], 64, "%s", pref_scene_names[c.scene]);
    snprintf(buf[5], 64, "%s", pref_saliency_names[c.saliency]);
    snprintf(buf[6], 64, "%s", k_sides[c.optimized_right]);
    snprintf(buf[7], 64, "%s", disp_operator_kind_name((disp_operator_kind)r->o->op));
    snprintf(buf[8], 64, "%s", study_observer_name(r->o));
    snprintf(buf[9], 64, "%s", k_sides[choice_right]);
    snprintf(buf[10], 64, "%d", choice_right == c.optimized_right);
    snprintf(buf[11], 64, "%.3f", response_s);
    study_utc_now(buf[12], 64);
    char display[STUDY_DISPLAY_COUNT][32];
    study_display_fields(r->o, display);
    for (int k = 0; k < STUDY_DISPLAY_COUNT; k++)
        memcpy(buf[COL_DISPLAY + k], display[k], sizeof display[k]);
    for (int i = 0; i < COL_COUNT; i++)
        f[i] = buf[i];
    vg_status st = study_log_append(&r->ss.log, f);
    if (st == VG_OK)
        vg_progress("study preference", trial + 1, r->ss.trials);
    return st;
}

static vg_status run_model(pref_run *r, const char *arena)
{
    model_scene ms[PREF_SCENES][2] = {{{0}}};
    vg_status st = VG_OK;
    gpu *g = NULL;
    if (r->o->observer_view == STUDY_VIEW_ENGINE)
        st = gpu_cli_open(&r->o->win.gpu, false, &g);
    for (int i = r->ss.log.rows; i < r->ss.trials && st == VG_OK; i++) {
        pref_cell c = pref_cell_of(r->ss.cells[i]);
        model_scene *m = &ms[c.scene][c.saliency];
        if (!m->obs && (st = model_scene_load(r->o, g, arena, c.scene, c.saliency, m)) != VG_OK)
            break;
        game_rng noise = game_rng_make(r->ss.seed, 2 * (uint64_t)i + 2);
        /* Side 0 left, 1 right, 2 the reference between them. */
        int fs = c.optimized_right;
        const frame_mode modes[3] = {fs ? FRAME_MODE_MANIPULATED : FRAME_MODE_OPTIMIZED,
                                     fs ? FRAME_MODE_OPTIMIZED : FRAME_MODE_MANIPULATED, FRAME_MODE_ORIGINAL};
        const observer_shown *shown[3] = {NULL, NULL, NULL};
        if (g)
            shown[fs] = &m->shown[1], shown[1 - fs] = &m->shown[0];
        observer_choice ch;
        st = observer_prefer(m->obs, (const double (*)[3])m->track, m->frames, modes, g ? shown : NULL, &noise, &ch);
        /* Why it chose (issue 18): the figures it compared, and the paper's
         * own measure of the same two tracks against the reference. */
        if (st == VG_OK)
            vg_info("study preference: trial %d (%s, %s saliency): chose %s (%s); perceived-change distance to g "
                    "f %.2f h %.2f JND^2; paper's MID distortion f %.3f h %.3f JND: f %s by the paper's measure",
                    i, pref_scene_names[c.scene], pref_saliency_names[c.saliency], k_sides[ch.side],
                    ch.side == fs ? "f" : "h", ch.compared[fs], ch.compared[1 - fs], ch.mid_jnd[fs],
                    ch.mid_jnd[1 - fs], ch.mid_jnd[fs] < ch.mid_jnd[1 - fs] ? "closer" : "not closer");
        if (st == VG_OK)
            st = log_choice(r, i, ch.side, 0.0);
    }
    for (int s = 0; s < PREF_SCENES; s++)
        for (int v = 0; v < 2; v++)
            model_scene_free(&ms[s][v]);
    if (g)
        st = gpu_cli_release(g, st);
    return st;
}

static vg_status check_rows(pref_run *r)
{
    const study_log *l = &r->ss.log;
    for (int i = 0; i < l->rows_read; i++) {
        pref_cell c = pref_cell_of(r->ss.cells[i]);
        char want[32];
        snprintf(want, sizeof want, "%d", i);
        if (strcmp(study_log_cell(l, i, COL_STUDY), "preference") || strcmp(study_log_cell(l, i, COL_TRIAL), want) ||
            strcmp(study_log_cell(l, i, COL_SCENE), pref_scene_names[c.scene]) ||
            strcmp(study_log_cell(l, i, COL_SALIENCY), pref_saliency_names[c.saliency]) ||
            strcmp(study_log_cell(l, i, COL_SIDE), k_sides[c.optimized_right])) {
            vg_error("%s: line %d is not trial %d of seed %" PRIu64 "'s schedule: the file is corrupt (left as it "
                     "is)", l->path, i + 2, i, r->ss.seed);
            return VG_ERR_FORMAT;
        }
    }
    return VG_OK;
}

vg_status study_preference_run(const study_opts *o)
{
    char buf[1024];
    const char *arena = game_scene_path(o->scene, buf, sizeof buf);
    if (!arena)
        return VG_ERR_IO;
    pref_run r = {.o = o};
    char display[STUDY_DISPLAY_COUNT][32];
    study_display_fields(o, display);
    const study_setting settings[] = {
        {7, "--operator", disp_operator_kind_name((disp_operator_kind)o->op)},
        {8, "--observer", study_observer_name(o)},
        {COL_DISPLAY, "--screen-width-m", display[0]},
        {COL_DISPLAY + 1, "--screen-resolution", display[1]},
        {COL_DISPLAY + 2, "--distance-m", display[2]},
        {COL_DISPLAY + 3, "--ipd-m", display[3]},
    };
    static const int numeric[] = {10, 11};
    const study_kind kind = {
        .name = "preference", .columns = k_columns, .column_count = COL_COUNT, .col_seed = COL_SEED,
        .settings = settings, .setting_count = 6, .numeric = numeric, .numeric_count = 2,
        .cells = PREF_CELLS, .default_trials = 24,
    };
    char paths[PREF_SCENES][1024];
    const char *scene_paths[PREF_SCENES];
    vg_status st = VG_OK;
    for (int i = 0; i < PREF_SCENES && st == VG_OK; i++) {
        st = pref_scene_path(arena, i, paths[i], sizeof paths[i]);
        scene_paths[i] = paths[i];
    }
    if (st == VG_OK)
        st = play_check_outputs(&o->win, scene_paths, PREF_SCENES, "--out", o->out);
    if (st == VG_OK)
        st = study_begin(o, &kind, &r.ss);
    if (st == VG_OK)
        st = check_rows(&r);
    if (st == VG_OK && r.ss.log.rows < r.ss.trials)
        st = o->observer ? run_model(&r, arena)
                         : pref_window_run(&(pref_window_desc){
                               .win = &o->win, .arena_path = arena, .op = (disp_operator_kind)o->op,
                               .display = display_cli_desc(&o->display), .cells = r.ss.cells,
                               .first_trial = r.ss.log.rows, .trial_count = r.ss.trials, .on_choice = log_choice,
                               .user = &r});
    return study_end(&r.ss, o, &kind, st);
}
