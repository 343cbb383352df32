/* vergence — what `vergence optimize` writes into --out: f per frame as
 * PFM; for people, colour previews of the middle frame of g, h and f, a
 * video of each (ffmpeg) and their x-t slices at one row (engine/figure);
 * with --image, a new stereo pair from f (warp/image_warp.h); metrics.json
 * last, the manifest of the result. Before any of it, the check that
 * nothing it writes or removes is an input. */
#include "offline_internal.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/io.h"
#include "core/json.h"
#include "core/log.h"
#include "footage/footage.h"
#include "disparity/disp_metrics.h"
#include "warp/image_warp.h"

static const char *const k_maps[3] = {"g", "h", "f"};

/* ------------------------------------------------------------------------- */
/* The output folder                                                         */
/* ------------------------------------------------------------------------- */

const char *offline_stereo_name(offline_stereo_layout layout)
{
    static const char *const names[4] = {"stereo_LRF_Full_SBS", "stereo_LR", "stereo_TBF_fulltb", "stereo_TB"};
    return names[(unsigned)layout < 4 ? layout : 0];
}

/* What optimize writes into --out: f_NNNN.pfm, the x-t slices, the
 * previews, the videos, metrics.json. */
static bool writes(const char *name)
{
    size_t n = strlen(name);
    for (int l = 0; l < 4; l++)
        for (int k = 0; k < 2; k++) {
            char x[64];
            snprintf(x, sizeof x, "%s.%s", offline_stereo_name((offline_stereo_layout)l), k ? "mkv" : "mp4");
            if (!strcmp(name, x))
                return true;
        }
    for (int m = 0; m < 3; m++) {
        char x[32];
        const char *forms[3] = {"xt_%s.png", "preview_%s.png", "%s.mp4"};
        for (int k = 0; k < 3; k++) {
            snprintf(x, sizeof x, forms[k], k_maps[m]);
            if (!strcmp(name, x))
                return true;
        }
    }
    bool png = n > 4 && !strcmp(name + n - 4, ".png");
    return (!strncmp(name, "f_", 2) && n > 6 && !strcmp(name + n - 4, ".pfm")) || !strcmp(name, "metrics.json") ||
           !strcmp(name, "preview_saliency.png") ||
           (png && (!strncmp(name, "left_", 5) || !strncmp(name, "right_", 6)));
}

/* Nothing optimize writes or removes may be an input. */
vg_status offline_check_out_dir(offline_seq *s)
{
    const offline_desc *d = s->desc;
    vg_inputs in = {0};
    struct { const disp_pattern *p; bool has; const char *label; } seqs[] = {
        {&s->g_pattern, !s->g_from_depth, "--g"},
        {&s->h_pattern, s->has_h, "--h"},
        {&s->depth_pattern, s->has_depth, "--depth"},
        {&s->flow_next_pattern, s->has_flow_next, "--flow-next"},
        {&s->flow_prev_pattern, s->has_flow_prev, "--flow-prev"},
        {&s->saliency_pattern, s->has_saliency, "--saliency"},
        {&s->ids_pattern, s->has_ids, "--ids"},
        {&s->image_pattern, s->has_image, "--image"}};
    vg_status st = VG_OK;
    /* Each frame is found before the next is named: a range far past the
     * files (--frames 0:99999999) stops at the first missing one, bounded
     * by what exists rather than by the number given; pass A then reports
     * it, in frame order, before anything is written. The flow to the next
     * frame is not read at the last frame, nor the previous at the first. */
    for (size_t k = 0; k < sizeof seqs / sizeof seqs[0] && st == VG_OK; k++)
        for (int t = d->first; seqs[k].has && t <= d->last && st == VG_OK; t++) {
            char path[OFFLINE_PATH_CAP];
            bool read = !((seqs[k].p == &s->flow_next_pattern && t == d->last) ||
                          (seqs[k].p == &s->flow_prev_pattern && t == d->first));
            struct stat sb;
            if ((st = offline_frame_path(seqs[k].p, t, path)) != VG_OK)
                break;
            if (read && stat(path, &sb) != 0)
                break;
            st = vg_inputs_add(&in, seqs[k].label, path);
        }
    if (st == VG_OK)
        st = vg_inputs_check_dir(&in, "--out", d->out_dir, "metrics.json", writes);
    vg_inputs_free(&in);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Buffers and videos                                                        */
/* ------------------------------------------------------------------------- */

/* The x-t slices and f's keyframe samples (samples: the window's). */
vg_status offline_outputs_alloc(const offline_seq *s, int samples, offline_outputs *o)
{
    o->f_key = malloc((size_t)samples * sizeof(float));
    o->slice_g = malloc((size_t)s->width * s->frames * sizeof(float));
    o->slice_h = malloc((size_t)s->width * s->frames * sizeof(float));
    o->slice_f = malloc((size_t)s->width * s->frames * sizeof(float));
    return o->f_key && o->slice_g && o->slice_h && o->slice_f ? VG_OK : VG_ERR_NOMEM;
}

void offline_outputs_free(offline_outputs *o)
{
    offline_videos_close(o);
    free(o->f_key);
    free(o->slice_g);
    free(o->slice_h);
    free(o->slice_f);
    o->f_key = o->slice_g = o->slice_h = o->slice_f = NULL;
}

/* One video per map (g.mp4, h.mp4, f.mp4) when ffmpeg is installed. */
static void videos_open(const offline_seq *s, figure_video *v[3])
{
    char ffmpeg[OFFLINE_PATH_CAP];
    const char *exe = s->desc->video ? figure_find_ffmpeg(ffmpeg, sizeof ffmpeg) : NULL;
    for (int m = 0; m < 3; m++) {
        char name[16], path[OFFLINE_PATH_CAP];
        snprintf(name, sizeof name, "%s.mp4", k_maps[m]);
        v[m] = exe && vg_path_join(path, sizeof path, s->desc->out_dir, name) == VG_OK
                   ? figure_video_open(exe, path, s->width, s->height, s->fps)
                   : NULL;
    }
    if (s->desc->video && !exe)
        vg_info("optimize: ffmpeg is not installed (Debian package ffmpeg): previews without videos");
}

/* The new pair's video frame: its size for the layout (a halved eye drops
 * an odd last column or row). */
static void pair_size(const offline_seq *s, int *w, int *h)
{
    switch (s->desc->stereo_layout) {
    case OFFLINE_STEREO_HALF_SBS: *w = 2 * (s->width / 2), *h = s->height; break;
    case OFFLINE_STEREO_FULL_TB: *w = s->width, *h = 2 * s->height; break;
    case OFFLINE_STEREO_HALF_TB: *w = s->width, *h = 2 * (s->height / 2); break;
    default: *w = 2 * s->width, *h = s->height; break;
    }
}

/* Eye e (0 left) into its place of the pair's frame, averaged down where
 * the layout halves it. */
static void pair_place(const offline_seq *s, const uint8_t *eye, int e, uint8_t *frame)
{
    int w = s->width, h = s->height, fw, fh;
    pair_size(s, &fw, &fh);
    switch (s->desc->stereo_layout) {
    case OFFLINE_STEREO_HALF_SBS:
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w / 2; x++)
                for (int c = 0; c < 3; c++)
                    frame[((size_t)y * fw + (size_t)e * (w / 2) + x) * 3 + c] =
                        (uint8_t)((eye[((size_t)y * w + 2 * x) * 3 + c] + eye[((size_t)y * w + 2 * x + 1) * 3 + c] + 1) / 2);
        break;
    case OFFLINE_STEREO_FULL_TB:
        memcpy(frame + (size_t)e * h * w * 3, eye, (size_t)w * h * 3);
        break;
    case OFFLINE_STEREO_HALF_TB:
        for (int y = 0; y < h / 2; y++)
            for (int x = 0; x < w * 3; x++)
                frame[((size_t)e * (h / 2) + y) * w * 3 + x] =
                    (uint8_t)((eye[(size_t)2 * y * w * 3 + x] + eye[((size_t)2 * y + 1) * w * 3 + x] + 1) / 2);
        break;
    default:
        for (int y = 0; y < h; y++)
            memcpy(frame + ((size_t)y * fw + (size_t)e * w) * 3, eye + (size_t)y * w * 3, (size_t)w * 3);
        break;
    }
}

/* The videos of g, h and f, and with --image the new pair's, packed as the
 * layout says and signalled so (figure_video_open_stereo): MP4 and, with
 * --mkv, Matroska. */
vg_status offline_videos_open(const offline_seq *s, offline_outputs *o)
{
    if (!(o->rgb = malloc((size_t)s->width * s->height * 3)))
        return VG_ERR_NOMEM;
    float tol = s->desc->occlusion_tolerance > 0 ? s->desc->occlusion_tolerance : MID_OCCLUSION_TOLERANCE;
    for (int k = 0; k < 2; k++) {
        vg_status st = disp_tepe_init(&o->tepe[k], (size_t)s->width * s->height, tol);
        if (st != VG_OK)
            return st;
    }
    videos_open(s, o->video);
    if (o->video[0] && s->has_image) { /* ffmpeg is there */
        char ffmpeg[OFFLINE_PATH_CAP], path[OFFLINE_PATH_CAP], name[64];
        offline_stereo_layout l = s->desc->stereo_layout;
        figure_packing packing = l == OFFLINE_STEREO_FULL_TB || l == OFFLINE_STEREO_HALF_TB ? FIGURE_PACKING_TB
                                                                                          : FIGURE_PACKING_SBS;
        int w, h;
        pair_size(s, &w, &h);
        for (int k = 0; k < (s->desc->stereo_mkv ? 2 : 1); k++) {
            snprintf(name, sizeof name, "%s.%s", offline_stereo_name(l), k ? "mkv" : "mp4");
            if (figure_find_ffmpeg(ffmpeg, sizeof ffmpeg) &&
                vg_path_join(path, sizeof path, s->desc->out_dir, name) == VG_OK)
                o->pair_video[k] = figure_video_open_stereo(ffmpeg, path, w, h, s->fps, packing);
        }
    }
    return VG_OK;
}

/* Closed before metrics.json lists the files with their sizes. */
void offline_videos_close(offline_outputs *o)
{
    for (int m = 0; m < 3; m++) {
        figure_video_close(o->video[m]);
        o->video[m] = NULL;
    }
    for (int k = 0; k < 2; k++) {
        figure_video_close(o->pair_video[k]);
        o->pair_video[k] = NULL;
        o->tepe_v[k] = disp_tepe_velocity(&o->tepe[k]);
        o->tepe_a[k] = disp_tepe_accel(&o->tepe[k]);
        disp_tepe_free(&o->tepe[k]);
    }
    free(o->rgb);
    o->rgb = NULL;
}

/* ------------------------------------------------------------------------- */
/* Frames                                                                    */
/* ------------------------------------------------------------------------- */

/* The colour scale of a map: g its own range, h and f the target range. */
static void map_scale(const offline_seq *s, int m, float *lo, float *hi)
{
    *lo = (float)(m == 0 ? s->g_min : s->range_lo);
    *hi = (float)(m == 0 ? s->g_max : s->range_hi);
}

/* The full-resolution row of the x-t slices. */
static int slice_row(const offline_seq *s)
{
    return s->desc->row >= 0 && s->desc->row < s->height ? s->desc->row : s->height / 2;
}

/* The view of --image is the left camera's. */
static bool image_left(const offline_seq *s)
{
    return s->desc->image_view == OFFLINE_VIEW_LEFT ||
           (s->desc->image_view == OFFLINE_VIEW_AUTO && offline_g_in_px(s));
}

/* The middle frame of each map as a colour PNG with a legend. */
static vg_status write_previews(const offline_seq *s, int t, const float *const maps[3])
{
    vg_status st = VG_OK;
    for (int m = 0; m < 3 && st == VG_OK; m++) {
        char name[32], path[OFFLINE_PATH_CAP], title[96];
        float lo, hi;
        map_scale(s, m, &lo, &hi);
        snprintf(name, sizeof name, "preview_%s.png", k_maps[m]);
        snprintf(title, sizeof title, "%s, frame %d: vergence", k_maps[m], t);
        st = vg_path_join(path, sizeof path, s->desc->out_dir, name);
        if (st == VG_OK)
            st = figure_map_png(path, maps[m], s->width, s->height, 1, lo, hi,
                                &(figure_legend){.title = title, .unit = "arcmin"});
    }
    /* The operator's saliency of that frame (frame_h in offline_solve.c just filled it). */
    if (st == VG_OK && (s->has_saliency || s->compute_saliency)) {
        char path[OFFLINE_PATH_CAP], title[96];
        snprintf(title, sizeof title, "saliency (%s), frame %d", s->has_saliency ? "--saliency" : "computed", t);
        st = vg_path_join(path, sizeof path, s->desc->out_dir, "preview_saliency.png");
        if (st == VG_OK)
            st = figure_map_png(path, s->saliency, s->width, s->height, 1, 0.0f, 1.0f,
                                &(figure_legend){.title = title, .unit = ""});
    }
    return st;
}

static void videos_frame(const offline_seq *s, figure_video *v[3], const float *const maps[3], uint8_t *rgb)
{
    for (int m = 0; m < 3; m++) {
        if (!v[m])
            continue;
        float lo, hi;
        map_scale(s, m, &lo, &hi);
        figure_map_rgb(maps[m], s->width, s->height, 1, lo, hi, rgb);
        figure_video_frame(&v[m], rgb);
    }
}

/* The new stereo pair of frame t from f: the image's pixels move to where
 * f puts them in each eye, the engine's image warping (warp/image_warp.h,
 * the pass imagewarp.left/right), then the hole fill. With P(a) the image
 * parallax of vergence a (x_right - x_left, pixels of this image across the
 * panel width) and the image at s on the baseline (0 the centre view, -1/2
 * the left), a pixel at x moves to x - s P(g) + e P(f), e = -1/2 left, +1/2
 * right. Writes left_NNNN.png, right_NNNN.png and a frame of the pair's videos. */
static vg_status write_pair(offline_seq *s, int t, const float *g, const float *f, const float *z,
                            figure_video *video[2])
{
    size_t np = (size_t)s->width * s->height;
    bool packed = video[0] || video[1];
    uint8_t *src = NULL, *eye = malloc(np * 3), *hole = malloc(np), *sbs = packed ? malloc(2 * np * 3) : NULL;
    float *shift = malloc(np * sizeof(float)), *zo = malloc(np * sizeof(float));
    double *pf = malloc(np * sizeof(double)), *pg = malloc(np * sizeof(double));
    vg_status st = eye && hole && shift && zo && pf && pg && (sbs || !packed) ? offline_read_image(s, t, &src)
                                                                              : VG_ERR_NOMEM;
    double to_px = (double)s->width / s->display.width_m, at = image_left(s) ? -0.5 : 0.0;
    for (size_t i = 0; st == VG_OK && i < np; i++) { /* once for both eyes */
        pf[i] = stereo_parallax_from_vergence(&s->display, f[i]);
        pg[i] = at * stereo_parallax_from_vergence(&s->display, g[i]);
    }
    for (int e = 0; e < 2 && st == VG_OK; e++) {
        double side = e ? 0.5 : -0.5;
        for (size_t i = 0; i < np; i++)
            shift[i] = (float)(to_px * (side * pf[i] - pg[i]));
        long holes = image_warp(src, s->width, s->height, 3, shift, z, eye, zo, hole);
        if (holes < 0) {
            st = VG_ERR_NOMEM;
            break;
        }
        s->pair_holes += holes;
        image_warp_fill(eye, s->width, s->height, 3, zo, hole);
        char name[64], path[OFFLINE_PATH_CAP];
        snprintf(name, sizeof name, "%s_%04d.png", e ? "right" : "left", t);
        st = vg_path_join(path, sizeof path, s->desc->out_dir, name);
        if (st == VG_OK)
            st = vg_png_write(path, s->width, s->height, 3, eye);
        if (sbs)
            pair_place(s, eye, e, sbs);
    }
    for (int k = 0; k < 2 && st == VG_OK && sbs; k++)
        figure_video_frame(&video[k], sbs);
    free(src); free(eye); free(hole); free(sbs); free(shift); free(zo); free(pf); free(pg);
    return st;
}

/* Frame t of pass C, upsampled: its samples outside the target range, the
 * new pair (--image), f_NNNN.pfm, a frame of each video, the previews at the
 * middle frame and the frame's row of each x-t slice. Unknown g stays
 * unknown: g, h and f become inf there, grey in every picture. */
vg_status offline_write_frame(offline_seq *s, int t, float *g, float *h, float *f, const float *z,
                              offline_outputs *o)
{
    const offline_desc *d = s->desc;
    size_t np = (size_t)s->width * s->height;
    vg_status st = VG_OK;
    for (size_t i = 0; i < np; i++) {
        if (s->unknown[i])
            continue;
        o->h_outside_range += !disp_metrics_in_range(h[i], (float)s->range_lo, (float)s->range_hi);
        o->f_outside_range += !disp_metrics_in_range(f[i], (float)s->range_lo, (float)s->range_hi);
    }
    if (s->has_image && (st = write_pair(s, t, g, f, z, o->pair_video)) != VG_OK)
        return st;
    for (int k = 0; k < 2 && offline_is_cut(s, t); k++) /* the change across a cut is no motion */
        disp_tepe_restart(&o->tepe[k]);
    disp_tepe_frame(&o->tepe[0], h, g, z, s->unknown);
    disp_tepe_frame(&o->tepe[1], f, g, z, s->unknown);
    for (size_t i = 0; i < np; i++)
        if (s->unknown[i])
            g[i] = h[i] = f[i] = INFINITY;
    char path[OFFLINE_PATH_CAP], name[64];
    snprintf(name, sizeof name, "f_%04d.pfm", t);
    st = vg_path_join(path, sizeof path, d->out_dir, name);
    vg_imagef img = {.width = s->width, .height = s->height, .channels = 1, .data = f};
    if (st == VG_OK)
        st = vg_pfm_write(path, &img);
    const float *const maps[3] = {g, h, f};
    videos_frame(s, o->video, maps, o->rgb);
    if (st == VG_OK && t == d->first + (d->last - d->first) / 2)
        st = write_previews(s, t, maps);
    size_t r = (size_t)(t - d->first) * s->width, src = (size_t)slice_row(s) * s->width;
    memcpy(o->slice_g + r, g + src, s->width * sizeof(float));
    memcpy(o->slice_h + r, h + src, s->width * sizeof(float));
    memcpy(o->slice_f + r, f + src, s->width * sizeof(float));
    return st;
}

/* ------------------------------------------------------------------------- */
/* Results                                                                   */
/* ------------------------------------------------------------------------- */

/* An x-t slice (time runs down) in colour with a legend. */
static vg_status write_slice(const offline_seq *s, int m, const float *v, float lo, float hi)
{
    char name[32], path[OFFLINE_PATH_CAP], title[128];
    const offline_desc *d = s->desc;
    snprintf(name, sizeof name, "xt_%s.png", k_maps[m]);
    snprintf(title, sizeof title, "%s at row %d, frames %d-%d down: vergence", k_maps[m], slice_row(s), d->first,
             d->last);
    vg_status st = vg_path_join(path, sizeof path, d->out_dir, name);
    int repeat = s->frames < 60 ? (60 + s->frames - 1) / s->frames : 1; /* a short clip still reads */
    return st == VG_OK ? figure_map_png(path, v, s->width, s->frames, repeat, lo, hi,
                                        &(figure_legend){.title = title, .unit = "arcmin"})
                       : st;
}

/* tepe: the field's TEPE and its acceleration variant at full resolution
 * (NULL: not measured, the solver's keyframe samples). */
static void json_metrics(vg_json *j, const char *key, const disp_metrics *m, double range_violation,
                         const double tepe[2])
{
    vg_json_object_begin(j, key);
    disp_metrics_write_json(j, m, range_violation);
    if (tepe) {
        vg_json_num(j, "tepe_arcmin", tepe[0]);
        vg_json_num(j, "tepe_accel_arcmin", tepe[1]);
    }
    vg_json_object_end(j);
}

/* The x-t slices, then metrics.json: the metrics of h, of the written f
 * and of the solve's f, the solve, the input and the display. */
vg_status offline_write_results(offline_seq *s, const mid_window *w, const float *f_sol, const offline_outputs *o,
                                const mid_solve_stats *ss)
{
    disp_metrics mh, mf, ms;
    disp_metrics_window(w, w->h, NULL, &mh);
    disp_metrics_window(w, o->f_key, NULL, &mf);
    disp_metrics_window(w, f_sol, NULL, &ms);
    double np = (double)s->width * s->height * s->frames - (double)s->unknown_total; /* pixels of known g */
    if (np < 1)
        np = 1;
    /* g on its own scale; h and f on one, so the two compare pixel for pixel. */
    float lo[2] = {FLT_MAX, FLT_MAX}, hi[2] = {-FLT_MAX, -FLT_MAX};
    size_t n = (size_t)s->width * s->frames;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(o->slice_g[i]))
            continue; /* unknown g */
        lo[0] = fminf(lo[0], o->slice_g[i]), hi[0] = fmaxf(hi[0], o->slice_g[i]);
        lo[1] = fminf(lo[1], fminf(o->slice_h[i], o->slice_f[i]));
        hi[1] = fmaxf(hi[1], fmaxf(o->slice_h[i], o->slice_f[i]));
    }
    const float *slice[3] = {o->slice_g, o->slice_h, o->slice_f};
    vg_status st = VG_OK;
    for (int m = 0; m < 3 && st == VG_OK; m++)
        st = write_slice(s, m, slice[m], lo[m > 0], hi[m > 0]);
    if (st != VG_OK)
        return st;
    const offline_desc *d = s->desc;
    vg_json j = {0};
    vg_json_object_begin(&j, NULL);
    json_metrics(&j, "h", &mh, o->h_outside_range / np, (const double[2]){o->tepe_v[0], o->tepe_a[0]});
    json_metrics(&j, "f", &mf, o->f_outside_range / np, (const double[2]){o->tepe_v[1], o->tepe_a[1]});
    json_metrics(&j, "f_solver", &ms, ms.range_violation, NULL);
    if (s->f_ungated) { /* the causal window's f before its gate: what it would show without one */
        disp_metrics mu;
        disp_metrics_window(w, s->f_ungated, NULL, &mu);
        json_metrics(&j, "f_ungated", &mu, mu.range_violation, NULL);
        vg_json_num(&j, "ungated_mid_ratio",
                    mh.mid_distortion_jnd > 0 ? mu.mid_distortion_jnd / mh.mid_distortion_jnd : NAN);
    }
    vg_json_num(&j, "mid_reduction",
                mh.mid_distortion_jnd > 0 ? 1.0 - mf.mid_distortion_jnd / mh.mid_distortion_jnd : 0.0);
    vg_json_num(&j, "mid_ratio", mh.mid_distortion_jnd > 0 ? mf.mid_distortion_jnd / mh.mid_distortion_jnd : NAN);
    vg_json_object_begin(&j, "solve");
    vg_json_str(&j, "solver", d->solver == MID_SOLVER_DESCENT ? "descent" : "gauss-newton");
    vg_json_str(&j, "look_ahead", d->causal ? "causal" : "foresight");
    vg_json_str(&j, "edge_norm", (const char *[]){"range", "arcmin", "pixel"}[d->edge_norm]);
    vg_json_str(&j, "velocity_unit", d->velocity_per_keyframe ? "keyframe" : "second");
    if (d->causal) { /* cost_h / cost_f: the last window's */
        vg_json_int(&j, "windows", s->causal_windows);
        vg_json_int(&j, "keyframes_behind", s->causal_past);
        vg_json_int(&j, "keyframes_ahead", s->causal_future);
    }
    vg_json_int(&j, "iterations", ss->iterations);
    vg_json_int(&j, "cg_steps", ss->cg_steps);
    vg_json_num(&j, "cost_h", ss->cost_initial);
    vg_json_num(&j, "cost_f", ss->cost_final);
    vg_json_num(&j, "ms", ss->ms);
    vg_json_object_end(&j);
    vg_json_object_begin(&j, "input");
    vg_json_int(&j, "first", d->first);
    vg_json_int(&j, "last", d->last);
    vg_json_int(&j, "width", s->width);
    vg_json_int(&j, "height", s->height);
    vg_json_int(&j, "keyframes", s->keyframes);
    vg_json_int(&j, "coarse_width", s->grid.nx);
    vg_json_int(&j, "coarse_height", s->grid.ny);
    vg_json_str(&j, "operator", s->has_h ? "given" : d->ema ? "ema" : disp_operator_kind_name(d->op));
    if (!s->has_h && d->ema) {
        vg_json_num(&j, "ema_decay", d->ema_decay > 0 ? d->ema_decay : 0.9);
        vg_json_int(&j, "ema_window", d->ema_window > 0 ? d->ema_window : 30);
        const struct offline_range *e0 = &s->ema[0], *e1 = &s->ema[s->frames - 1];
        vg_json_nums(&j, "ema_range_first", (const float[2]){e0->lo, e0->hi}, 2);
        vg_json_nums(&j, "ema_range_last", (const float[2]){e1->lo, e1->hi}, 2);
    }
    vg_json_str(&j, "saliency", s->has_saliency ? "file" : s->compute_saliency ? "computed" : "uniform");
    vg_json_str(&j, "flow", offline_flow_name(s->flow));
    vg_json_str(&j, "g_units", offline_g_in_px(s) ? "px" : "arcmin");
    vg_json_str(&j, "g_file", s->g_from_depth                     ? "depth"
                              : s->g_dataset_png                  ? s->g_dataset_png
                              : footage_is_exr(s->g_pattern.text)  ? "OpenEXR"
                              : footage_is_hdf5(s->g_pattern.text) ? "HDF5"
                                                                   : "PFM");
    vg_json_num(&j, "g_min", s->g_min);
    vg_json_num(&j, "g_max", s->g_max);
    vg_json_num(&j, "range_lo", s->range_lo);
    vg_json_num(&j, "range_hi", s->range_hi);
    vg_json_object_end(&j);
    if (s->flow == OFFLINE_FLOW_COMPUTED) { /* how the flows were made (input.flow "computed") */
        vg_json_object_begin(&j, "flow");
        vg_json_str(&j, "method", "DIS optical flow (OpenCV); pixels failing the forward-backward check "
                                  "take their row's nearest consistent flow");
        vg_json_str(&j, "preset", flow_preset_name(d->flow_preset));
        vg_json_str(&j, "from", d->video_in ? "--video" : "--image");
        vg_json_str(&j, "to", s->flow_direct ? "keyframes" : "frames");
        vg_json_int(&j, "pairs_computed", (int)s->flow_computed);
        vg_json_num(&j, "inconsistent_fraction",
                    s->flow_computed ? s->flow_occluded / (2.0 * s->flow_computed * s->width * s->height) : 0.0);
        vg_json_num(&j, "ms", s->flow_ms);
        vg_json_object_end(&j);
    }
    vg_json_object_begin(&j, "scene_cuts");
    vg_json_str(&j, "mode", offline_cuts_name(d->scene_cuts));
    if (d->scene_cuts == OFFLINE_CUTS_AUTO) {
        vg_json_str(&j, "measure", s->has_image ? "joint RGB histogram, 4 bins a channel, half the L1 distance of "
                                                  "consecutive frames'" : "none (no colour frames)");
        vg_json_num(&j, "threshold", d->cut_threshold > 0 ? d->cut_threshold : OFFLINE_CUT_THRESHOLD);
        vg_json_num(&j, "largest_within_shots", s->cut_within_max);
    }
    vg_json_array_begin(&j, "frames");
    for (int i = 0; i < s->cuts; i++)
        vg_json_int(&j, NULL, s->cut[i].frame);
    vg_json_array_end(&j);
    vg_json_array_begin(&j, "distances");
    for (int i = 0; i < s->cuts; i++)
        vg_json_num(&j, NULL, s->cut[i].distance);
    vg_json_array_end(&j);
    vg_json_object_end(&j);
    if (s->has_image) {
        vg_json_object_begin(&j, "stereo_pair");
        vg_json_str(&j, "image_view", image_left(s) ? "left" : "centre");
        vg_json_num(&j, "hole_fraction", s->pair_holes / (2.0 * s->width * s->height * s->frames));
        vg_json_str(&j, "hole_fill", "each run of holes in a row takes its farther neighbour's colour");
        vg_json_object_end(&j);
    }
    stereo_display_json(&j, &d->display);
    /* metrics.json is the manifest of the result, written last. */
    st = vg_manifest_files(&s->manifest, &j);
    vg_json_object_end(&j);
    char path[OFFLINE_PATH_CAP];
    if (st == VG_OK)
        st = vg_path_join(path, sizeof path, d->out_dir, "metrics.json");
    if (st == VG_OK)
        st = vg_json_write_file(&j, path);
    vg_json_free(&j);
    if (st == VG_OK)
        vg_info("optimize: MID distortion %.3f -> %.3f JND (%.1f %% less), f range violation %.4f, static RMS %.3f "
                "arcmin", mh.mid_distortion_jnd, mf.mid_distortion_jnd,
                mh.mid_distortion_jnd > 0 ? 100.0 * (1.0 - mf.mid_distortion_jnd / mh.mid_distortion_jnd) : 0.0,
                o->f_outside_range / np, mf.static_rms);
    return st;
}
