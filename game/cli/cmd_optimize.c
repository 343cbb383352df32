/* vergence optimize — the motion-in-depth optimisation of disparity videos
 * from files (paper Sec. 4; pipeline in engine/offline/offline.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "commands.h"
#include "core/io.h"
#include "core/json_read.h"
#include "core/log.h"
#include "offline/offline.h"
#include "frame/frame_desc.h"
#include "options/display_cli.h"

static const char *const g_solvers[] = {"gauss-newton", "descent", NULL};
static const char *const g_presets[] = {"comfort", "study", NULL};
static const char *const g_units[] = {"arcmin", "px", NULL};
static const char *const g_flow_to[] = {"frame", "keyframe", NULL};
static const char *const g_views[] = {"auto", "centre", "left", NULL};
static const char *const g_edge_norms[] = {"range", "arcmin", "pixel", NULL};
static const char *const g_velocity_units[] = {"second", "keyframe", NULL};
static const char *const g_stereo_layouts[] = {"full-sbs", "half-sbs", "full-tb", "half-tb", NULL};
static const char *const g_flow_sources[] = {"auto", "given", "computed", "none", NULL}; /* offline_flow's order */
static const char *const g_flow_presets[] = {"fine", "medium", "fast", "ultrafast", NULL}; /* flow_preset's order */

static struct {
    const char *g, *h, *op, *depth, *flow_next, *flow_prev, *saliency, *ids, *image, *out, *frames, *weights, *capture,
        *video, *rig, *cuts, *depth_video;
    int stride, coarse, row, iterations, cg, threads, solver, preset, units, flow_to, view, look_ahead, edge_norm,
        velocity_unit, stereo_layout, flow, flow_preset;
    bool no_video, uniform_saliency, mkv, depth_inverse;
    double fps, range, px_zero, occlusion, depth_scale, cut_threshold, ema_decay;
    int ema_window;
    display_cli display;
} o;

static const vg_opt g_opts[] = {
    {.name = "--capture", .kind = VG_OPT_STRING, .dest = &o.capture, .metavar = "DIR", .help = "a folder from 'vergence capture': its g, h, depth, ids, flows to the keyframes, colour image (a new pair), frames, stride, fps, display and range (flags override)"},
    {.name = "--g", .kind = VG_OPT_STRING, .dest = &o.g, .metavar = "PATTERN", .help = "original disparity g, PFM (or KITTI/Sintel PNG) per frame, e.g. 'in/g_%04d.pfm' (or g from --depth, or --capture)"},
    {.name = "--frames", .kind = VG_OPT_STRING, .dest = &o.frames, .metavar = "A:B", .help = "first and last frame number, inclusive (required with --g)"},
    {.name = "--out", .kind = VG_OPT_STRING, .dest = &o.out, .metavar = "DIR", .help = "output folder: f_%04d.pfm, xt_{g,h,f}.png, preview_{g,h,f}.png, {g,h,f}.mp4 (with ffmpeg), with --image left_/right_%04d.png and the pair's video (--stereo-layout), metrics.json (required)"},
    {.name = "--h", .kind = VG_OPT_STRING, .dest = &o.h, .metavar = "PATTERN", .help = "manipulated disparity h, PFM arcmin (instead of --operator)"},
    {.name = "--operator", .kind = VG_OPT_STRING, .dest = &o.op, .metavar = "NAME", .help = "h = M(g): none, linear, lang (default), lang-smoothed, or ema (the stereo converters' baseline, nunif's iw3: g's range over the next --ema-window frames, smoothed, mapped linearly)"},
    {.name = "--ema-decay", .kind = VG_OPT_FLOAT, .dest = &o.ema_decay, .metavar = "D", .help = "with --operator ema: the moving average's decay per frame (default 0.9, iw3's WindowEMAScaler)", .min = 0.0001, .max = 0.9999},
    {.name = "--ema-window", .kind = VG_OPT_INT, .dest = &o.ema_window, .metavar = "N", .help = "with --operator ema: frames of look-ahead whose range is taken (default 30)", .min = 1, .max = 100000},
    {.name = "--preset", .kind = VG_OPT_CHOICE, .dest = &o.preset, .metavar = "NAME", .help = "operator strength: comfort (+-60 arcmin) or study (+-30)", .choices = g_presets},
    {.name = "--depth", .kind = VG_OPT_STRING, .dest = &o.depth, .metavar = "PATTERN", .help = "linear depth per frame, PFM metres or 16-bit grey PNG (0 = unknown) with --depth-scale; without --g, g is the display's vergence of it through --rig (default: depth from g)"},
    {.name = "--depth-video", .kind = VG_OPT_STRING, .dest = &o.depth_video, .metavar = "FILE", .help = "instead of --depth: a grey video of depth (any file ffmpeg reads), read as 16-bit PNGs with --depth-scale (an 8-bit video's value v as 257 v)"},
    {.name = "--depth-scale", .kind = VG_OPT_FLOAT, .dest = &o.depth_scale, .metavar = "S", .help = "metres per depth unit (0.001: millimetres; needed for PNG depth; default 1)", .min = 1e-9, .max = 1e9},
    {.name = "--depth-inverse", .kind = VG_OPT_FLAG, .dest = &o.depth_inverse, .help = "depth files hold inverse depth (as monocular estimators write it): metres = 1 / (value * --depth-scale)"},
    {.name = "--rig", .kind = VG_OPT_STRING, .dest = &o.rig, .metavar = "B,C,FOV", .help = "g from --depth: interaxial B and convergence C in metres, horizontal field of view in degrees (default 0,0,0: the display's eye separation, viewing distance and angle, ortho-stereo)"},
    {.name = "--flow-next", .kind = VG_OPT_STRING, .dest = &o.flow_next, .metavar = "PATTERN", .help = "per-frame .flo flow to the next frame"},
    {.name = "--flow-prev", .kind = VG_OPT_STRING, .dest = &o.flow_prev, .metavar = "PATTERN", .help = "per-frame .flo flow to the previous frame"},
    {.name = "--image", .kind = VG_OPT_STRING, .dest = &o.image, .metavar = "PATTERN", .help = "8-bit RGB PNG of the view g belongs to: a new stereo pair from f, left_/right_%04d.png (and its video, --stereo-layout)"},
    {.name = "--video", .kind = VG_OPT_STRING, .dest = &o.video, .metavar = "FILE", .help = "instead of --image: a colour video (any file ffmpeg reads), its frames --frames A:B counted from 0"},
    {.name = "--scene-cuts", .kind = VG_OPT_STRING, .dest = &o.cuts, .metavar = "HOW", .help = "where the window restarts: auto (default: found in the colour frames of --image or --video), none, or the first frames of new shots, N,N,..."},
    {.name = "--cut-threshold", .kind = VG_OPT_FLOAT, .dest = &o.cut_threshold, .metavar = "D", .help = "with --scene-cuts auto: the colour histogram distance of consecutive frames (0 to 1) above which they are cut apart (default 0.3)", .min = 0.01, .max = 1},
    {.name = "--image-view", .kind = VG_OPT_CHOICE, .dest = &o.view, .metavar = "V", .help = "where --image was taken: centre (the engine's) or left (datasets); auto: left for pixel disparities", .choices = g_views},
    {.name = "--flow", .kind = VG_OPT_CHOICE, .dest = &o.flow, .metavar = "FROM", .help = "where the per-frame flows come from: given (--flow-next/--flow-prev, or the capture's), computed (DIS optical flow between consecutive --image frames, checked forward against backward), none (a static scene); auto (default): given if named, else computed if --image, else none", .choices = g_flow_sources},
    {.name = "--flow-preset", .kind = VG_OPT_CHOICE, .dest = &o.flow_preset, .metavar = "P", .help = "with --flow computed: fine (default: DIS's medium down to full resolution), or DIS's own medium, fast or ultrafast (faster, coarser)", .choices = g_flow_presets},
    {.name = "--flow-to", .kind = VG_OPT_CHOICE, .dest = &o.flow_to, .metavar = "TO", .help = "given flows go to the next/previous frame (default) or keyframe (as capture writes them); computed flows go to the keyframes (default) or, chained, frame to frame", .choices = g_flow_to},
    {.name = "--ids", .kind = VG_OPT_STRING, .dest = &o.ids, .metavar = "PATTERN", .help = "instance ids, 24-bit RGB PNG as capture writes them (links stay on one object)"},
    {.name = "--saliency", .kind = VG_OPT_STRING, .dest = &o.saliency, .metavar = "PATTERN", .help = "8-bit grey PNG saliency for the operator (default: computed from --image, the flows and depth)"},
    {.name = "--uniform-saliency", .kind = VG_OPT_FLAG, .dest = &o.uniform_saliency, .help = "without --saliency: every pixel weighs alike (no computed saliency)"},
    {.name = "--g-units", .kind = VG_OPT_CHOICE, .dest = &o.units, .metavar = "U", .help = "units of g: arcmin (vergence) or px (dataset disparity x_l - x_r)", .choices = g_units},
    {.name = "--px-zero", .kind = VG_OPT_FLOAT, .dest = &o.px_zero, .metavar = "D", .help = "with --g-units px: the disparity that lands on the screen (default 0)"},
    {.name = "--keyframe-stride", .kind = VG_OPT_INT, .dest = &o.stride, .metavar = "N", .help = "frames between keyframes (default 10)", .min = 1, .max = 1000},
    {.name = "--coarse", .kind = VG_OPT_INT, .dest = &o.coarse, .metavar = "N", .help = "pixels per coarse solver sample (default 5)", .min = 1, .max = 64},
    {.name = "--fps", .kind = VG_OPT_FLOAT, .dest = &o.fps, .metavar = "F", .help = "frame rate (default 60)", .min = 1, .max = 1000},
    {.name = "--row", .kind = VG_OPT_INT, .dest = &o.row, .metavar = "Y", .help = "row of the x-t slices (default: the middle)", .min = 0, .max = 100000},
    {.name = "--target-range", .kind = VG_OPT_FLOAT, .dest = &o.range, .metavar = "ARCMIN", .help = "half-width of the target range around the screen (default 60)", .min = 1, .max = 1000},
    {.name = "--weights", .kind = VG_OPT_STRING, .dest = &o.weights, .metavar = "M,S,T,A", .help = "cost weights (default 0.05,1,0.1,0.1)"},
    {.name = "--solver", .kind = VG_OPT_CHOICE, .dest = &o.solver, .metavar = "NAME", .help = "minimiser", .choices = g_solvers},
    {.name = "--look-ahead", .kind = VG_OPT_CHOICE, .dest = &o.look_ahead, .metavar = "HOW", .help = "foresight (default): one window over the whole sequence; causal: the engine's sliding window, its future keyframes predicted from the past (docs/method.md)", .choices = frame_look_ahead_names},
    {.name = "--edge-norm", .kind = VG_OPT_CHOICE, .dest = &o.edge_norm, .metavar = "N", .help = "sensitivity study: the spatial weights exp(-10 |dh|) with dh over the target range (default), in arcmin per coarse sample, or per pixel", .choices = g_edge_norms},
    {.name = "--velocity-unit", .kind = VG_OPT_CHOICE, .dest = &o.velocity_unit, .metavar = "U", .help = "sensitivity study: the velocities the perceptual model sees, per second (default) or per keyframe interval", .choices = g_velocity_units},
    {.name = "--iterations", .kind = VG_OPT_INT, .dest = &o.iterations, .metavar = "N", .help = "outer iterations (default 4 gauss-newton, 8 descent)", .min = 1, .max = 100000},
    {.name = "--cg-iterations", .kind = VG_OPT_INT, .dest = &o.cg, .metavar = "N", .help = "CG steps per Gauss-Newton iteration (default 8)", .min = 1, .max = 100000},
    {.name = "--threads", .kind = VG_OPT_INT, .dest = &o.threads, .metavar = "N", .help = "worker threads (default: all cores)", .min = 0, .max = 1024},
    {.name = "--occlusion-tolerance", .kind = VG_OPT_FLOAT, .dest = &o.occlusion, .metavar = "R", .help = "relative depth difference of one surface (default 0.2)", .min = 0.001, .max = 10},
    {.name = "--no-video", .kind = VG_OPT_FLAG, .dest = &o.no_video, .help = "no g.mp4, h.mp4, f.mp4 even when ffmpeg is installed"},
    {.name = "--stereo-layout", .kind = VG_OPT_CHOICE, .dest = &o.stereo_layout, .metavar = "L", .help = "with --image, the new pair's video: full-sbs (default, stereo_LRF_Full_SBS.mp4), half-sbs (stereo_LR.mp4), full-tb (stereo_TBF_fulltb.mp4) or half-tb (stereo_TB.mp4); H.264 frame-packing SEI in each", .choices = g_stereo_layouts},
    {.name = "--mkv", .kind = VG_OPT_FLAG, .dest = &o.mkv, .help = "with --image, the pair's video as Matroska too, its StereoMode set"},
    DISPLAY_CLI_OPTIONS(o.display),
};

const vg_cmd vg_cmd_optimize;

static int fail(vg_status st)
{
    return vg_status_exit_code(st == VG_OK ? VG_ERR_ARG : st);
}

static bool parse_frames(const char *text, int *first, int *last)
{
    char *end;
    long a = strtol(text, &end, 10);
    if (end == text || *end != ':')
        return false;
    const char *b_text = end + 1;
    long b = strtol(b_text, &end, 10);
    if (end == b_text || *end || a < 0 || b < a || b > 100000000)
        return false;
    *first = (int)a;
    *last = (int)b;
    return true;
}

static bool parse_weights(const char *text, mid_weights *w)
{
    float v[4];
    char tail;
    if (sscanf(text, "%f,%f,%f,%f%c", &v[0], &v[1], &v[2], &v[3], &tail) != 4)
        return false;
    for (int i = 0; i < 4; i++)
        if (!(v[i] >= 0.0f && v[i] < 1e6f))
            return false;
    *w = (mid_weights){v[0], v[1], v[2], v[3]};
    return v[0] > 0.0f; /* the data term keeps the problem well posed */
}

/* `--capture DIR`: what a capture folder holds, for the options not given.
 * g, depth, ids, the flows to the keyframes and the centre image (a new
 * pair) always; h (the engine's own) when the capture's mode computed it,
 * else the saliency for the operator;
 * frames from the first keyframe to the last; stride, fps, the display and
 * the target range from capture.json. */
static vg_status from_capture(offline_desc *d, char *frames_buf, size_t cap, char pat[8][4096], char *display)
{
    char path[4096];
    vg_jdoc doc = {0};
    vg_status st = vg_path_join(path, sizeof path, o.capture, "capture.json");
    if (st == VG_OK && access(path, R_OK) != 0) {
        vg_error("optimize: --capture %s: no capture.json (not a capture folder, or an incomplete capture)", o.capture);
        st = VG_ERR_IO;
    }
    if (st == VG_OK)
        st = vg_json_read_file(path, &doc);
    if (st != VG_OK)
        return st;
    const vg_jvalue *r = doc.root;
    /* The capture's flows (to its keyframes) unless others, or none, are asked for. */
    bool capture_flows = o.flow_to < 0 && !o.flow_next && !o.flow_prev && !o.stride &&
                         (o.flow == OFFLINE_FLOW_AUTO || o.flow == OFFLINE_FLOW_GIVEN);
    int count = (int)vg_jnum(r, "frames", 0), first_index = (int)vg_jnum(r, "first_frame", 0);
    int stride = (int)vg_jnum(r, "keyframe_stride", 0);
    if (count < 1 || stride < 1 || first_index < 0) {
        vg_error("%s: no frames, first_frame or keyframe_stride", path);
        vg_jdoc_free(&doc);
        return VG_ERR_FORMAT;
    }
    /* File numbers from 0; the engine's keyframes are the multiples of the stride. */
    int first = (stride - first_index % stride) % stride, last = first + (count - 1 - first) / stride * stride;
    if (!o.frames) {
        if (first > count - 1) {
            vg_error("%s: %d frames from frame %d hold no keyframe (stride %d)", path, count, first_index, stride);
            vg_jdoc_free(&doc);
            return VG_ERR_FORMAT;
        }
        snprintf(frames_buf, cap, "%d:%d", first, last);
        o.frames = frames_buf;
        if (first > 0 || last < count - 1)
            vg_info("optimize: --capture %s: frames %d:%d, from its first keyframe to its last", o.capture, first, last);
    } else if (capture_flows && atoi(o.frames) % stride != first % stride) {
        /* The capture's flows go to its keyframes: the range must start on one. */
        vg_error("optimize: --frames %s: with --capture %s the first frame must be a keyframe (%d + a multiple of %d)",
                 o.frames, o.capture, first, stride);
        vg_jdoc_free(&doc);
        return VG_ERR_ARG;
    }
    if (!o.stride)
        d->keyframe_stride = stride;
    if (!(o.fps > 0))
        d->fps = vg_jnum(r, "fps", 60);
    if (!o.coarse)
        d->coarse = (int)vg_jnum(r, "metrics.coarse_stride", 0);
    double lo = vg_jnum(r, "metrics.range_lo", 0), hi = vg_jnum(r, "metrics.range_hi", 0);
    if (!(o.range > 0) && hi > lo)
        d->target_range = 0.5 * (hi - lo);
    vg_jdoc_free(&doc);
    if (!o.display.file)
        o.display.file = strcpy(display, path);
    /* The file patterns, named as capture writes them. */
    static const char *const names[7] = {"g.pfm", "depth.pfm", "ids.png", "motion_next.flo", "motion_prev.flo",
                                         "color.png", "h.pfm"};
    const char **dest[7] = {&d->g, &d->depth, &d->ids, &d->flow_next, &d->flow_prev, &d->image, &d->h};
    for (int k = 0; k < 7; k++) {
        char name[64];
        snprintf(name, sizeof name, "frame_%%04d_%s", names[k]);
        if ((st = vg_path_join(pat[k], 4096, o.capture, name)) != VG_OK)
            return st;
        if (*dest[k] || ((k == 3 || k == 4) && o.flow != OFFLINE_FLOW_AUTO && o.flow != OFFLINE_FLOW_GIVEN))
            continue;
        if (k == 6) { /* h when the capture computed it, else the operator (with the saliency) */
            snprintf(name, sizeof name, "frame_%04d_h.pfm", first);
            if ((st = vg_path_join(path, sizeof path, o.capture, name)) != VG_OK)
                return st;
            if (access(path, R_OK) != 0 || o.op)
                continue;
        }
        *dest[k] = pat[k];
    }
    if (!d->h && !d->saliency) {
        if ((st = vg_path_join(pat[7], 4096, o.capture, "frame_%04d_saliency.png")) != VG_OK)
            return st;
        d->saliency = pat[7];
    }
    if (o.flow_to < 0 && !o.flow_next && !o.flow_prev && (o.flow == OFFLINE_FLOW_AUTO || o.flow == OFFLINE_FLOW_GIVEN))
        d->flow_to_keyframe = true;
    return VG_OK;
}

/* --rig B,C,FOV: each >= 0 (0 = the display's). */
static bool parse_rig(const char *text, stereo_camera_desc *rig)
{
    double v[3];
    char tail;
    if (sscanf(text, "%lf,%lf,%lf%c", &v[0], &v[1], &v[2], &tail) != 3)
        return false;
    for (int i = 0; i < 3; i++)
        if (!(v[i] >= 0 && v[i] < 1e6))
            return false;
    *rig = (stereo_camera_desc){.interaxial_m = v[0], .convergence_m = v[1], .hfov_deg = v[2]};
    return v[2] < 180;
}

/* --scene-cuts auto | none | N,N,... (at most 4096 cuts). */
static bool parse_cuts(const char *text, offline_desc *d, int *frames, int cap)
{
    if (!strcmp(text, "auto") || !strcmp(text, "none")) {
        d->scene_cuts = !strcmp(text, "auto") ? OFFLINE_CUTS_AUTO : OFFLINE_CUTS_NONE;
        return true;
    }
    int n = 0;
    for (const char *p = text; *p;) {
        char *end;
        long v = strtol(p, &end, 10);
        if (end == p || v < 0 || v > 100000000 || n == cap || (*end && *end != ','))
            return false;
        frames[n++] = (int)v;
        p = *end ? end + 1 : end;
        if (*end && !*p)
            return false;
    }
    d->scene_cuts = OFFLINE_CUTS_GIVEN;
    d->cut_frames = frames;
    d->cut_count = n;
    return n > 0;
}

static int run(int argc, char **argv)
{
    memset(&o, 0, sizeof o);
    o.row = -1;
    o.flow_to = -1; /* unset: frame, or keyframe with --capture */
    bool help;
    display_cli_renames("optimize", argc, argv);
    vg_status st = vg_cli_parse(&vg_cmd_optimize, argc, argv, &help);
    if (st != VG_OK || help)
        return help ? 0 : fail(st);
    offline_desc d = {
        .g = o.g, .h = o.h, .depth = o.depth, .flow_next = o.flow_next, .flow_prev = o.flow_prev,
        .saliency = o.saliency, .ids = o.ids, .image = o.image, .image_view = (offline_view)o.view, .flow_to_keyframe = o.flow_to == 1, .flow_to_frame = o.flow_to == 0,
        .out_dir = o.out, .keyframe_stride = o.stride, .coarse = o.coarse,
        .fps = o.fps, .row = o.row, .preset = (disp_operator_preset)o.preset, .target_range = o.range,
        .solver = o.solver == 1 ? MID_SOLVER_DESCENT : MID_SOLVER_GAUSS_NEWTON,
        .iterations = o.iterations, .cg_iterations = o.cg, .threads = o.threads,
        .g_units = o.units == 1 ? DISP_G_PX : DISP_G_ARCMIN, .px_zero = o.px_zero,
        .occlusion_tolerance = (float)o.occlusion, .video = !o.no_video,
        .stereo_layout = (offline_stereo_layout)o.stereo_layout, .stereo_mkv = o.mkv,
        .causal = o.look_ahead == FRAME_LOOK_AHEAD_CAUSAL, .uniform_saliency = o.uniform_saliency,
        .edge_norm = (offline_edge_norm)o.edge_norm, .velocity_per_keyframe = o.velocity_unit == 1,
        .flow = (offline_flow)o.flow, .flow_preset = (flow_preset)o.flow_preset,
        .video_in = o.video, .depth_video = o.depth_video, .depth_scale = o.depth_scale, .depth_inverse = o.depth_inverse,
    };
    static char frames_buf[32], patterns[8][4096], display[4096];
    if (o.capture && o.g) {
        vg_error("optimize: give --capture DIR or --g PATTERN, not both");
        return fail(VG_ERR_ARG);
    }
    if (o.capture && (st = from_capture(&d, frames_buf, sizeof frames_buf, patterns, display)) != VG_OK)
        return fail(st);
    if ((st = display_cli_load(&o.display)) != VG_OK)
        return fail(st);
    d.display = display_cli_desc(&o.display);
    if (!o.capture && !o.g && !o.depth && !o.depth_video) {
        vg_error("optimize: --g PATTERN (or --depth PATTERN, g from depth) is required (see 'vergence optimize --help')");
        return fail(VG_ERR_ARG);
    }
    if (o.rig && !parse_rig(o.rig, &d.rig)) {
        vg_error("optimize: --rig '%s' is not B,C,FOV: interaxial and convergence in metres, field of view in "
                 "degrees below 180, each >= 0 (0: the display's)", o.rig);
        return fail(VG_ERR_ARG);
    }
    if (o.rig && (o.g || o.capture)) {
        vg_error("optimize: --rig makes g from --depth: it is not used with --g or --capture");
        return fail(VG_ERR_ARG);
    }
    static int cut_frames[4096];
    if (o.cuts && !parse_cuts(o.cuts, &d, cut_frames, 4096)) {
        vg_error("optimize: --scene-cuts '%s' is not auto, none or frame numbers N,N,... (the first frame of each "
                 "new shot)", o.cuts);
        return fail(VG_ERR_ARG);
    }
    d.cut_threshold = o.cut_threshold;
    if (o.capture && !o.cuts) /* one shot, and its flows go to its keyframes */
        d.scene_cuts = OFFLINE_CUTS_NONE;
    if ((o.video || o.depth_video) && o.capture) {
        vg_error("optimize: %s with --capture: the capture has its %s", o.video ? "--video" : "--depth-video",
                 o.video ? "colour frames" : "depth");
        return fail(VG_ERR_ARG);
    }
    if (vg_cli_require(&vg_cmd_optimize, "--frames", o.frames) != VG_OK ||
        vg_cli_require(&vg_cmd_optimize, "--out", o.out) != VG_OK)
        return fail(VG_ERR_ARG);
    if (!parse_frames(o.frames, &d.first, &d.last)) {
        vg_error("optimize: --frames '%s' is not A:B with 0 <= A <= B", o.frames);
        return fail(VG_ERR_ARG);
    }
    if (o.h && o.op) {
        vg_error("optimize: give either --h or --operator, not both");
        return fail(VG_ERR_ARG);
    }
    d.ema = o.op && !strcmp(o.op, "ema");
    d.op = d.ema ? DISP_OPERATOR_LINEAR : o.op ? disp_operator_kind_parse(o.op) : DISP_OPERATOR_LANG;
    if (o.op && d.op == DISP_OPERATOR_DEFAULT) {
        vg_error("optimize: --operator '%s' is not one of: none, linear, lang, lang-smoothed, ema", o.op);
        return fail(VG_ERR_ARG);
    }
    if ((o.ema_decay > 0 || o.ema_window > 0) && !d.ema) {
        vg_error("optimize: --ema-decay and --ema-window go with --operator ema");
        return fail(VG_ERR_ARG);
    }
    d.ema_decay = o.ema_decay;
    d.ema_window = o.ema_window;
    if (o.weights && !parse_weights(o.weights, &d.weights)) {
        vg_error("optimize: --weights '%s' is not four numbers M,S,T,A >= 0 with M > 0", o.weights);
        return fail(VG_ERR_ARG);
    }
    st = offline_run(&d);
    return st == VG_OK ? 0 : fail(st);
}

const vg_cmd vg_cmd_optimize = {
    .name = "optimize",
    .summary = "optimise disparity videos for motion in depth (Kellnhofer et al. Sec. 4)",
    .usage = "vergence optimize --g PATTERN --frames A:B --out DIR [options]\n"
             "       vergence optimize --depth PATTERN [--video FILE] --frames A:B --out DIR [options]\n"
             "       vergence optimize --capture DIR --out DIR [options]",
    .details = "Reads per-frame PFM vergence g (or dataset pixel disparity with --g-units px),\n"
               "makes h with an operator (or reads --h), solves the motion-in-depth optimisation\n"
               "on coarse keyframes and writes the upsampled f for every frame, with colour\n"
               "previews of g, h and f (the middle frame as PNG with a legend, a video of each\n"
               "with ffmpeg) and x-t slices; given the images (--image), a new stereo pair from f.\n"
               "Unknown g (inf, KITTI's 0) is left out of the costs and the metrics. --capture DIR\n"
               "takes a folder of 'vergence capture' whole. Patterns take one %d-style\n"
               "conversion, as in ffmpeg. Without flow files the flows are computed from the\n"
               "colour frames (--image; DIS optical flow, checked forward against backward),\n"
               "and without those too the scene is taken as static (--flow chooses); a missing\n"
               "flow direction is approximated by the other one negated.",
    .opts = g_opts,
    .opt_count = (int)(sizeof g_opts / sizeof g_opts[0]),
    .run = run,
};
