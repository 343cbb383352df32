/* vergence — G-buffer benchmark: GPU milliseconds per pass (shadow,
 * G-buffer) at 960x540 and 1920x1080 on the current device.
 *
 *   bench_gbuffer [--scene FILE] [--frames N] [--warmup N] [--first F] [--gpu N] [--validate]
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

#include "core/clock.h"
#include "core/log.h"
#include "core/stats.h"
#include "frame/frame.h"

typedef struct bench_opts {
    const char *scene;
    int frames, warmup, first, device;
    bool validate;
} bench_opts;

static const struct { uint32_t w, h; } k_sizes[] = {{960, 540}, {1920, 1080}};
enum { SIZES = sizeof k_sizes / sizeof k_sizes[0] };

/* ------------------------------------------------------------------------- */
/* Options                                                                   */
/* ------------------------------------------------------------------------- */

static void usage(FILE *out)
{
    fprintf(out,
            "usage: bench_gbuffer [--scene FILE] [--frames N] [--warmup N] [--first F] [--gpu N] [--validate]\n"
            "  --scene FILE  glTF scene (default content/balloon.gltf)\n"
            "  --frames N    measured frames per size (default 30)\n"
            "  --warmup N    unmeasured frames first (default 5)\n"
            "  --first F     first frame number (default 90)\n"
            "  --gpu N       Vulkan device N (default: automatic)\n"
            "  --validate    Khronos validation (also VERGENCE_VALIDATE=1; distorts timings)\n");
}

static bool int_arg(const char *name, const char *val, int lo, int hi, int *out)
{
    char *end;
    long v = val ? strtol(val, &end, 10) : 0;
    if (!val || !*val || *end || v < lo || v > hi) {
        vg_error("bench_gbuffer %s: '%s' is not an integer in [%d, %d]", name, val ? val : "", lo, hi);
        return false;
    }
    *out = (int)v;
    return true;
}

/* Returns 0 to run, 1 after --help, 2 on a bad argument. */
static int parse(int argc, char **argv, bench_opts *o)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        bool ok = true;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 1;
        } else if (!strcmp(a, "--validate")) {
            o->validate = true;
            continue;
        } else if (!strcmp(a, "--scene") && v) {
            o->scene = v;
        } else if (!strcmp(a, "--frames")) {
            ok = int_arg(a, v, 1, 100000, &o->frames);
        } else if (!strcmp(a, "--warmup")) {
            ok = int_arg(a, v, 0, 100000, &o->warmup);
        } else if (!strcmp(a, "--first")) {
            ok = int_arg(a, v, 0, 100000000, &o->first);
        } else if (!strcmp(a, "--gpu")) {
            ok = int_arg(a, v, 0, 63, &o->device);
        } else {
            vg_error("bench_gbuffer: unknown or incomplete option '%s'", a);
            usage(stderr);
            return 2;
        }
        if (!ok)
            return 2;
        i++;
    }
    return 0;
}

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

static vg_status bench_size(gpu *g, const scene *s, const bench_opts *o, uint32_t w, uint32_t h, bench_result *r)
{
    frame *f = NULL;
    vg_status st = frame_create(g, s, &(frame_desc){.width = w, .height = h}, &f);
    if (st != VG_OK)
        return st;
    frame_time_passes(f, true);
    int n = o->frames;
    double *samples = calloc((size_t)n * (RG_MAX_PASSES + 2), sizeof *samples);
    if (!samples) {
        frame_destroy(f);
        return VG_ERR_NOMEM;
    }
    double *sum = samples + (size_t)n * RG_MAX_PASSES, *wall = sum + n;
    memset(r, 0, sizeof *r);
    r->shadow_size = frame_get_desc(f)->shadow_size;
    long index = o->first;
    for (int i = 0; i < o->warmup && st == VG_OK; i++)
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

int main(int argc, char **argv)
{
    bench_opts o = {.frames = 30, .warmup = 5, .first = 90, .device = -1};
    int parsed = parse(argc, argv, &o);
    if (parsed)
        return parsed == 1 ? 0 : 2;
    /* From the project root by default; from anywhere via the source path. */
    char fallback[1024];
    if (!o.scene) {
        o.scene = "content/balloon.gltf";
        FILE *probe = fopen(o.scene, "rb");
        if (probe)
            fclose(probe);
        else
            snprintf(fallback, sizeof fallback, "%s/content/balloon.gltf", VG_SOURCE_DIR), o.scene = fallback;
    }

    scene *s = NULL;
    vg_status st = scene_load(o.scene, &s);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    gpu *g = NULL;
    st = gpu_create(&(gpu_desc){.validate = o.validate, .use_device = o.device >= 0, .device_index = o.device}, &g);
    if (st != VG_OK) {
        scene_destroy(s);
        return vg_status_exit_code(st);
    }
    printf("device: %s (%s)%s\n", g->props.deviceName, gpu_device_type_text(g->props.deviceType),
           g->validation ? "  [validation on: timings are distorted]" : "");
    if (!g->features.timestamps)
        printf("note: the device has no timestamps; pass times are NaN\n");
    printf("scene: %s (%d instances, %u triangles)\n", o.scene, s->instance_count, s->index_count / 3);
    printf("frames %d..%d after %d warm-up frame(s); medians of %d frames\n\n", o.first + o.warmup,
           o.first + o.warmup + o.frames - 1, o.warmup, o.frames);

    bench_result res[SIZES];
    for (int k = 0; k < SIZES && st == VG_OK; k++)
        st = bench_size(g, s, &o, k_sizes[k].w, k_sizes[k].h, &res[k]);
    if (st == VG_OK) {
        printf("%-11s", "size");
        for (uint32_t p = 0; p < res[0].pass_count; p++)
            printf(" %10s ms", res[0].names[p]);
        printf(" %10s ms %10s ms %8s\n", "passes", "frame wall", "of wall");
        for (int k = 0; k < SIZES; k++) {
            char size[32];
            snprintf(size, sizeof size, "%ux%u", k_sizes[k].w, k_sizes[k].h);
            printf("%-11s", size);
            for (uint32_t p = 0; p < res[k].pass_count; p++)
                printf(" %13.2f", res[k].pass_ms[p]);
            printf(" %13.2f %13.2f %7.1f%%\n", res[k].gpu_ms, res[k].wall_ms, 100 * res[k].gpu_ms / res[k].wall_ms);
        }
        printf("(shadow map %u px; passes = median over frames of the sum of the passes, by the pass clock)\n",
               res[0].shadow_size);
    } else {
        vg_error("bench_gbuffer: %s", vg_status_text(st));
    }
    gpu_destroy(g);
    scene_destroy(s);
    if (st == VG_OK && gpu_validation_messages() > 0) {
        vg_error("validation reported %d message(s)", gpu_validation_messages());
        st = VG_ERR_VALIDATION;
    }
    return vg_status_exit_code(st);
}
