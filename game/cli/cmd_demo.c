/* vergence demo — the main job without a display: renders the paper's
 * scenes in the three modes (original g, manipulated h, optimized f) and
 * writes a report, DIR/index.html, with everything computed in this run:
 *
 *   DIR/index.html                       the report (figures, captions, tables)
 *   DIR/SCENE/MODE/capture.json          the figures of one scene in one mode
 *   DIR/SCENE/MODE/still_K_{sbs,anaglyph,cascade}.png, {warp,imagewarp}_K_left.png
 *   DIR/SCENE/MODE/video.mp4             when Debian's ffmpeg is installed
 *   DIR/SCENE/xt_{g,h,f}.png, tracks_{g,hf}.svg
 *
 * Modes the frame cannot render yet are left out with a note (on stderr
 * and in the report), never faked. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "commands.h"
#include "core/clock.h"
#include "core/io.h"
#include "core/log.h"
#include "figure/figure.h"
#include "core/manifest.h"
#include "demo/demo.h"
#include "scene/scene.h"
#include "options/display_cli.h"
#include "options/gpu_cli.h"

#define DEMO_MAX_SCENES 8

/* The scenes of the report, in order (content/NAME.gltf). */
#define DEMO_DEFAULT_SCENES "balloon,cubes,bird"

typedef struct demo_cli {
    const char *out, *scenes, *content;
    int op;
    int size[2], step, analysis_step, stills, stride;
    double seconds, fps, tess_error;
    bool no_video;
    gpu_cli gpu;
    display_cli display;
} demo_cli;

static demo_cli o = {
    .out = "out/demo", .scenes = DEMO_DEFAULT_SCENES, .content = "content", .size = {400, 225},
    .op = DISP_OPERATOR_LANG, .step = 2, .analysis_step = 1, .stills = 3, .stride = 5, .fps = 30, .tess_error = 0.1,
    .gpu = {.device = -1},
};

/* disp_operator_kind minus one, as on `vergence capture`. */
static const vg_opt k_opts[] = {
    {"--out", VG_OPT_STRING, &o.out, "DIR", "report folder (default out/demo; created if missing)", NULL, 0, 0},
    {"--scenes", VG_OPT_STRING, &o.scenes, "LIST", "comma-separated scene names (default " DEMO_DEFAULT_SCENES ")", NULL, 0, 0},
    {"--content", VG_OPT_STRING, &o.content, "DIR", "folder of the scenes' .gltf files (default content)", NULL, 0, 0},
    {"--size", VG_OPT_SIZE, o.size, "WxH", "image size of each eye (default 400x225)", NULL, 0, 0},
    {"--step", VG_OPT_INT, &o.step, "N", "videos and stills: every N-th frame (default 2)", NULL, 1, 100},
    {"--analysis-step", VG_OPT_INT, &o.analysis_step, "N", "the optimized run (maps, plots, metrics): every N-th frame; "
     "f is exact only with 1, the default (the solver is amortised over a keyframe interval)", NULL, 1, 100},
    {"--fps", VG_OPT_FLOAT, &o.fps, "HZ", "frame rate of the fixed time step (default 30; with the stride of 5, keyframes are 1/6 s apart as at 60 Hz)", NULL, 1, 1000},
    {"--seconds", VG_OPT_FLOAT, &o.seconds, "T", "clip length (default: each scene's animation)", NULL, 0.1, 600},
    {"--stills", VG_OPT_INT, &o.stills, "N", "stereo stills per scene and mode (default 3, at most 4)", NULL, 1, DEMO_MAX_STILLS},
    {"--keyframe-stride", VG_OPT_INT, &o.stride, "S", "frames between keyframes (default 5: 1/6 s at 30 Hz, as the paper's 10 at 60 Hz)", NULL, 1, 1000},
    {"--tess-error", VG_OPT_FLOAT, &o.tess_error, "PX", "the warp's tessellation tolerance (default 0.1: a quarter of "
     "the time of capture's 0.025 px, p99 disparity error about 0.1 px, within the 0.25 px the warp must hold)", NULL, 0.001, 100},
    {"--operator", VG_OPT_ENUM, &o.op, "NAME", "disparity operator h = M(g, saliency) (default lang)", disp_operator_names, 0, 0},
    {"--no-video", VG_OPT_FLAG, &o.no_video, NULL, "do not write videos even when ffmpeg is installed", NULL, 0, 0},
    DISPLAY_CLI_OPTIONS(o.display),
    GPU_CLI_OPTIONS(o.gpu),
};

/* ------------------------------------------------------------------------- */
/* Progress                                                                  */
/* ------------------------------------------------------------------------- */

typedef struct progress {
    int done, total;
    double start_ms;
    char label[96];
} progress;

static void progress_show(progress *p)
{
    double elapsed = (vg_now_ms() - p->start_ms) / 1000.0;
    char label[160];
    if (p->done > 0 && p->done < p->total) {
        double left = elapsed * (p->total - p->done) / p->done;
        snprintf(label, sizeof label, "demo %-24s %3.0f s, ~%3.0f s left", p->label, elapsed, left);
    } else
        snprintf(label, sizeof label, "demo %-24s %3.0f s              ", p->label, elapsed);
    vg_progress(label, p->done, p->total);
}

static void progress_add(void *user, int units)
{
    progress *p = user;
    p->done += units;
    if (p->done > p->total)
        p->done = p->total;
    progress_show(p);
}

/* ------------------------------------------------------------------------- */
/* Set-up                                                                    */
/* ------------------------------------------------------------------------- */

/* What the report writes under --out: index.html and each scene's folder. */
static char (*g_names)[DEMO_NAME];
static int g_count;

static bool demo_writes(const char *name)
{
    if (!strcmp(name, "index.html"))
        return true;
    for (int i = 0; i < g_count; i++) {
        size_t n = strlen(g_names[i]);
        if (!strncmp(name, g_names[i], n) && name[n] == '/')
            return true;
    }
    return false;
}

static int split_scenes(char names[DEMO_MAX_SCENES][DEMO_NAME])
{
    int n = 0;
    const char *p = o.scenes;
    while (*p) {
        size_t len = strcspn(p, ",");
        if (len == 0 || len >= DEMO_NAME || n == DEMO_MAX_SCENES) {
            vg_error("vergence demo: --scenes: '%s' is not a list of up to %d scene names", o.scenes,
                     DEMO_MAX_SCENES);
            return -1;
        }
        snprintf(names[n], DEMO_NAME, "%.*s", (int)len, p);
        /* A scene is content/NAME.gltf and its results go to --out/NAME: a
         * name, not a path (no '/', no "..": nothing outside --out). */
        if (strspn(names[n], "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_") != len) {
            vg_error("vergence demo: --scenes: '%s' is not a scene name (letters, digits, '-' and '_': "
                     "the name of a file content/NAME.gltf)", names[n]);
            return -1;
        }
        n++;
        p += len + (p[len] == ',');
    }
    if (n == 0)
        vg_error("vergence demo: --scenes is empty");
    return n ? n : -1;
}

/* ------------------------------------------------------------------------- */
/* Command                                                                   */
/* ------------------------------------------------------------------------- */

static vg_status demo_scene_all_modes(gpu *g, const demo_opts *d, demo_scene *sc, const char *name,
                                      const char *path, progress *pr)
{
    scene *s;
    vg_status st = scene_load(path, &s);
    if (st != VG_OK)
        return st;
    st = demo_scene_init(sc, s, name, path, d);
    /* The richest mode first: it renders every frame and records the maps. */
    bool analysed = false;
    for (int m = DEMO_MODES - 1; m >= 0 && st == VG_OK; m--) {
        snprintf(pr->label, sizeof pr->label, "%s/%s", sc->name, frame_mode_names[demo_modes[m]]);
        progress_show(pr);
        st = demo_run_scene_mode(g, s, d, sc, m, !analysed, progress_add, pr);
        analysed |= sc->runs[m].available;
    }
    if (st == VG_OK)
        st = demo_figures_write(d, sc);
    scene_destroy(s);
    return st;
}

static vg_status demo(gpu *g, const demo_opts *d, char names[DEMO_MAX_SCENES][DEMO_NAME], int count,
                      const vg_manifest *m)
{
    demo_scene *scenes = calloc((size_t)count, sizeof *scenes);
    char (*paths)[4096] = calloc((size_t)count, sizeof *paths);
    if (!scenes || !paths) {
        free(scenes);
        free(paths);
        return VG_ERR_NOMEM;
    }
    vg_status st = VG_OK;
    progress pr = {.start_ms = vg_now_ms()};
    for (int i = 0; i < count && st == VG_OK; i++) {
        char file[DEMO_MAX_SCENES * DEMO_NAME + 8];
        snprintf(file, sizeof file, "%s.gltf", names[i]);
        st = vg_path_join(paths[i], sizeof paths[i], o.content, file); /* run() found it */
    }
    /* The work is counted in rendered frames, known once each scene's clip is. */
    for (int i = 0; i < count && st == VG_OK; i++) {
        scene *s;
        if ((st = scene_load(paths[i], &s)) != VG_OK)
            break;
        demo_scene probe = {.last = demo_clip_last(d, s)};
        pr.total += demo_run_units(d, &probe, true) + (DEMO_MODES - 1) * demo_run_units(d, &probe, false);
        scene_destroy(s);
    }
    for (int i = 0; i < count && st == VG_OK; i++)
        st = demo_scene_all_modes(g, d, &scenes[i], names[i], paths[i], &pr);
    double seconds = (vg_now_ms() - pr.start_ms) / 1000.0;
    if (st == VG_OK) {
        pr.done = pr.total;
        snprintf(pr.label, sizeof pr.label, "report");
        progress_show(&pr);
        st = demo_html_write(d, scenes, count, seconds, g->props.deviceName, m);
    }
    for (int i = 0; i < count; i++)
        demo_scene_free(&scenes[i]);
    free(scenes);
    free(paths);
    return st;
}

static int run(int argc, char **argv)
{
    bool help;
    if (vg_cli_parse(&vg_cmd_demo, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    vg_status dst = display_cli_load(&o.display);
    if (dst != VG_OK)
        return vg_status_exit_code(dst);
    if (o.stride % o.analysis_step != 0 || o.step % o.analysis_step != 0) {
        vg_error("vergence demo: --analysis-step %d must divide the keyframe stride (%d) and --step (%d)",
                 o.analysis_step, o.stride, o.step);
        return 2;
    }
    char why[256];
    if (!frame_size_ok((uint32_t)o.size[0], (uint32_t)o.size[1], why, sizeof why)) {
        vg_error("--size %dx%d: %s", o.size[0], o.size[1], why);
        return 2;
    }
    char names[DEMO_MAX_SCENES][DEMO_NAME];
    int count = split_scenes(names);
    if (count < 0)
        return 2;
    char ffmpeg_buf[4096];
    demo_opts d = {
        .out = o.out, .width = o.size[0], .height = o.size[1], .step = o.step, .analysis_step = o.analysis_step,
        .fps = o.fps, .stills = o.stills,
        .seconds = o.seconds, .video = !o.no_video, .op = (disp_operator_kind)o.op, .keyframe_stride = o.stride,
        .tess_error = o.tess_error, .display = display_cli_desc(&o.display),
    };
    d.ffmpeg = d.video ? figure_find_ffmpeg(ffmpeg_buf, sizeof ffmpeg_buf) : NULL;
    if (d.video && !d.ffmpeg)
        vg_warn("demo: ffmpeg is not installed (Debian package ffmpeg): the report has stills but no videos");
    /* Nothing it writes or removes may be an input (the scenes and their files). */
    vg_inputs in = {0};
    vg_status st = VG_OK;
    g_names = names;
    g_count = count;
    for (int i = 0; i < count && st == VG_OK; i++) {
        char file[DEMO_NAME + 8], path[4096];
        snprintf(file, sizeof file, "%s.gltf", names[i]);
        st = vg_path_join(path, sizeof path, o.content, file);
        scene *s = NULL;
        if (st == VG_OK && access(path, R_OK) != 0) {
            vg_error("vergence demo: scene '%s': %s is missing (see --content, --scenes)", names[i], path);
            st = VG_ERR_IO;
        }
        if (st == VG_OK && (st = scene_load(path, &s)) == VG_OK) {
            for (int k = 0; k < s->file_count && st == VG_OK; k++)
                st = vg_inputs_add(&in, "--scenes", s->files[k]);
            scene_destroy(s);
        }
    }
    if (st == VG_OK)
        st = vg_inputs_check_dir(&in, "--out", o.out, "index.html", demo_writes);
    vg_inputs_free(&in);
    gpu *g = NULL;
    if (st == VG_OK && (st = gpu_cli_open(&o.gpu, false, &g)) != VG_OK)
        g = NULL;
    /* The earlier report in --out goes first (index.html, then its files). */
    vg_manifest man = {0};
    if (st == VG_OK)
        st = vg_manifest_begin(&man, o.out, "index.html");
    /* A dying ffmpeg must not kill the run: writes to its pipe fail instead. */
    signal(SIGPIPE, SIG_IGN);
    if (st == VG_OK)
        st = demo(g, &d, names, count, &man);
    vg_manifest_end(&man);
    int code = g ? gpu_cli_close(g, st) : vg_status_exit_code(st);
    if (code == 0) {
        char index[4096];
        vg_path_join(index, sizeof index, o.out, "index.html");
        vg_info("demo: the report is %s", index);
    }
    return code;
}

const vg_cmd vg_cmd_demo = {
    .name = "demo",
    .summary = "render the paper's scenes in every mode and write a report (index.html)",
    .usage = "vergence demo [--out DIR] [--size WxH] [--scenes LIST] [--step N] [--operator NAME]",
    .details = "Renders each scene in the original (g), manipulated (h) and optimized (f) modes and\n"
               "writes DIR/index.html: stereo stills, videos (with ffmpeg), x-t slices of g, h and f,\n"
               "the objects' vergence over time, the cascade view, the image-warping baseline's\n"
               "holes, a metrics table per scene and per-pass ms. Each scene and mode also gets a\n"
               "capture.json with the figures the report shows. See docs/demo.md.",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
