/* vergence bench — the engine's figures in one table (issue 8): per-pass GPU
 * ms of the optimised stereo frame at two sizes, the ratio of that frame to
 * plain two-camera stereo measured in the same run, warp ms per eye against
 * the tessellation setting, the CPU solver's speed against a STREAM triad
 * (bench_solver.c's tables), and peak memory. Medians over frames; nothing
 * here is a test (the figures go to docs/PERFORMANCE.md).
 *
 * `vergence bench MODE` runs one part's own benchmark instead (issue 41):
 * gbuffer, solver, disparity, warp (bench_modes.h), each with its options.
 *
 * Passes are timed by the frame's pass clock (frame_time_passes), so they
 * add up to the frame's wall time; the table says how closely. Every frame
 * size also renders frames with the clock off, interleaved with the timed
 * ones: their wall time is the frame as the game runs it, and the ratio to
 * two-camera stereo is taken from those. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/resource.h>

#include "bench_game.h"
#include "bench_modes.h"
#include "bench_report.h"
#include "commands.h"
#include "core/clock.h"
#include "core/io.h"
#include "core/log.h"
#include "core/manifest.h"
#include "core/parallel.h"
#include "core/stats.h"
#include "options/display_cli.h"
#include "options/gpu_cli.h"
#include "frame/frame.h"
#include "scene/scene.h"

static struct {
    const char *scene, *sizes, *tess, *markdown;
    int frames, tess_frames, game_frames, frame_ticks, game_throws;
    bool no_solver, all_passes, game, each_throw, ball_frames;
    gpu_cli gpu;
    display_cli display;
} o;

static const vg_opt k_opts[] = {
    {"--scene", VG_OPT_STRING, &o.scene, "FILE", "glTF scene to render (default: content/balloon.gltf; --game: content/arena.gltf)", NULL, 0, 0},
    {"--frames", VG_OPT_INT, &o.frames, "N", "frames per setting, medians (default 10: one keyframe interval)",
     NULL, 1, 1000},
    {"--sizes", VG_OPT_STRING, &o.sizes, "WxH,WxH", "the two frame sizes (default 960x540,1920x1080)", NULL, 0, 0},
    {"--tess", VG_OPT_STRING, &o.tess, "P,P,...",
     "tess-px settings timed at the first size beside error-driven (default 1,2,4,8; 'none' skips)", NULL, 0, 0},
    {"--tess-frames", VG_OPT_INT, &o.tess_frames, "N",
     "frames per tess-px setting (default 1: 1-px tessellation takes minutes a frame on a CPU)", NULL, 1, 1000},
    {"--all-passes", VG_OPT_FLAG, &o.all_passes, NULL, "also list every pass of the optimised frame", NULL, 0, 0},
    {"--game", VG_OPT_FLAG, &o.game, NULL,
     "only the game: its frame rate in each mode at its defaults, the same replay every run (--scene: the arena)",
     NULL, 0, 0},
    {"--game-frames", VG_OPT_INT, &o.game_frames, "N", "with --game: frames a mode (default 120: 6 s, two throws; 0: no frame rates)",
     NULL, 0, 10000},
    {"--frame-ticks", VG_OPT_INT, &o.frame_ticks, "T",
     "with --game: 1/60 s ticks the clock advances a frame (default 3: a 20 fps game)", NULL, 1, 60},
    {"--game-throws", VG_OPT_INT, &o.game_throws, "N",
     "with --game: throws of each kind whose ball is measured (default 5; 0: none)", NULL, 0, 1000},
    {"--ball-frames", VG_OPT_FLAG, &o.ball_frames, NULL,
     "with --game: measure the ball at every frame of its flight, not only at its keyframes (10x the frames)", NULL,
     0, 0},
    {"--each-throw", VG_OPT_FLAG, &o.each_throw, NULL,
     "with --game: a line for every throw measured (its figures, g and f - h at its keyframes)", NULL, 0, 0},
    {"--no-solver", VG_OPT_FLAG, &o.no_solver, NULL,
     "skip the CPU solver's speed table and memory bandwidth ('vergence bench solver' runs them alone)", NULL, 0,
     0},
    {"--markdown", VG_OPT_STRING, &o.markdown, "FILE", "also write the tables as Markdown (docs/PERFORMANCE.md)",
     NULL, 0, 0},
    DISPLAY_CLI_OPTIONS(o.display),
    GPU_CLI_OPTIONS(o.gpu),
};

/* ------------------------------------------------------------------------- */
/* Measurements                                                              */
/* ------------------------------------------------------------------------- */

/* The columns of the per-pass table: frame graph passes by name prefix. */
enum { G_GBUFFER, G_OPERATOR, G_WINDOW, G_SOLVE, G_UPSAMPLE, G_CURVE, G_WARP, G_COMPOSE, G_HOST, G_OTHER, G_COUNT };
static const char *const k_group_names[G_COUNT] = {"gbuffer", "operator", "window",  "solve",
                                                   "upsample", "curve",   "warp",    "compose",
                                                   "host (CPU: begin, record, submit)", "other"};

static int group_of(const char *pass)
{
    static const struct {
        const char *prefix;
        int group;
    } k[] = {
        {"shadow", G_GBUFFER},        {"gbuffer", G_GBUFFER},  {"disparity.", G_OPERATOR},
        {"mid.keyframes", G_WINDOW},  {"mid.window", G_WINDOW}, {"mid.solve", G_SOLVE},
        {"mid.upsample", G_UPSAMPLE}, {"warp.curve", G_CURVE},  {"warp.", G_WARP},
        {"cameras.", G_WARP},         {"compose", G_COMPOSE},  {FRAME_PASS_HOST, G_HOST},
    };
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++)
        if (!strncmp(pass, k[i].prefix, strlen(k[i].prefix)))
            return k[i].group;
    return G_OTHER;
}

/* Per frame: GPU ms of each group, of all passes, of the eyes, wall ms. */
#define MAX_PASSES 64

typedef struct samples {
    int n;
    double *group[G_COUNT], *gpu, *eyes, *wall, *solve;
    int n_untimed;
    double *untimed;                  /* wall ms of the frames rendered with the pass clock off */
    int passes;                       /* every pass of the graph, for --all-passes */
    char pass_name[MAX_PASSES][48];
    double *pass_ms[MAX_PASSES];
} samples;

typedef struct figures {
    double group[G_COUNT], gpu, eyes, wall, untimed;
    int passes;
    char pass_name[MAX_PASSES][48];
    double pass[MAX_PASSES];
    double solve_mean;          /* mid.solve, mean over the frames (amortised over a keyframe interval) */
    double device_mb;           /* device memory the frame holds */
} figures;

static vg_status samples_init(samples *s, int n)
{
    *s = (samples){.n = 0};
    double **all[] = {&s->gpu, &s->eyes, &s->wall, &s->solve, &s->untimed};
    for (int i = 0; i < 5; i++)
        if (!(*all[i] = calloc((size_t)n, sizeof(double))))
            return VG_ERR_NOMEM;
    for (int g = 0; g < G_COUNT; g++)
        if (!(s->group[g] = calloc((size_t)n, sizeof(double))))
            return VG_ERR_NOMEM;
    for (int p = 0; p < MAX_PASSES; p++)
        if (!(s->pass_ms[p] = calloc((size_t)n, sizeof(double))))
            return VG_ERR_NOMEM;
    return VG_OK;
}

static void samples_free(samples *s)
{
    free(s->gpu);
    free(s->eyes);
    free(s->wall);
    free(s->solve);
    free(s->untimed);
    for (int g = 0; g < G_COUNT; g++)
        free(s->group[g]);
    for (int p = 0; p < MAX_PASSES; p++)
        free(s->pass_ms[p]);
}

/* One frame with the pass clock on (timed) or off (its wall time only). */
static vg_status render_one(frame *f, long index, samples *s, bool timed)
{
    frame_time_passes(f, timed);
    double t0 = vg_now_ms();
    vg_status st = frame_render(f, index);
    if (st != VG_OK)
        return st;
    double wall = vg_now_ms() - t0;
    if (!timed) {
        s->untimed[s->n_untimed++] = wall;
        return VG_OK;
    }
    const char *names[MAX_PASSES];
    double ms[MAX_PASSES];
    uint32_t n = frame_pass_timings(f, names, ms, MAX_PASSES);
    int i = s->n++;
    s->passes = (int)n;
    for (uint32_t p = 0; p < n; p++) {
        snprintf(s->pass_name[p], sizeof s->pass_name[p], "%s", names[p]);
        s->pass_ms[p][i] = ms[p];
    }
    s->wall[i] = wall;
    for (uint32_t p = 0; p < n; p++) {
        int g = group_of(names[p]);
        s->group[g][i] += ms[p];
        s->gpu[i] += ms[p];
        if (!strncmp(names[p], "warp.left", 9) || !strncmp(names[p], "warp.right", 10) ||
            !strncmp(names[p], "cameras.", 8))
            s->eyes[i] += ms[p];
        if (!strcmp(names[p], "mid.solve"))
            s->solve[i] += ms[p];
    }
    return VG_OK;
}

static figures summarise(const samples *s, double device_mb)
{
    figures r = {.gpu = vg_median(s->gpu, (size_t)s->n, 1), .eyes = vg_median(s->eyes, (size_t)s->n, 1),
                 .wall = vg_median(s->wall, (size_t)s->n, 1),
                 .untimed = s->n_untimed ? vg_median(s->untimed, (size_t)s->n_untimed, 1) : NAN,
                 .device_mb = device_mb};
    for (int g = 0; g < G_COUNT; g++)
        r.group[g] = vg_median(s->group[g], (size_t)s->n, 1);
    r.passes = s->passes;
    for (int p = 0; p < s->passes; p++) {
        memcpy(r.pass_name[p], s->pass_name[p], sizeof r.pass_name[p]);
        r.pass[p] = vg_median(s->pass_ms[p], (size_t)s->n, 1);
    }
    for (int i = 0; i < s->n; i++)
        r.solve_mean += s->solve[i] / s->n;
    return r;
}

/* The median ms of the pass named `name` (0 when the frame has none). */
static double figures_pass(const figures *f, const char *name)
{
    for (int p = 0; p < f->passes; p++)
        if (!strcmp(f->pass_name[p], name))
            return f->pass[p];
    return 0;
}

/* Frames of several descriptions rendered in turn, frame by frame, so all
 * see the same load on a shared machine, each frame index once with the
 * pass clock on and the next with it off. The first frame of each is not
 * counted (it runs the whole first solve at once). */
static vg_status run_interleaved(gpu *g, const scene *sc, const frame_desc *descs, int count, int frames,
                                 figures *out)
{
    frame *f[4] = {0};
    samples s[4];
    double mb[4] = {0};
    vg_status st = VG_OK;
    for (int k = 0; k < count; k++)
        if (samples_init(&s[k], frames) != VG_OK)
            st = VG_ERR_NOMEM;
    for (int k = 0; k < count && st == VG_OK; k++) {
        VkDeviceSize before = g->memory_bytes;
        st = frame_create(g, sc, &descs[k], &f[k]);
        if (st == VG_OK)
            st = frame_render(f[k], 89); /* warm-up; the graph's transients exist from here */
        mb[k] = (double)(g->memory_bytes - before) / (1024.0 * 1024.0);
    }
    for (int i = 0; i < frames && st == VG_OK; i++) {
        for (int k = 0; k < count && st == VG_OK; k++)
            st = render_one(f[k], 90 + 2 * i, &s[k], true);
        for (int k = 0; k < count && st == VG_OK; k++)
            st = render_one(f[k], 91 + 2 * i, &s[k], false);
        vg_progress("bench", i + 1, frames);
    }
    for (int k = 0; k < count; k++) {
        if (st == VG_OK)
            out[k] = summarise(&s[k], mb[k]);
        samples_free(&s[k]);
        frame_destroy(f[k]);
    }
    return st;
}

/* ------------------------------------------------------------------------- */
/* The command                                                               */
/* ------------------------------------------------------------------------- */

/* "1,2,4,8" -> px[]; "none" -> 0 settings. Returns the count or -1. */
static int parse_tess(const char *text, double *px, int cap)
{
    if (!strcmp(text, "none"))
        return 0;
    int n = 0;
    const char *p = text;
    while (*p) {
        char *end;
        double v = strtod(p, &end);
        if (end == p || !(v >= 0.25 && v <= 64) || n == cap)
            return -1;
        px[n++] = v;
        p = end;
        if (*p == ',')
            p++;
        else if (*p)
            return -1;
    }
    return n;
}

static vg_status bench_frames(gpu *g, const scene *sc, uint32_t sizes[2][2], bench_report *r)
{
    frame_desc base = {.stereo = FRAME_STEREO_WARP, .mode = FRAME_MODE_OPTIMIZED, .diffuse = true,
                       .display = display_cli_desc(&o.display)};
    figures fig[2][2]; /* [size][optimised, cameras] */
    for (int k = 0; k < 2; k++) {
        frame_desc d[2] = {base, base};
        for (int j = 0; j < 2; j++) {
            d[j].width = sizes[k][0];
            d[j].height = sizes[k][1];
        }
        d[1].stereo = FRAME_STEREO_CAMERAS;
        d[1].mode = FRAME_MODE_ORIGINAL;
        vg_info("bench: %ux%u, optimised warp and two cameras in turn, %d frames", sizes[k][0],
               sizes[k][1], o.frames);
        vg_status st = run_interleaved(g, sc, d, 2, o.frames, fig[k]);
        if (st != VG_OK)
            return st;
    }
    char cells[4][32];
    bench_heading(r, "Per-pass ms, optimised stereo frame (warp, error-driven tessellation 0.025 px)");
    for (int k = 0; k < 2; k++)
        snprintf(cells[k], sizeof cells[k], "%ux%u", sizes[k][0], sizes[k][1]);
    bench_row(r, true, "pass (median ms)", 2, cells);
    for (int gi = 0; gi < G_COUNT; gi++) {
        double v[2] = {fig[0][0].group[gi], fig[1][0].group[gi]};
        if (gi == G_OTHER && v[0] == 0 && v[1] == 0)
            continue;
        bench_row_values(r, k_group_names[gi], 2, v, "%.1f");
    }
    double v[2];
    v[0] = fig[0][0].gpu, v[1] = fig[1][0].gpu;
    bench_row_values(r, "all passes (sum)", 2, v, "%.1f");
    v[0] = fig[0][0].wall, v[1] = fig[1][0].wall;
    bench_row_values(r, "frame, wall clock (passes timed)", 2, v, "%.1f");
    v[0] = 100 * fig[0][0].gpu / fig[0][0].wall, v[1] = 100 * fig[1][0].gpu / fig[1][0].wall;
    bench_row_values(r, "passes / wall", 2, v, "%.1f%%");
    v[0] = fig[0][0].untimed, v[1] = fig[1][0].untimed;
    bench_row_values(r, "frame, wall clock (clock off: as played)", 2, v, "%.1f");
    v[0] = fig[0][1].gpu, v[1] = fig[1][1].gpu;
    bench_row_values(r, "two cameras: all passes (sum)", 2, v, "%.1f");
    v[0] = fig[0][1].wall, v[1] = fig[1][1].wall;
    bench_row_values(r, "two cameras: frame, wall (passes timed)", 2, v, "%.1f");
    v[0] = 100 * fig[0][1].gpu / fig[0][1].wall, v[1] = 100 * fig[1][1].gpu / fig[1][1].wall;
    bench_row_values(r, "two cameras: passes / wall", 2, v, "%.1f%%");
    v[0] = fig[0][1].untimed, v[1] = fig[1][1].untimed;
    bench_row_values(r, "two cameras: frame, wall (clock off)", 2, v, "%.1f");
    v[0] = fig[0][0].untimed / fig[0][1].untimed, v[1] = fig[1][0].untimed / fig[1][1].untimed;
    bench_row_values(r, "ratio optimised / two cameras (clock off)", 2, v, "%.2fx");
    /* What the ratio would be were the keyframes, window, solve and
     * upsampling free, and the least the frame's design costs: the paper
     * renders the scene twice (the centre G-buffer, then the warped pair,
     * each eye at least a camera's), so no optimised frame is cheaper than
     * two cameras plus a G-buffer pass (passes timed, same run). */
    for (int k = 0; k < 2; k++) {
        const figures *a = &fig[k][0];
        v[k] = (a->gpu - a->group[G_WINDOW] - a->group[G_SOLVE] - a->group[G_UPSAMPLE]) / fig[k][1].gpu;
    }
    bench_row_values(r, "ratio, MID passes free (passes timed)", 2, v, "%.2fx");
    for (int k = 0; k < 2; k++)
        v[k] = (fig[k][1].gpu + figures_pass(&fig[k][0], "gbuffer")) / fig[k][1].gpu;
    bench_row_values(r, "least ratio: two cameras + gbuffer (timed)", 2, v, "%.2fx");
    v[0] = fig[0][0].eyes / 2, v[1] = fig[1][0].eyes / 2;
    bench_row_values(r, "warp ms per eye", 2, v, "%.1f");
    v[0] = fig[0][0].solve_mean * 10, v[1] = fig[1][0].solve_mean * 10;
    bench_row_values(r, "mid.solve per window (mean x 10 frames)", 2, v, "%.1f");
    v[0] = fig[0][0].device_mb, v[1] = fig[1][0].device_mb;
    bench_row_values(r, "device memory of the frame (MB)", 2, v, "%.1f");
    v[0] = fig[0][1].device_mb, v[1] = fig[1][1].device_mb;
    bench_row_values(r, "two cameras: device memory (MB)", 2, v, "%.1f");
    if (o.all_passes && fig[0][0].passes == fig[1][0].passes) {
        bench_heading(r, "Every pass of the optimised frame (median ms)");
        for (int k = 0; k < 2; k++)
            snprintf(cells[k], sizeof cells[k], "%ux%u", sizes[k][0], sizes[k][1]);
        bench_row(r, true, "pass", 2, cells);
        for (int p = 0; p < fig[0][0].passes; p++) {
            v[0] = fig[0][0].pass[p], v[1] = fig[1][0].pass[p];
            bench_row_values(r, fig[0][0].pass_name[p], 2, v, "%.1f");
        }
    }
    char big[512];
    snprintf(big, sizeof big,
             "Targets (issue 17): two cameras %ux%u / %ux%u >= 2.5x (measured %.2fx); optimised / two cameras "
             "<= 1.3x at %ux%u (%.2fx) and <= 1.5x at %ux%u (%.2fx); passes within 10 %% of the wall time "
             "(%.0f %%, %.0f %%, %.0f %%, %.0f %%).",
             sizes[1][0], sizes[1][1], sizes[0][0], sizes[0][1], fig[1][1].untimed / fig[0][1].untimed, sizes[0][0],
             sizes[0][1], fig[0][0].untimed / fig[0][1].untimed, sizes[1][0], sizes[1][1],
             fig[1][0].untimed / fig[1][1].untimed, 100 * fig[0][0].gpu / fig[0][0].wall,
             100 * fig[1][0].gpu / fig[1][0].wall, 100 * fig[0][1].gpu / fig[0][1].wall,
             100 * fig[1][1].gpu / fig[1][1].wall);
    bench_note(r, big);
    return VG_OK;
}

static vg_status bench_tessellation(gpu *g, const scene *sc, uint32_t w, uint32_t h, bench_report *r)
{
    double px[8];
    int n = parse_tess(o.tess ? o.tess : "1,2,4,8", px, 8);
    char cells[4][32], label[64];
    bench_heading(r, "Warp ms per eye against tessellation (optimised f)");
    snprintf(cells[0], sizeof cells[0], "%ux%u ms/eye", w, h);
    snprintf(cells[1], sizeof cells[1], "frame ms (wall)");
    snprintf(cells[2], sizeof cells[2], "frames");
    bench_row(r, true, "tessellation", 3, cells);
    for (int i = 0; i <= n; i++) {
        frame_desc d = {.width = w, .height = h, .stereo = FRAME_STEREO_WARP, .mode = FRAME_MODE_OPTIMIZED,
                        .diffuse = true, .display = display_cli_desc(&o.display)};
        int frames = o.frames;
        if (i < n) {
            d.tess_px = px[i];
            frames = o.tess_frames;
            snprintf(label, sizeof label, "tess-px %g", px[i]);
        } else {
            snprintf(label, sizeof label, "error-driven 0.025 px (default)");
        }
        vg_info("bench: %s at %ux%u, %d frame(s)", label, w, h, frames);
        figures f;
        frame *fr;
        samples s;
        vg_status st = samples_init(&s, frames);
        if (st == VG_OK)
            st = frame_create(g, sc, &d, &fr);
        if (st != VG_OK) {
            samples_free(&s);
            return st;
        }
        for (int k = 0; k < frames && st == VG_OK; k++)
            st = render_one(fr, 90 + k, &s, true);
        if (st == VG_OK)
            f = summarise(&s, 0);
        samples_free(&s);
        frame_destroy(fr);
        if (st != VG_OK)
            return st;
        snprintf(cells[0], sizeof cells[0], "%.1f", f.eyes / 2);
        snprintf(cells[1], sizeof cells[1], "%.1f", f.wall);
        snprintf(cells[2], sizeof cells[2], "%d", frames);
        bench_row(r, false, label, 3, cells);
    }
    return VG_OK;
}

/* The modes: `vergence bench MODE [options]`, MODE the word after "bench ". */
static const vg_cmd *const k_modes[] = {&vg_cmd_bench_gbuffer, &vg_cmd_bench_solver, &vg_cmd_bench_disparity,
                                        &vg_cmd_bench_warp};
enum { MODES = sizeof k_modes / sizeof k_modes[0] };

static const char *mode_word(const vg_cmd *mode) { return mode->name + strlen("bench "); }

static int run(int argc, char **argv)
{
    if (argc > 1 && argv[1][0] != '-') {
        for (int i = 0; i < MODES; i++)
            if (!strcmp(argv[1], mode_word(k_modes[i])))
                return k_modes[i]->run(argc - 1, argv + 1);
        vg_error("bench: '%s' is not a mode (gbuffer, solver, disparity or warp; see 'vergence bench --help')",
                 argv[1]);
        return 2;
    }
    memset(&o, 0, sizeof o);
    o.scene = NULL;
    o.sizes = "960x540,1920x1080";
    o.game_frames = 120;
    o.frame_ticks = 3;
    o.game_throws = 5;
    o.frames = 10;
    o.tess_frames = 1;
    o.gpu.device = -1;
    bool help = false;
    if (vg_cli_parse(&vg_cmd_bench, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    vg_status dst = display_cli_load(&o.display);
    if (dst != VG_OK)
        return vg_status_exit_code(dst);
    uint32_t sizes[2][2];
    if (!bench_parse_sizes("bench", o.sizes, sizes))
        return 2;
    double px[8];
    if (o.tess && parse_tess(o.tess, px, 8) < 0) {
        vg_error("vergence bench: --tess: '%s' is not 'none' or a list of up to 8 pixel sizes (0.25..64)", o.tess);
        return 2;
    }
    if (!o.scene)
        o.scene = o.game ? "content/arena.gltf" : "content/balloon.gltf";
    scene *sc;
    vg_status st = scene_load(o.scene, &sc);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    /* The tables' file: no input, and writable before minutes of work. */
    bench_report r = {0};
    char tmp[4096];
    if (o.markdown) {
        vg_inputs in = {0};
        for (int i = 0; i < sc->file_count && st == VG_OK; i++)
            st = vg_inputs_add(&in, "--scene", sc->files[i]);
        if (st == VG_OK)
            st = vg_inputs_check(&in, "--markdown", o.markdown);
        vg_inputs_free(&in);
        /* The tables replace the file at the end (a rename): a folder there
         * would fail only after the whole run. */
        struct stat sb;
        if (st == VG_OK && stat(o.markdown, &sb) == 0 && !S_ISREG(sb.st_mode)) {
            vg_error("--markdown %s: is %s, not a file: give the name of the file to write", o.markdown,
                     S_ISDIR(sb.st_mode) ? "a folder" : "a device or a pipe");
            st = VG_ERR_IO;
        }
        if (st == VG_OK && (snprintf(tmp, sizeof tmp, "%s.tmp", o.markdown) >= (int)sizeof tmp ||
                            !(r.md = fopen(tmp, "w")))) {
            vg_error("--markdown %s: cannot write there: %s", o.markdown, strerror(errno));
            st = VG_ERR_IO;
        }
        if (st != VG_OK) {
            scene_destroy(sc);
            return vg_status_exit_code(st);
        }
    }
    gpu *g;
    st = gpu_cli_open(&o.gpu, false, &g);
    if (st != VG_OK) {
        if (r.md) {
            fclose(r.md);
            remove(tmp);
        }
        scene_destroy(sc);
        return vg_status_exit_code(st);
    }
    if (o.game) {
        printf("vergence bench --game: %s on %s, %d CPU cores\n", o.scene, g->props.deviceName, vg_cpu_count());
        if (r.md)
            fprintf(r.md, "Scene `%s` on %s, %d CPU cores.\n", o.scene, g->props.deviceName, vg_cpu_count());
        if (o.game_frames > 0)
            st = bench_game(g, sc, o.scene, display_cli_desc(&o.display), o.game_frames, o.frame_ticks, &r);
        if (st == VG_OK && o.game_throws > 0)
            st = bench_ball(g, sc, o.scene, display_cli_desc(&o.display), o.game_throws, o.ball_frames, o.each_throw,
                            &r);
    } else {
        printf("vergence bench: %s on %s, %d CPU cores; medians of %d frames per setting\n", o.scene,
               g->props.deviceName, vg_cpu_count(), o.frames);
        if (r.md)
            fprintf(r.md, "Scene `%s` on %s, %d CPU cores; medians of %d frames per setting.\n", o.scene,
                    g->props.deviceName, vg_cpu_count(), o.frames);
        st = bench_frames(g, sc, sizes, &r);
        if (st == VG_OK)
            st = bench_tessellation(g, sc, sizes[0][0], sizes[0][1], &r);
        if (st == VG_OK && !o.no_solver)
            st = bench_solver_tables(&r, 5, false);
    }
    if (st == VG_OK) {
        struct rusage ru;
        getrusage(RUSAGE_SELF, &ru);
        char cells[4][32];
        bench_heading(&r, "Peak memory");
        snprintf(cells[0], sizeof cells[0], "MB");
        bench_row(&r, true, "measure", 1, cells);
        snprintf(cells[0], sizeof cells[0], "%.1f", (double)g->memory_peak / (1024.0 * 1024.0));
        bench_row(&r, false, "device memory allocated (peak)", 1, cells);
        snprintf(cells[0], sizeof cells[0], "%.1f", (double)ru.ru_maxrss / 1024.0);
        bench_row(&r, false, "process resident set (peak; lavapipe's memory is host memory)", 1, cells);
    }
    if (r.md) {
        bool closed = fclose(r.md) == 0;
        if (st == VG_OK && (!closed || rename(tmp, o.markdown) != 0)) {
            vg_error("--markdown %s: cannot write: %s", o.markdown, strerror(errno));
            st = VG_ERR_IO;
        }
        if (st != VG_OK)
            remove(tmp);
        else
            vg_info("bench: tables written to %s", o.markdown);
    }
    scene_destroy(sc);
    return gpu_cli_close(g, st);
}

const vg_cmd vg_cmd_bench = {
    .name = "bench",
    .summary = "benchmark the frame: per-pass ms, stereo cost ratio, tessellation, solver, memory; or one part",
    .usage = "vergence bench [gbuffer|solver|disparity|warp] [options]",
    .details = "Without a mode: renders the optimised stereo frame and plain two-camera stereo in turn at\n"
               "two sizes and prints one table: per-pass GPU ms, their ratio, warp ms against the tessellation\n"
               "setting, the CPU solver's ms and GB/s against a STREAM triad (the speed tables of 'vergence\n"
               "bench solver'), and peak memory. Takes several minutes on a CPU (1-px tessellation alone\n"
               "takes minutes a frame); figures belong in docs/PERFORMANCE.md. The options below are this\n"
               "table's.\n"
               "\n"
               "modes (each with its own options: 'vergence bench MODE --help'):\n"
               "  gbuffer    shadow and G-buffer ms per pass at two sizes\n"
               "  solver     the CPU MID solver: ms and GB/s with 1 and all threads, the quality each reaches\n"
               "  disparity  the GPU disparity passes at two sizes: the solve flat, the upsampling per pixel\n"
               "  warp       warp ms per eye for tess-px 1, 2, 4, 8 and error-driven, against two cameras",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
