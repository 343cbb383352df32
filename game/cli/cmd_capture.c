/* vergence capture — render frames headless and write the G-buffer to files.
 *
 * Per frame NNNN (0-based within the capture):
 *   frame_NNNN_color.png        lit colour (sRGB)
 *   frame_NNNN_saliency.png     saliency, 8-bit grey
 *   frame_NNNN_depth.pfm        linear depth along the view axis, metres
 *   frame_NNNN_ids.png          instance id, 24 bits in RGB (R low byte); 0 = background
 *   frame_NNNN_motion_prev.flo  pixels to where each surface point is at the previous keyframe
 *   frame_NNNN_motion_next.flo  ... at the next keyframe
 * the middle frame's g, h and f (those its mode computed) as colour previews
 * with a legend, preview_{g,h,f}.png, and capture.json last, so a folder
 * without it is an incomplete capture. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "capture/capture_image.h"
#include "capture/capture_json.h"
#include "commands.h"
#include "core/clock.h"
#include "core/io.h"
#include "core/json.h"
#include "core/log.h"
#include "figure/figure.h"
#include "core/manifest.h"
#include "options/display_cli.h"
#include "options/gpu_cli.h"
#include "frame/frame.h"
#include "shared.h"
#include "disparity/disp_curve.h"
#include "observer/ball_measure.h"
#include "observer/observer_engine.h"
#include "rules/game.h"

typedef struct capture_opts {
    const char *scene, *out, *dump_graph;
    int frames, camera, stride, solver_iterations, throw_no, occlusion, look_ahead, saliency;
    double time, fps;
    int size[2];
    int stereo, mode, compose, op;
    double target_range;
    bool swap_eyes, diffuse, no_reference, write_aux;
    const char *curve;
    double tess_px, tess_error;
    const char *caption;
    double caption_parallax;
    gpu_cli gpu;
    display_cli display;
} capture_opts;

static capture_opts o = {
    .frames = 1, .fps = 60, .stride = 10, .size = {960, 540}, .gpu = {.device = -1},
    .stereo = FRAME_STEREO_WARP, .mode = FRAME_MODE_OPTIMIZED, .compose = FRAME_COMPOSE_SBS,
    .op = DISP_OPERATOR_LANG, .throw_no = -1,
};

static const char *const k_occlusion[] = {"links", "depth", NULL};

/* --throw: the ball, the camera its throws are aimed with, and its figures. */
static game_ball ball;
static vg_camera ball_aim;
static ball_figures ball_fig;

static const vg_opt k_opts[] = {
    {"--scene", VG_OPT_STRING, &o.scene, "FILE", "glTF 2.0 scene (.gltf or .glb)", NULL, 0, 0},
    {"--out", VG_OPT_STRING, &o.out, "DIR", "output folder (created if missing)", NULL, 0, 0},
    {"--frames", VG_OPT_INT, &o.frames, "N", "number of frames (default 1)", NULL, 1, 100000},
    {"--time", VG_OPT_FLOAT, &o.time, "T0", "start time in seconds (rounded to a frame; default 0)", NULL, 0, 1e6},
    {"--fps", VG_OPT_FLOAT, &o.fps, "HZ", "frame rate of the fixed time step (default 60)", NULL, 1, 1000},
    {"--size", VG_OPT_SIZE, o.size, "WxH", "image size (default 960x540)", NULL, 0, 0},
    {"--camera", VG_OPT_INT, &o.camera, "N", "camera node of the scene to use (default 0)", NULL, 0, 1000},
    {"--keyframe-stride", VG_OPT_INT, &o.stride, "S", "frames between keyframes (default 10, paper 4.4)", NULL, 1, 1000},
    {"--throw", VG_OPT_INT, &o.throw_no, "N", "throw the scene's 'ball' as the game's free play draws throw N, "
     "launched at --time (the arena)", NULL, 0, 100000},
    {"--temporal-occlusion", VG_OPT_CHOICE, &o.occlusion, "TEST", "the upsampling's occlusion test in time: links "
     "(instance, and depth or trajectory; default) or depth (alone, paper 4.4)", k_occlusion, 0, 0},
    {"--saliency", VG_OPT_CHOICE, &o.saliency, "FROM", "the operator's saliency: authored (the glTF's "
     "extras; none: uniform), computed (colour contrast, motion, depth) or auto (authored when the scene has "
     "any; default)", frame_saliency_names, 0, 0},
    {"--look-ahead", VG_OPT_CHOICE, &o.look_ahead, "HOW", "the keyframe window's future: foresight (the scene "
     "evaluated ahead; default) or causal (predicted from the past frames only)", frame_look_ahead_names, 0, 0},
    {"--solver-iterations", VG_OPT_INT, &o.solver_iterations, "N", "outer solver iterations each time the keyframe window moves (default: the frame's)", NULL, 1, 64},
    {"--stereo-render", VG_OPT_CHOICE, &o.stereo, "HOW", "how the stereo pair is made (default warp)", frame_stereo_names, 0, 0},
    {"--mode", VG_OPT_ENUM, &o.mode, "MODE", "disparity shown: g, h or f (default optimized)", frame_mode_names, 0, 0},
    {"--output", VG_OPT_ENUM, &o.compose, "LAYOUT", "how frame_NNNN_stereo.png packs the eyes (default sbs)", frame_compose_names, 0, 0},
    {"--operator", VG_OPT_ENUM, &o.op, "NAME", "disparity operator h = M(g, saliency) (default lang)", disp_operator_names, 0, 0},
    {"--target-range", VG_OPT_FLOAT, &o.target_range, "ARCMIN", "half-width of the target range around the screen (default 60)", NULL, 1, 600},
    {"--swap-eyes", VG_OPT_FLAG, &o.swap_eyes, NULL, "exchange left and right in the composed output", NULL, 0, 0},
    {"--tess-px", VG_OPT_FLOAT, &o.tess_px, "PX", "tessellate edges down to PX pixels (paper: 1); default: error-driven", NULL, 0.05, 1000},
    {"--tess-error", VG_OPT_FLOAT, &o.tess_error, "PX", "error-driven tessellation tolerance in pixels (default 0.025)", NULL, 0.001, 100},
    {"--diffuse", VG_OPT_FLAG, &o.diffuse, NULL, "no specular highlights (eyes shade identically)", NULL, 0, 0},
    {"--curve", VG_OPT_STRING, &o.curve, "FILE", "use a global curve baked by 'vergence bake-curve'", NULL, 0, 0},
    {"--no-reference", VG_OPT_FLAG, &o.no_reference, NULL, "skip the two-camera reference (no holes or PSNR figures)", NULL, 0, 0},
    {"--write-aux", VG_OPT_FLAG, &o.write_aux, NULL, "also write frame_NNNN_{left,right}_aux.pfm (centre x, disparity error px, cascade stage)", NULL, 0, 0},
    {"--caption", VG_OPT_STRING, &o.caption, "TEXT", "draw TEXT at the top left of each eye (an overlay: "
     "in the eye images and their measures too)", NULL, 0, 0},
    {"--caption-parallax", VG_OPT_FLOAT, &o.caption_parallax, "PX", "the caption's parallax in eye pixels: "
     "positive behind the screen, negative in front (default 0: screen depth)", NULL, -1000, 1000},
    {"--dump-graph", VG_OPT_STRING, &o.dump_graph, "FILE", "print the compiled frame graph and write it as Graphviz DOT to FILE", NULL, 0, 0},
    DISPLAY_CLI_OPTIONS(o.display),
    GPU_CLI_OPTIONS(o.gpu),
};

/* ------------------------------------------------------------------------- */
/* Frame files                                                               */
/* ------------------------------------------------------------------------- */

static vg_status write_rgba_as_rgb(const char *dir, const char *name, const uint8_t *rgba, uint32_t w, uint32_t h)
{
    size_t px = (size_t)w * h;
    uint8_t *rgb = malloc(px * 3);
    if (!rgb)
        return VG_ERR_NOMEM;
    for (size_t i = 0; i < px; i++)
        memcpy(rgb + 3 * i, rgba + 4 * i, 3);
    char path[4096];
    vg_status st = vg_path_join(path, sizeof path, dir, name);
    if (st == VG_OK)
        st = vg_png_write(path, (int)w, (int)h, 3, rgb);
    free(rgb);
    return st;
}

/* The cascade debug view (paper Fig. 5): the left eye tinted by the stage
 * that gave each pixel's vertices their disparity. */
static vg_status write_cascade(const char *dir, int n, const frame_outputs *fo, uint32_t w, uint32_t h)
{
    uint8_t *rgb = malloc((size_t)w * h * 3);
    if (!rgb)
        return VG_ERR_NOMEM;
    capture_image_cascade(fo, w, h, false, rgb);
    char name[64], path[4096];
    snprintf(name, sizeof name, "frame_%04d_cascade.png", n);
    vg_status st = vg_path_join(path, sizeof path, dir, name);
    if (st == VG_OK)
        st = vg_png_write(path, (int)w, (int)h, 3, rgb);
    free(rgb);
    return st;
}

static vg_status write_stereo(const char *dir, int n, const frame_outputs *fo, uint32_t w, uint32_t h)
{
    char name[64], path[4096];
    vg_status st;
    snprintf(name, sizeof name, "frame_%04d_left.png", n);
    if ((st = write_rgba_as_rgb(dir, name, fo->left, w, h)))
        return st;
    snprintf(name, sizeof name, "frame_%04d_right.png", n);
    if ((st = write_rgba_as_rgb(dir, name, fo->right, w, h)))
        return st;
    snprintf(name, sizeof name, "frame_%04d_stereo.png", n);
    if ((st = write_rgba_as_rgb(dir, name, fo->stereo, fo->stereo_width, fo->stereo_height)))
        return st;
    if ((st = write_cascade(dir, n, fo, w, h)))
        return st;
    for (int e = 0; e < 2 && o.write_aux; e++) {
        vg_imagef aux;
        if ((st = vg_imagef_alloc(&aux, (int)w, (int)h, 3)))
            return st;
        const float *src = e ? fo->right_aux : fo->left_aux;
        const uint8_t *rgba = e ? fo->right : fo->left;
        for (size_t i = 0; i < (size_t)w * h; i++) {
            aux.data[3 * i] = src[4 * i];
            aux.data[3 * i + 1] = rgba[4 * i + 3] > 192 ? src[4 * i + 2] : 0.0f; /* geometry only */
            aux.data[3 * i + 2] = src[4 * i + 3];
        }
        snprintf(name, sizeof name, "frame_%04d_%s_aux.pfm", n, e ? "right" : "left");
        if (!(st = vg_path_join(path, sizeof path, dir, name)))
            st = vg_pfm_write(path, &aux);
        vg_imagef_free(&aux);
        if (st)
            return st;
    }
    vg_imagef g = {.width = (int)w, .height = (int)h, .channels = 1, .data = (float *)fo->g};
    snprintf(name, sizeof name, "frame_%04d_g.pfm", n);
    if ((st = vg_path_join(path, sizeof path, dir, name)) || (st = vg_pfm_write(path, &g)))
        return st;
    /* h and f beside g (vergence, arcmin), when the frame computed them. */
    const float *maps[2] = {fo->h, fo->f};
    for (int m = 0; m < 2; m++) {
        if (!maps[m])
            continue;
        vg_imagef img = {.width = (int)w, .height = (int)h, .channels = 1, .data = (float *)maps[m]};
        snprintf(name, sizeof name, "frame_%04d_%c.pfm", n, m ? 'f' : 'h');
        if ((st = vg_path_join(path, sizeof path, dir, name)) || (st = vg_pfm_write(path, &img)))
            return st;
    }
    snprintf(name, sizeof name, "frame_%04d_curve.bin", n);
    if ((st = vg_path_join(path, sizeof path, dir, name)) || (st = disp_curve_write(path, fo->curve)))
        return st;
    return VG_OK;
}

static vg_status write_frame(const char *dir, int n, const frame_outputs *fo, uint32_t w, uint32_t h)
{
    size_t px = (size_t)w * h;
    char path[4096], name[64];
    uint8_t *rgb = malloc(px * 3), *grey = malloc(px);
    vg_imagef depth = {0}, prev = {0}, next = {0};
    vg_status st = rgb && grey ? VG_OK : VG_ERR_NOMEM;
    if (st == VG_OK)
        st = vg_imagef_alloc(&depth, (int)w, (int)h, 1);
    if (st == VG_OK)
        st = vg_imagef_alloc(&prev, (int)w, (int)h, 2);
    if (st == VG_OK)
        st = vg_imagef_alloc(&next, (int)w, (int)h, 2);
    if (st != VG_OK)
        goto done;

    for (size_t i = 0; i < px; i++) {
        memcpy(rgb + 3 * i, fo->color + 4 * i, 3);
        grey[i] = fo->color[4 * i + 3];
    }
    snprintf(name, sizeof name, "frame_%04d_color.png", n);
    if ((st = vg_path_join(path, sizeof path, dir, name)) || (st = vg_png_write(path, (int)w, (int)h, 3, rgb)))
        goto done;
    snprintf(name, sizeof name, "frame_%04d_saliency.png", n);
    if ((st = vg_path_join(path, sizeof path, dir, name)) || (st = vg_png_write(path, (int)w, (int)h, 1, grey)))
        goto done;

    for (size_t i = 0; i < px; i++) {
        uint32_t id = fo->ids[i];
        rgb[3 * i] = (uint8_t)id;
        rgb[3 * i + 1] = (uint8_t)(id >> 8);
        rgb[3 * i + 2] = (uint8_t)(id >> 16);
    }
    snprintf(name, sizeof name, "frame_%04d_ids.png", n);
    if ((st = vg_path_join(path, sizeof path, dir, name)) || (st = vg_png_write(path, (int)w, (int)h, 3, rgb)))
        goto done;

    memcpy(depth.data, fo->depth, px * sizeof(float));
    snprintf(name, sizeof name, "frame_%04d_depth.pfm", n);
    if ((st = vg_path_join(path, sizeof path, dir, name)) || (st = vg_pfm_write(path, &depth)))
        goto done;

    for (size_t i = 0; i < px; i++) {
        prev.data[2 * i] = fo->motion[4 * i];
        prev.data[2 * i + 1] = fo->motion[4 * i + 1];
        next.data[2 * i] = fo->motion[4 * i + 2];
        next.data[2 * i + 1] = fo->motion[4 * i + 3];
    }
    snprintf(name, sizeof name, "frame_%04d_motion_prev.flo", n);
    if ((st = vg_path_join(path, sizeof path, dir, name)) || (st = vg_flo_write(path, &prev)))
        goto done;
    snprintf(name, sizeof name, "frame_%04d_motion_next.flo", n);
    if ((st = vg_path_join(path, sizeof path, dir, name)) || (st = vg_flo_write(path, &next)))
        goto done;
    if (fo->left)
        st = write_stereo(dir, n, fo, w, h);
done:
    free(rgb);
    free(grey);
    vg_imagef_free(&depth);
    vg_imagef_free(&prev);
    vg_imagef_free(&next);
    return st;
}

/* ------------------------------------------------------------------------- */
/* capture.json                                                              */
/* ------------------------------------------------------------------------- */

/* "ball" (--throw): the ball's own figures over the keyframes of its flight
 * that were captured (game/observer/ball_measure.h). */
static void write_ball(vg_json *j, const ball_figures *b)
{
    float g[BALL_MEASURE_MAX_KEYS], h[BALL_MEASURE_MAX_KEYS], f[BALL_MEASURE_MAX_KEYS];
    for (int i = 0; i < b->keys; i++)
        g[i] = (float)b->g[i], h[i] = (float)b->h[i], f[i] = (float)b->f[i];
    vg_json_object_begin(j, "ball");
    vg_json_int(j, "keyframes", b->keys);
    if (b->keys >= 3) {
        vg_json_num(j, "h_mid_distortion_jnd", b->h_jnd);
        vg_json_num(j, "f_mid_distortion_jnd", b->f_jnd);
        if (b->h_jnd > 0)
            vg_json_num(j, "f_over_h", b->f_jnd / b->h_jnd);
    }
    vg_json_num(j, "max_f_minus_h_arcmin", b->max_f_minus_h);
    /* At the frame rate, where every frame from the launch was captured. */
    vg_json_int(j, "frames", b->frames);
    if (b->frames >= 3) {
        vg_json_num(j, "h_frame_mid_distortion_jnd", b->h_frame_jnd);
        vg_json_num(j, "f_frame_mid_distortion_jnd", b->f_frame_jnd);
        if (b->h_frame_jnd > 0)
            vg_json_num(j, "f_over_h_frame", b->f_frame_jnd / b->h_frame_jnd);
        vg_json_num(j, "max_f_minus_h_frame_arcmin", b->max_f_minus_h_frame);
    }
    vg_json_int(j, "min_pixels", b->min_pixels);
    vg_json_int(j, "min_grid_samples", b->min_samples);
    vg_json_nums(j, "g_arcmin", g, b->keys);
    vg_json_nums(j, "h_arcmin", h, b->keys);
    vg_json_nums(j, "f_arcmin", f, b->keys);
    vg_json_object_end(j);
}

static vg_status write_json(const vg_manifest *m, const scene *s, const gpu *g, const frame_desc *fd,
                            const capture_log *log)
{
    vg_json j = {0};
    capture_json_header(&j, o.scene, s, fd, g, log);
    capture_json_cameras(&j, log);
    capture_json_passes(&j, log);
    capture_json_shadow(&j, log);
    if (fd->stereo != FRAME_STEREO_OFF)
        capture_json_stereo(&j, fd, &log->warp);
    if (o.throw_no >= 0)
        vg_json_int(&j, "throw", o.throw_no);
    if (o.throw_no >= 0 && ball_fig.keys)
        write_ball(&j, &ball_fig);
    if (o.caption) {
        vg_json_str(&j, "caption", o.caption);
        vg_json_num(&j, "caption_parallax_px", o.caption_parallax);
    }
    if (log->science)
        capture_json_metrics(&j, fd, &log->info, &log->result);
    return capture_json_finish(&j, m);
}

/* ------------------------------------------------------------------------- */
/* Command                                                                   */
/* ------------------------------------------------------------------------- */

/* Everything that can refuse the run (the device, the frame, the graph dump)
 * comes before the earlier result in --out is removed (manifest m). */
/* The middle frame's g, h and f (those the mode computed) as colour
 * previews with a legend, for people (engine/figure): g on its own range,
 * h and f on one shared scale. */
static vg_status write_previews(const char *dir, long n, const frame_outputs *fo, uint32_t w, uint32_t h)
{
    const float *maps[3] = {fo->g, fo->h, fo->f};
    size_t px = (size_t)w * h;
    float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int m = 0; m < 3; m++)
        for (size_t i = 0; maps[m] && i < px; i++)
            if (isfinite(maps[m][i])) {
                lo[m > 0] = fminf(lo[m > 0], maps[m][i]);
                hi[m > 0] = fmaxf(hi[m > 0], maps[m][i]);
            }
    vg_status st = VG_OK;
    for (int m = 0; m < 3 && st == VG_OK; m++) {
        if (!maps[m])
            continue;
        char name[32], path[4096], title[64];
        snprintf(name, sizeof name, "preview_%c.png", "ghf"[m]);
        snprintf(title, sizeof title, "%c, frame %ld: vergence", "ghf"[m], n);
        st = vg_path_join(path, sizeof path, dir, name);
        if (st == VG_OK)
            st = figure_map_png(path, maps[m], (int)w, (int)h, 1, lo[m > 0], hi[m > 0],
                                &(figure_legend){.title = title, .unit = "arcmin"});
    }
    return st;
}

static vg_status capture(gpu *g, const scene *s, const vgx_curve_data *curve, vg_manifest *m)
{
    frame_desc fd = {
        .width = (uint32_t)o.size[0], .height = (uint32_t)o.size[1], .fps = o.fps,
        .keyframe_stride = o.stride, .camera = o.camera, .readback = true,
        .stereo = (frame_stereo)o.stereo, .mode = (frame_mode)o.mode,
        .compose = (frame_compose)o.compose, .swap_eyes = o.swap_eyes, .tess_px = o.tess_px,
        .tess_error = o.tess_error, .diffuse = o.diffuse,
        .reference = !o.no_reference && o.stereo != FRAME_STEREO_CAMERAS,
        .measure = true,
        .curve = curve,
        .op = (disp_operator_kind)o.op, .target_range = o.target_range,
        .solver_iterations = o.solver_iterations, .temporal_depth_only = o.occlusion == 1,
        .look_ahead = (frame_look_ahead)o.look_ahead, .saliency = (frame_saliency)o.saliency,
        .overlay = o.caption != NULL,
        .display = display_cli_desc(&o.display),
        /* The game's grid for its ball (game_grid_stride). */
        .coarse_stride = o.throw_no >= 0 ? game_grid_stride(&ball_aim, (uint32_t)o.size[1]) : 0,
    };
    frame *f;
    vg_status st = frame_create(g, s, &fd, &f);
    if (st != VG_OK)
        return st;
    if (o.caption) {
        frame_hud hud = {.visible = true, .line_count = 1, .parallax = (float)o.caption_parallax};
        snprintf(hud.lines[0], sizeof hud.lines[0], "%s", o.caption);
        st = frame_set_hud(f, &hud);
    }
    if (o.dump_graph) {
        rg_dump_text(frame_get_graph(f), stdout);
        st = rg_dump_dot(frame_get_graph(f), o.dump_graph);
    }
    /* The earlier capture in --out goes first (manifest, then its files). */
    if (st == VG_OK)
        st = vg_manifest_begin(m, o.out, "capture.json");
    const frame_desc *d = frame_get_desc(f);
    capture_log log = {0};
    if (st == VG_OK)
        st = capture_log_begin(&log, f, &(capture_log_desc){.frames = o.frames, .science = true,
                                                            .warp = d->stereo != FRAME_STEREO_OFF});
    long first = lround(o.time * o.fps);
    /* --throw: the window holds the keyframe before the launch (the ball
     * resting at its start), as the game's does; not a captured frame. */
    uint32_t *ball_ids = NULL;
    ball_fig = (ball_figures){0};
    if (st == VG_OK && o.throw_no >= 0) {
        if (!(ball_ids = observer_node_ids(s, ball.node)))
            st = VG_ERR_NOMEM;
        else if (first >= d->keyframe_stride)
            st = frame_render(f, first - d->keyframe_stride);
    }
    for (int i = 0; i < o.frames && st == VG_OK; i++) {
        vg_progress("capture", i, o.frames);
        if ((st = capture_log_render(&log, f, first + i)) == VG_OK)
            st = write_frame(o.out, i, frame_get_outputs(f), d->width, d->height);
        if (st == VG_OK && ball_ids)
            ball_figures_add(&ball_fig, f, &ball.th, ball.t_launch, ball_ids);
        if (st == VG_OK && i == o.frames / 2)
            st = write_previews(o.out, first + i, frame_get_outputs(f), d->width, d->height);
    }
    const frame_outputs *fo = frame_get_outputs(f);
    if (st == VG_OK && ball_ids && !(fo->g && fo->h && fo->f))
        vg_info("capture: --throw: the ball flies, but its figures need the maps g, h and f, which this stereo "
                "render does not make: capture.json has no \"ball\"");
    free(ball_ids);
    if (ball_fig.keys)
        ball_figures_finish(&ball_fig, d->keyframe_stride / d->fps, d->fps);
    if (st == VG_OK) {
        vg_progress("capture", o.frames, o.frames);
        st = capture_log_finish(&log);
        if (st == VG_OK)
            st = write_json(m, s, g, d, &log);
        const science_metrics_result *m = &log.result;
        if (st == VG_OK && log.science && m->h.moving_measured > 0 && m->h.mid_distortion_jnd > 0)
            vg_info("MID distortion h %.2f JND, f %.2f JND (%.3f of h's) over %d moving samples of %d keyframes; "
                    "f outside the range at %g of the pixels",
                    m->h.mid_distortion_jnd, m->f.mid_distortion_jnd, m->f.mid_distortion_jnd / m->h.mid_distortion_jnd,
                    m->f.moving_measured, m->keyframes, m->f_range_violation);
        if (st == VG_OK && ball_fig.keys >= 3)
            vg_info("the ball: MID distortion h %.2f JND, f %.2f JND (%.3f of h's) over %d keyframes of its flight; "
                    "f - h up to %.2f arcmin; %d grid samples on it at least", ball_fig.h_jnd, ball_fig.f_jnd,
                    ball_fig.h_jnd > 0 ? ball_fig.f_jnd / ball_fig.h_jnd : NAN, ball_fig.keys,
                    ball_fig.max_f_minus_h, ball_fig.min_samples);
        if (st == VG_OK && ball_fig.frames >= 3)
            vg_info("the ball at the frame rate: MID distortion h %.2f JND, f %.2f JND (%.3f of h's) over %d frames",
                    ball_fig.h_frame_jnd, ball_fig.f_frame_jnd,
                    ball_fig.h_frame_jnd > 0 ? ball_fig.f_frame_jnd / ball_fig.h_frame_jnd : NAN, ball_fig.frames);
    }
    capture_log_free(&log);
    frame_destroy(f);
    return st;
}

static int run(int argc, char **argv)
{
    bool help;
    if (vg_cli_parse(&vg_cmd_capture, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    if (vg_cli_require(&vg_cmd_capture, "--scene", o.scene) || vg_cli_require(&vg_cmd_capture, "--out", o.out))
        return 2;
    vg_status dst = display_cli_load(&o.display);
    if (dst != VG_OK)
        return vg_status_exit_code(dst);
    if (o.caption && (o.stereo == FRAME_STEREO_OFF || strlen(o.caption) >= FRAME_HUD_LINE)) {
        vg_error("--caption: %s", o.stereo == FRAME_STEREO_OFF ? "is drawn into the eyes: it needs a stereo render"
                                                                : "longer than 95 characters");
        return 2;
    }
    char why[256];
    if (o.stereo != FRAME_STEREO_OFF && !frame_size_ok((uint32_t)o.size[0], (uint32_t)o.size[1], why, sizeof why)) {
        vg_error("--size %dx%d: %s", o.size[0], o.size[1], why);
        return 2;
    }
    scene *s;
    vg_status st = scene_load(o.scene, &s);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    int cameras = scene_camera_count(s);
    if (o.camera >= (cameras > 0 ? cameras : 1)) {
        if (cameras)
            vg_error("--camera %d: %s has %d camera node%s (0 to %d)", o.camera, o.scene, cameras,
                     cameras == 1 ? "" : "s", cameras - 1);
        else
            vg_error("--camera %d: %s has no camera node (0 is the automatic camera)", o.camera, o.scene);
        scene_destroy(s);
        return 2;
    }
    /* An orthographic view has no stereo rig to derive g from: refused, not
     * rendered as zeros (docs/scene.md "Cameras"). */
    if (o.stereo != FRAME_STEREO_OFF && scene_camera_orthographic(s, o.camera)) {
        int node = scene_camera_node(s, o.camera);
        vg_error("%s: camera %d (node %d%s%s) is orthographic: stereo needs a perspective camera; choose another "
                 "--camera, or --stereo-render off for the G-buffer alone", o.scene, o.camera, node,
                 s->nodes[node].name[0] ? ", " : "", s->nodes[node].name);
        scene_destroy(s);
        return vg_status_exit_code(VG_ERR_FORMAT);
    }
    /* --throw: the ball flies as in the game, from the first frame (its pose
     * hook answers every time the frame asks, the keyframes ahead too). */
    if (o.throw_no >= 0) {
        if (!game_ball_attach(s, &ball, &ball_aim)) {
            vg_error("--throw: %s has no node named 'ball' (see docs/content.md)", o.scene);
            scene_destroy(s);
            return 2;
        }
        ball.t_launch = lround(o.time * o.fps) / o.fps;
        game_throw_free_play(1, o.throw_no, GAME_VISIBLE_S, &ball_aim, &ball.th);
    }
    /* Nothing it writes or removes may be one of its inputs. */
    vg_inputs in = {0};
    for (int i = 0; i < s->file_count && st == VG_OK; i++)
        st = vg_inputs_add(&in, "--scene", s->files[i]);
    if (st == VG_OK && o.curve)
        st = vg_inputs_add(&in, "--curve", o.curve);
    if (st == VG_OK && o.dump_graph)
        st = vg_inputs_check(&in, "--dump-graph", o.dump_graph);
    if (st == VG_OK)
        st = vg_inputs_check_dir(&in, "--out", o.out, "capture.json", capture_json_writes);
    vg_inputs_free(&in);
    vgx_curve_data baked;
    if (st == VG_OK && o.curve)
        st = disp_curve_read(o.curve, &baked);
    vg_manifest man = {0};
    gpu *g = NULL;
    if (st == VG_OK && (st = gpu_cli_open(&o.gpu, false, &g)) != VG_OK)
        g = NULL;
    if (st == VG_OK)
        st = capture(g, s, o.curve ? &baked : NULL, &man);
    vg_manifest_end(&man);
    int code = g ? gpu_cli_close(g, st) : vg_status_exit_code(st);
    scene_destroy(s);
    if (code == 0)
        vg_info("captured %d frame(s) of %s into %s", o.frames, o.scene, o.out);
    return code;
}

const vg_cmd vg_cmd_capture = {
    .name = "capture",
    .summary = "render frames headless and write colour, depth, ids, saliency and motion",
    .usage = "vergence capture --scene FILE --out DIR [--frames N] [--time T0] [--fps HZ] [--size WxH]",
    .details = "Writes frame_NNNN_{color,saliency,ids}.png, frame_NNNN_depth.pfm and\n"
               "frame_NNNN_motion_{prev,next}.flo per frame (stereo: also the eyes and\n"
               "frame_NNNN_{g,h,f}.pfm, vergence in arcmin), then capture.json (scene, camera,\n"
               "display model, per-pass GPU ms, and the MID metrics of h and f). Fixed time\n"
               "step: two runs write identical frame files. See docs/formats.md.",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
