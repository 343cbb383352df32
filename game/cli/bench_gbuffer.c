/* vergence bench gbuffer — GPU milliseconds per pass (shadow, G-buffer) at
 * two frame sizes (default 960x540 and 1920x1080) on the current device.
 *
 *   vergence bench gbuffer [--scene FILE] [--sizes WxH,WxH] [--frames N] [--warmup N] [--first F]
 *
 * Renders frames F+warmup .. F+warmup+N-1 after `warmup` unmeasured frames,
 * headless and without readback (what a windowed frame does), and prints the
 * median of each pass's time by the frame's pass clock (frame_time_passes) plus the
 * median wall time of frame_render (CPU scene evaluation, upload, submit and
 * wait). Not a test: figures go to docs/PERFORMANCE.md by hand. */
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

typedef struct bench_opts {
    const char *scene, *sizes;
    int frames, warmup, first;
    gpu_cli gpu;
    display_cli display;
} bench_opts;

static bench_opts o;

static const vg_opt k_opts[] = {
    {"--scene", VG_OPT_STRING, &o.scene, "FILE", "glTF scene (default content/balloon.gltf)", NULL, 0, 0},
    {"--sizes", VG_OPT_STRING, &o.sizes, "WxH,WxH", "the two frame sizes (default 960x540,1920x1080)", NULL, 0, 0},
    {"--frames", VG_OPT_INT, &o.frames, "N", "measured frames per size, medians (default 30)", NULL, 1, 100000},
    {"--warmup", VG_OPT_INT, &o.warmup, "N", "unmeasured frames first (default 5)", NULL, 0, 100000},
    {"--first", VG_OPT_INT, &o.first, "F", "first frame number (default 90)", NULL, 0, 100000000},
    DISPLAY_CLI_OPTIONS(o.display),
    GPU_CLI_OPTIONS(o.gpu),
};

/* ------------------------------------------------------------------------- */
/* Measuring                                                                 */
/* ------------------------------------------------------------------------- */

typedef struct bench_result {
    uint32_t pass_count;
    char names[RG_MAX_PASSES][32];   /* copies: the graph dies with the frame */
    double pass_ms[RG_MAX_PASSES];   /* medians */
    double gpu_ms;                   /* median of the per-frame sum over passes */
    double wall_ms;                  /* median of frame_render's wall time */
    uint32_t shadow_size;            /* shadow map resolution the frame chose */
} bench_result;

static vg_status bench_size(gpu *g, const scene *s, uint32_t w, uint32_t h, bench_result *r)
{
    frame *f = NULL;
    vg_status st = frame_create(g, s, &(frame_desc){.width = w, .height = h, .display = display_cli_desc(&o.display)},
                                &f);
    if (st != VG_OK)
        return st;
    frame_time_passes(f, true);
    int n = o.frames;
    double *samples = calloc((size_t)n * (RG_MAX_PASSES + 2), sizeof *samples);
    if (!samples) {
        frame_destroy(f);
        return VG_ERR_NOMEM;
    }
    double *sum = samples + (size_t)n * RG_MAX_PASSES, *wall = sum + n;
    memset(r, 0, sizeof *r);
    r->shadow_size = frame_get_desc(f)->shadow_size;
    long index = o.first;
    for (int i = 0; i < o.warmup && st == VG_OK; i++)
        st = frame_render(f, index++);
    for (int i = 0; i < n && st == VG_OK; i++) {
        double t0 = vg_now_ms();
        st = frame_render(f, index++);
        wall[i] = vg_now_ms() - t0;
        double ms[RG_MAX_PASSES];
        const char *names[RG_MAX_PASSES];
        r->pass_count = frame_pass_timings(f, names, ms, RG_MAX_PASSES);
        sum[i] = 0.0;
        for (uint32_t p = 0; p < r->pass_count; p++) {
            snprintf(r->names[p], sizeof r->names[p], "%s", names[p]);
            samples[(size_t)p * n + i] = ms[p];
            sum[i] += ms[p];
        }
    }
    if (st == VG_OK) {
        for (uint32_t p = 0; p < r->pass_count; p++)
            r->pass_ms[p] = vg_median(samples + (size_t)p * n, (size_t)n, 1);
        r->gpu_ms = vg_median(sum, (size_t)n, 1);
        r->wall_ms = vg_median(wall, (size_t)n, 1);
    }
    free(samples);
    frame_destroy(f);
    return st;
}

/* ------------------------------------------------------------------------- */
/* The mode                                                                  */
/* ------------------------------------------------------------------------- */

static int run(int argc, char **argv)
{
    o = (bench_opts){.scene = "content/balloon.gltf", .sizes = "960x540,1920x1080", .frames = 30, .warmup = 5,
                     .first = 90, .gpu = {.device = -1}};
    bool help = false;
    if (vg_cli_parse(&vg_cmd_bench_gbuffer, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    uint32_t sizes[2][2];
    if (!bench_parse_sizes(vg_cmd_bench_gbuffer.name, o.sizes, sizes))
        return 2;
    vg_status st = display_cli_load(&o.display);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    scene *s = NULL;
    st = scene_load(o.scene, &s);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    gpu *g = NULL;
    st = gpu_cli_open(&o.gpu, false, &g);
    if (st != VG_OK) {
        scene_destroy(s);
        return vg_status_exit_code(st);
    }
    printf("vergence bench gbuffer: %s (%s)%s\n", g->props.deviceName, gpu_device_type_text(g->props.deviceType),
           g->validation ? "  [validation on: timings are distorted]" : "");
    if (!g->features.timestamps)
        printf("note: the device has no timestamps; pass times are NaN\n");
    printf("scene: %s (%d instances, %u triangles)\n", o.scene, s->instance_count, s->index_count / 3);
    printf("frames %d..%d after %d warm-up frame(s); medians of %d frames\n\n", o.first + o.warmup,
           o.first + o.warmup + o.frames - 1, o.warmup, o.frames);

    bench_result res[2];
    for (int k = 0; k < 2 && st == VG_OK; k++) {
        vg_info("bench: %ux%u, %d frame(s)", sizes[k][0], sizes[k][1], o.warmup + o.frames);
        st = bench_size(g, s, sizes[k][0], sizes[k][1], &res[k]);
    }
    if (st == VG_OK) {
        printf("%-11s", "size");
        for (uint32_t p = 0; p < res[0].pass_count; p++)
            printf(" %10s ms", res[0].names[p]);
        printf(" %10s ms %10s ms %8s\n", "passes", "frame wall", "of wall");
        for (int k = 0; k < 2; k++) {
            char size[32];
            snprintf(size, sizeof size, "%ux%u", sizes[k][0], sizes[k][1]);
            printf("%-11s", size);
            for (uint32_t p = 0; p < res[k].pass_count; p++)
                printf(" %13.2f", res[k].pass_ms[p]);
            printf(" %13.2f %13.2f %7.1f%%\n", res[k].gpu_ms, res[k].wall_ms, 100 * res[k].gpu_ms / res[k].wall_ms);
        }
        printf("(shadow map %u px at %ux%u; passes = median over frames of the sum of the passes, by the pass clock)\n",
               res[0].shadow_size, sizes[0][0], sizes[0][1]);
    } else {
        vg_error("bench gbuffer: %s", vg_status_text(st));
    }
    scene_destroy(s);
    return gpu_cli_close(g, st);
}

const vg_cmd vg_cmd_bench_gbuffer = {
    .name = "bench gbuffer",
    .summary = "shadow and G-buffer GPU ms per pass at two frame sizes, medians over frames",
    .usage = "vergence bench gbuffer [--scene FILE] [--sizes WxH,WxH] [--frames N] [--warmup N] [--first F]",
    .details = "Renders the frame headless without readback (what a windowed frame does) at each size and\n"
               "prints the median ms of each pass by the pass clock, their sum and the frame's wall time\n"
               "(scene evaluation, upload, submit and wait). Validation distorts the timings.",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
