/* vergence bench warp — warp ms per eye at one size (default 960x540) for
 * tess-px 1, 2, 4, 8 and error-driven tessellation of the optimised map f,
 * and the ratio of the whole optimised stereo frame (G-buffer, disparity
 * pipeline, curve, warp, compose) to the plain two-camera stereo frame in
 * the same run. Medians of N frames after warm-up, no readback, no
 * per-pixel measurement (what a game frame does).
 *
 *   vergence bench warp [--scene FILE] [--frames N] [--size WxH] [--skip-1px] [--tess-error PX]
 *
 * Not a test: figures go to docs/PERFORMANCE.md. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_modes.h"
#include "core/clock.h"
#include "core/log.h"
#include "core/stats.h"
#include "frame/frame.h"
#include "options/display_cli.h"
#include "options/gpu_cli.h"

static struct {
    const char *scene;
    int frames, size[2];
    double tess_error;
    bool skip_1px;
    gpu_cli gpu;
    display_cli display;
} o;

static const vg_opt k_opts[] = {
    {"--scene", VG_OPT_STRING, &o.scene, "FILE", "glTF scene (default content/balloon.gltf)", NULL, 0, 0},
    {"--frames", VG_OPT_INT, &o.frames, "N",
     "frames per setting, medians after 3 warm-up frames (default 7; a third of them for tess-px)", NULL, 1, 1000},
    {"--size", VG_OPT_SIZE, o.size, "WxH", "frame size (default 960x540)", NULL, 0, 0},
    {"--skip-1px", VG_OPT_FLAG, &o.skip_1px, NULL, "leave out tess-px 1 (seconds to minutes a frame on a CPU)", NULL,
     0, 0},
    {"--tess-error", VG_OPT_FLOAT, &o.tess_error, "PX",
     "the error-driven rows' tolerance in pixels (default 0.025, the frame's)", NULL, 0.001, 100},
    DISPLAY_CLI_OPTIONS(o.display),
    GPU_CLI_OPTIONS(o.gpu),
};

typedef struct result {
    double frame_ms;   /* wall clock of a frame that waits for completion */
    double eye_ms;     /* warp.left + warp.right (or cameras.*) */
    double passes_ms;  /* every pass, by the frame's pass clock */
} result;

static vg_status measure(gpu *g, const scene *s, const frame_desc *d, int frames, result *out)
{
    frame *f;
    vg_status st = frame_create(g, s, d, &f);
    if (st != VG_OK)
        return st;
    frame_time_passes(f, true);
    double *total = calloc((size_t)frames, sizeof *total), *eyes = calloc((size_t)frames, sizeof *eyes),
           *sum = calloc((size_t)frames, sizeof *sum);
    if (!total || !eyes || !sum)
        st = VG_ERR_NOMEM;
    for (int i = -3; i < frames && st == VG_OK; i++) {
        double t0 = vg_now_ms();
        st = frame_render(f, 90 + i);
        double wall = vg_now_ms() - t0;
        const char *names[64];
        double ms[64];
        uint32_t n = frame_pass_timings(f, names, ms, 64);
        if (i < 0)
            continue;
        total[i] = wall;
        for (uint32_t p = 0; p < n; p++) {
            sum[i] += ms[p];
            if (!strncmp(names[p], "warp.left", 9) || !strncmp(names[p], "warp.right", 10) ||
                !strncmp(names[p], "cameras.", 8))
                eyes[i] += ms[p];
        }
    }
    if (st == VG_OK)
        *out = (result){vg_median(total, (size_t)frames, 1), vg_median(eyes, (size_t)frames, 1),
                        vg_median(sum, (size_t)frames, 1)};
    free(total);
    free(sum);
    free(eyes);
    frame_destroy(f);
    return st;
}

/* ------------------------------------------------------------------------- */
/* The mode                                                                  */
/* ------------------------------------------------------------------------- */

static void print_row(const char *label, const result *r)
{
    printf("%-22s %12.1f %15.1f %11.1f%%\n", label, r->eye_ms / 2, r->frame_ms, 100 * r->passes_ms / r->frame_ms);
}

static int run(int argc, char **argv)
{
    memset(&o, 0, sizeof o);
    o.scene = "content/balloon.gltf";
    o.frames = 7;
    o.size[0] = 960, o.size[1] = 540;
    o.gpu.device = -1;
    bool help = false;
    if (vg_cli_parse(&vg_cmd_bench_warp, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    uint32_t w = (uint32_t)o.size[0], h = (uint32_t)o.size[1];
    char why[256];
    if (!frame_size_ok(w, h, why, sizeof why)) {
        vg_error("bench warp --size %ux%u: %s", w, h, why);
        return 2;
    }
    vg_status st = display_cli_load(&o.display);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    scene *s;
    st = scene_load(o.scene, &s);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    gpu *g;
    st = gpu_cli_open(&o.gpu, false, &g);
    if (st != VG_OK) {
        scene_destroy(s);
        return vg_status_exit_code(st);
    }
    printf("vergence bench warp: %s, %ux%u, %s, median of %d frames\n", o.scene, w, h, g->props.deviceName,
           o.frames);
    printf("%-22s %12s %15s %12s\n", "tessellation", "warp ms/eye", "frame ms (wall)", "passes/wall");
    frame_desc base = {.width = w, .height = h, .stereo = FRAME_STEREO_WARP, .mode = FRAME_MODE_OPTIMIZED,
                       .diffuse = true, .display = display_cli_desc(&o.display)};
    static const double px[] = {1, 2, 4, 8};
    result warp_error = {0};
    for (int i = 0; i < 5 && st == VG_OK; i++) {
        frame_desc d = base;
        char label[32];
        if (i < 4) {
            if (o.skip_1px && px[i] == 1)
                continue;
            d.tess_px = px[i];
            snprintf(label, sizeof label, "tess-px %g", px[i]);
        } else {
            d.tess_error = o.tess_error; /* 0: the frame default */
            snprintf(label, sizeof label, "error-driven %g px", d.tess_error > 0 ? d.tess_error : 0.025);
        }
        int frames = i < 4 ? (o.frames + 2) / 3 : o.frames;
        vg_info("bench: %s, %d frame(s)", label, frames);
        result r;
        st = measure(g, s, &d, frames, &r);
        if (st == VG_OK)
            print_row(label, &r);
        if (i == 4)
            warp_error = r;
    }
    result cams = {0}, original = {0};
    if (st == VG_OK) {
        frame_desc d = base;
        d.tess_error = o.tess_error;
        d.mode = FRAME_MODE_ORIGINAL;
        vg_info("bench: error-driven, g only, %d frame(s)", o.frames);
        st = measure(g, s, &d, o.frames, &original);
        if (st == VG_OK)
            print_row("error-driven, g only", &original);
    }
    if (st == VG_OK) {
        frame_desc d = base;
        d.stereo = FRAME_STEREO_CAMERAS;
        d.mode = FRAME_MODE_ORIGINAL;
        vg_info("bench: two cameras, %d frame(s)", o.frames);
        st = measure(g, s, &d, o.frames, &cams);
    }
    if (st == VG_OK) {
        print_row("two cameras", &cams);
        printf("stereo frame ratio: optimised warp / two cameras %.2fx; warp of g / two cameras %.2fx\n",
               warp_error.frame_ms / cams.frame_ms, original.frame_ms / cams.frame_ms);
    } else {
        vg_error("bench warp: %s", vg_status_text(st));
    }
    scene_destroy(s);
    return gpu_cli_close(g, st);
}

const vg_cmd vg_cmd_bench_warp = {
    .name = "bench warp",
    .summary = "warp ms per eye for tess-px 1, 2, 4, 8 and error-driven, and the frame against two cameras",
    .usage = "vergence bench warp [--scene FILE] [--frames N] [--size WxH] [--skip-1px] [--tess-error PX]",
    .details = "The optimised stereo frame at one size with each tessellation setting, then the error-driven\n"
               "warp of g alone and plain two-camera stereo: warp ms per eye, the frame's wall ms and the\n"
               "share the pass clock accounts for, and the frame's ratio to two cameras. tess-px 1 takes\n"
               "seconds to minutes a frame on a CPU (--skip-1px leaves it out).",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
