/* vergence demo — one scene in one mode: render the clip's sampled frames
 * (video, x-t rows, object tracks, keyframes for the MID metrics, stills),
 * then the stills again against the two-camera reference with the warp and
 * with the image-warping baseline (holes, PSNR), then capture.json. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/io.h"
#include "capture/capture_json.h"
#include "core/log.h"
#include "demo.h"
#include "demo_image.h"
#include "figure/figure.h"

typedef struct run_ctx {
    gpu *gpu;
    frame *frame;                /* the clip's */
    const scene *s;
    const demo_opts *o;
    demo_scene *sc;
    demo_run *r;
    char dir[4096];
    int *node_track;             /* node -> track index or -1 */
    bool own[DEMO_MAPS];         /* this run writes the scene's slices and tracks of map m */
    capture_log log;             /* the clip's timings and, in the analysis run, the MID metrics */
    figure_video *video;
    demo_progress_fn progress;
    void *user;
} run_ctx;

int demo_run_units(const demo_opts *o, const demo_scene *sc, bool analysis)
{
    int step = analysis ? o->analysis_step : o->step;
    return (int)(sc->last / step) + 1 + 2;
}

void demo_run_free(demo_run *r)
{
    warp_metrics_free(&r->warp);
    warp_metrics_free(&r->imagewarp);
}

/* ------------------------------------------------------------------------- */
/* Per frame                                                                 */
/* ------------------------------------------------------------------------- */

/* Mean vergence of every tracked object, and the slice row. */
static void record_maps(run_ctx *c, const frame_outputs *fo, int sample, uint32_t w, uint32_t h)
{
    const float *maps[DEMO_MAPS] = {fo->g, fo->h, fo->f};
    double sum[DEMO_MAX_TRACKS][DEMO_MAPS] = {{0}};
    int count[DEMO_MAX_TRACKS] = {0};
    size_t px = (size_t)w * h;
    const scene *s = c->s;
    for (size_t i = 0; i < px; i++) {
        uint32_t id = fo->ids[i];
        if (id == 0 || id > (uint32_t)s->instance_count)
            continue;
        int t = c->node_track[s->instances[id - 1].node];
        if (t < 0)
            continue;
        count[t]++;
        for (int m = 0; m < DEMO_MAPS; m++)
            if (maps[m])
                sum[t][m] += maps[m][i];
    }
    demo_scene *sc = c->sc;
    for (int m = 0; m < DEMO_MAPS; m++) {
        if (!c->own[m])
            continue;
        for (int t = 0; t < sc->track_count; t++)
            sc->tracks[t].v[m][sample] = count[t] >= 3 ? (float)(sum[t][m] / count[t]) : NAN;
        memcpy(sc->xt[m] + (size_t)sample * w, maps[m] + (size_t)sc->row * w, sizeof(float) * w);
    }
}

/* The analysis run keeps the maps its frames carry (optimized: g, h, f). */
static vg_status claim_maps(run_ctx *c, const frame_outputs *fo)
{
    const float *maps[DEMO_MAPS] = {fo->g, fo->h, fo->f};
    demo_scene *sc = c->sc;
    for (int m = 0; m < DEMO_MAPS; m++) {
        c->own[m] = maps[m] && c->r->analysis;
        if (!c->own[m])
            continue;
        sc->xt[m] = malloc(sizeof(float) * (size_t)sc->samples * (size_t)sc->width);
        if (!sc->xt[m])
            return VG_ERR_NOMEM;
        for (int t = 0; t < sc->track_count; t++) {
            float *v = sc->tracks[t].v[m] = malloc(sizeof(float) * (size_t)sc->samples);
            if (!v)
                return VG_ERR_NOMEM;
            for (int i = 0; i < sc->samples; i++)
                v[i] = NAN;
        }
    }
    return VG_OK;
}

static figure_video *video_open(run_ctx *c, uint32_t w, uint32_t h)
{
    char path[4096];
    if (!c->o->video || vg_path_join(path, sizeof path, c->dir, "video.mp4") != VG_OK)
        return NULL;
    return figure_video_open(c->o->ffmpeg, path, (int)w, (int)h, c->o->fps / c->o->step);
}

static void video_frame(run_ctx *c, const frame_outputs *fo)
{
    if (!c->video)
        return;
    size_t px = (size_t)fo->stereo_width * fo->stereo_height;
    uint8_t *rgb = malloc(px * 3);
    if (!rgb)
        return;
    for (size_t i = 0; i < px; i++)
        memcpy(rgb + 3 * i, fo->stereo + 4 * i, 3);
    figure_video_frame(&c->video, rgb);
    free(rgb);
}

static vg_status write_still(run_ctx *c, int k, const frame_outputs *fo, uint32_t w, uint32_t h)
{
    char name[64];
    vg_status st;
    snprintf(name, sizeof name, "still_%d_sbs.png", k);
    if ((st = demo_png_sbs(c->dir, name, fo->left, fo->right, w, h)))
        return st;
    snprintf(name, sizeof name, "still_%d_anaglyph.png", k);
    if ((st = demo_png_rgba(c->dir, name, fo->stereo, fo->stereo_width, fo->stereo_height)))
        return st;
    snprintf(name, sizeof name, "still_%d_cascade.png", k);
    return demo_png_cascade(c->dir, name, fo, w, h);
}

/* ------------------------------------------------------------------------- */
/* Passes over the clip                                                      */
/* ------------------------------------------------------------------------- */

static frame_desc base_desc(const run_ctx *c)
{
    return (frame_desc){
        .width = (uint32_t)c->o->width, .height = (uint32_t)c->o->height, .fps = c->o->fps,
        .keyframe_stride = c->o->keyframe_stride, .readback = true, .stereo = FRAME_STEREO_WARP,
        .mode = c->r->mode, .compose = FRAME_COMPOSE_ANAGLYPH, .op = c->o->op, .tess_error = c->o->tess_error,
        .display = c->o->display,
    };
}

/* The clip's figures for the report. */
static vg_status log_finish(run_ctx *c)
{
    vg_status st = capture_log_finish(&c->log);
    demo_run *r = c->r;
    const capture_log *log = &c->log;
    r->pass_count = log->pass_count;
    for (uint32_t p = 0; p < log->pass_count; p++) {
        snprintf(r->pass_names[p], DEMO_NAME, "%s", log->pass_names[p]);
        r->pass_ms[p] = capture_log_pass_median(log, p);
    }
    r->frame_ms = capture_log_frame_median(log);
    if (st != VG_OK || !log->science)
        return st;
    const science_metrics_result *res = &log->result;
    r->has_mid = res->keyframes >= 3;
    r->mid[0] = res->h;
    r->mid[1] = res->f;
    r->range_violation[0] = res->h_range_violation;
    r->range_violation[1] = res->f_range_violation;
    r->second_difference[0][0] = res->h_d2.boundary;
    r->second_difference[0][1] = res->h_d2.between;
    r->second_difference[1][0] = res->f_d2.boundary;
    r->second_difference[1][1] = res->f_d2.between;
    r->range_lo = res->range_lo;
    r->range_hi = res->range_hi;
    r->keyframes = res->keyframes;
    return VG_OK;
}

/* The clip: every step-th frame in this run's mode. */
static vg_status render_clip(run_ctx *c, frame *f)
{
    demo_run *r = c->r;
    uint32_t w = (uint32_t)c->o->width, h = (uint32_t)c->o->height;
    vg_status st = VG_OK;
    int still = 0;
    for (int i = 0; i < r->frames && st == VG_OK; i++) {
        long n = (long)i * r->step;
        if ((st = capture_log_render(&c->log, f, n)) != VG_OK)
            break;
        const frame_outputs *fo = frame_get_outputs(f);
        if (i == 0) {
            if ((st = claim_maps(c, fo)) != VG_OK)
                break;
            c->video = video_open(c, fo->stereo_width, fo->stereo_height);
        }
        if (r->analysis)
            record_maps(c, fo, i, w, h);
        /* What f changes of h, at the middle still (the report's map). */
        if (r->analysis && r->still_count > 0 && fo->f && fo->h && n == r->still_frames[r->still_count / 2] &&
            !c->sc->fh_diff) {
            float *d = c->sc->fh_diff = malloc(sizeof(float) * (size_t)w * h);
            if (!d) {
                st = VG_ERR_NOMEM;
                break;
            }
            for (size_t p = 0; p < (size_t)w * h; p++)
                d[p] = fabsf(fo->f[p] - fo->h[p]);
            c->sc->fh_frame = n;
        }
        /* Every run's video has the same frames (every o->step-th). */
        if (n % c->o->step == 0)
            video_frame(c, fo);
        if (still < r->still_count && r->still_frames[still] == n)
            st = write_still(c, still++, fo, w, h);
        c->progress(c->user, 1);
    }
    return st;
}

/* The middle still again, against the two-camera reference: the warp
 * (accuracy, holes) and the image-warping baseline (holes). A fresh frame
 * starts the MID window there (the clip's f had the frames before). */
static vg_status render_stills(run_ctx *c, frame_stereo how)
{
    frame_desc d = base_desc(c);
    d.stereo = how;
    d.reference = true;
    d.measure = true; /* the disparity error per pixel: the cascade again in every fragment */
    d.compose = FRAME_COMPOSE_SBS;
    frame *f = NULL;
    vg_status st = frame_create(c->gpu, c->s, &d, &f);
    uint32_t w = (uint32_t)c->o->width, h = (uint32_t)c->o->height;
    warp_metrics *m = how == FRAME_STEREO_WARP ? &c->r->warp : &c->r->imagewarp;
    int k = c->r->still_count / 2;
    if (st == VG_OK)
        st = frame_render(f, c->r->still_frames[k]);
    if (st == VG_OK) {
        const frame_outputs *fo = frame_get_outputs(f);
        st = warp_metrics_add(m, fo, w, h);
        char name[64];
        snprintf(name, sizeof name, "%s_%d_left.png", how == FRAME_STEREO_WARP ? "warp" : "imagewarp", k);
        if (st == VG_OK)
            st = demo_png_holes(c->dir, name, fo->left, w, h, NULL);
        c->progress(c->user, 1);
    }
    if (st == VG_OK)
        warp_metrics_finish(m);
    frame_destroy(f);
    return st;
}

/* Stills spread over the middle of the clip, where the motion happens, on
 * frames every run renders. */
static void pick_stills(run_ctx *c)
{
    demo_run *r = c->r;
    int step = c->o->step;
    r->still_count = c->o->stills < DEMO_MAX_STILLS ? c->o->stills : DEMO_MAX_STILLS;
    for (int k = 0; k < r->still_count; k++) {
        double frac = r->still_count > 1 ? 0.25 + 0.6 * k / (r->still_count - 1) : 0.55;
        r->still_frames[k] = lround(frac * (double)c->sc->last / step) * step;
    }
}

/* Shaped as `vergence capture`'s (the same sections, capture/capture_json.h),
 * with the run's step, its stills and the image-warping baseline. */
static vg_status write_capture_json(const vg_manifest *m, const scene *s, const demo_scene *sc, const demo_run *r,
                            const frame_desc *clip, const gpu *g, const capture_log *log)
{
    vg_json j = {0};
    capture_json_header(&j, sc->path, s, clip, g, log);
    vg_json_int(&j, "frame_step", r->step);
    vg_json_bool(&j, "analysis", r->analysis);
    vg_json_array_begin(&j, "still_frames");
    for (int i = 0; i < r->still_count; i++)
        vg_json_int(&j, NULL, r->still_frames[i]);
    vg_json_array_end(&j);
    capture_json_passes(&j, log);
    /* The warp at the middle still, against the two-camera reference ... */
    capture_json_stereo(&j, clip, &r->warp);
    /* ... and the image-warping baseline there. */
    vg_json_object_begin(&j, "imagewarp");
    vg_json_num(&j, "hole_fraction", r->imagewarp.hole_fraction);
    vg_json_object_begin(&j, "psnr_db");
    vg_json_num(&j, "left", r->imagewarp.psnr[0]);
    vg_json_num(&j, "right", r->imagewarp.psnr[1]);
    vg_json_object_end(&j);
    vg_json_object_end(&j);
    if (r->has_mid)
        capture_json_metrics(&j, clip, &log->info, &log->result);
    return capture_json_finish(&j, m);
}

vg_status demo_run_scene_mode(gpu *g, const scene *s, const demo_opts *o, demo_scene *sc, int mode_index,
                              bool analysis, demo_progress_fn progress, void *user)
{
    demo_run *r = &sc->runs[mode_index];
    run_ctx c = {.gpu = g, .s = s, .o = o, .sc = sc, .r = r, .progress = progress, .user = user};
    int units = demo_run_units(o, sc, analysis);
    r->analysis = analysis;
    r->step = analysis ? o->analysis_step : o->step;
    r->frames = (int)(sc->last / r->step) + 1;
    char sub[4096];
    vg_status st = vg_path_join(sub, sizeof sub, o->out, sc->name);
    if (st == VG_OK)
        st = vg_path_join(c.dir, sizeof c.dir, sub, frame_mode_names[r->mode]);
    /* The run's own result: an earlier one there goes first (core/manifest.h). */
    vg_manifest man = {0};
    if (st == VG_OK)
        st = vg_manifest_begin(&man, c.dir, "capture.json");
    if (st != VG_OK)
        return st;
    pick_stills(&c);

    frame_desc d = base_desc(&c);
    frame *f = NULL;
    st = frame_create(g, s, &d, &f);
    if (st == VG_ERR_UNSUPPORTED && r->mode != FRAME_MODE_ORIGINAL) {
        snprintf(r->note, sizeof r->note,
                 "mode '%s' is not available in this build: the frame does not produce its disparity map yet "
                 "(the GPU disparity pipeline, issue 4)", frame_mode_names[r->mode]);
        vg_warn("demo: %s: %s; the report leaves it out", sc->name, r->note);
        progress(user, units);
        vg_manifest_end(&man);
        return VG_OK;
    }
    if (st != VG_OK) {
        vg_manifest_end(&man);
        return st;
    }
    c.node_track = malloc(sizeof(int) * (size_t)(s->node_count > 0 ? s->node_count : 1));
    if (!c.node_track)
        st = VG_ERR_NOMEM;
    if (st == VG_OK)
        st = capture_log_begin(&c.log, f, &(capture_log_desc){.frames = r->frames, .science = r->analysis});
    for (int n = 0; st == VG_OK && n < s->node_count; n++)
        c.node_track[n] = -1;
    for (int t = 0; st == VG_OK && t < sc->track_count; t++)
        c.node_track[sc->tracks[t].node] = t;

    if (st == VG_OK)
        st = render_clip(&c, c.frame = f);
    frame_desc clip = *frame_get_desc(f);
    frame_destroy(f);
    r->video = figure_video_close(c.video);
    r->available = st == VG_OK;
    if (st == VG_OK)
        st = log_finish(&c);
    if (st == VG_OK)
        st = render_stills(&c, FRAME_STEREO_WARP);
    if (st == VG_OK)
        st = render_stills(&c, FRAME_STEREO_IMAGEWARP);
    if (st == VG_OK)
        st = write_capture_json(&man, s, sc, r, &clip, g, &c.log);
    vg_manifest_end(&man);
    capture_log_free(&c.log);
    free(c.node_track);
    return st;
}
