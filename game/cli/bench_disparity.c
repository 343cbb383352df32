/* vergence bench disparity — the GPU disparity pipeline's cost per frame at
 * two sizes (default 960x540 and 1920x1080; issue 4): the frame graph's
 * per-pass ms (the pass clock), medians of N frames after a keyframe
 * interval of amortised solves (the two sizes rendered frame by frame in
 * turn), and wall-clock ms of the resolution-dependent passes run on their
 * own.
 *
 * At the default sizes the solver's grid is the same (192 x 108: the stride
 * widens with the frame, paper 4.5), so mid.solve should cost the same; the
 * upsampling is per output pixel, so it should grow with the pixel count.
 *
 * On lavapipe a compute pass's GPU timestamps are only meaningful when the
 * pass waits for its own work (the solver's step graphs do: every indirect
 * dispatch makes lavapipe finish what came before); the others' time shows
 * up in the next pass that waits. So the per-output-pixel passes are also
 * timed on their own, with a wait after each (wall clock).
 *
 *   vergence bench disparity [--scene FILE] [--sizes WxH,WxH] [--frames N] [--runs R]
 *
 * Not a test: figures go to docs/PERFORMANCE.md, "GPU disparity passes". */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_modes.h"
#include "core/clock.h"
#include "core/log.h"
#include "core/stats.h"
#include "disparity/gpu/disparity_gpu.h"
#include "disparity/mid_shared.h"
#include "disparity/gpu/operator_gpu.h"
#include "disparity/gpu/upsample_gpu.h"
#include "frame/frame.h"
#include "options/display_cli.h"
#include "options/gpu_cli.h"
#include "stereo/stereo_display.h"

static struct {
    const char *scene, *sizes;
    int frames, runs;
    gpu_cli gpu;
    display_cli display;
} o;

static const vg_opt k_opts[] = {
    {"--scene", VG_OPT_STRING, &o.scene, "FILE", "glTF scene (default content/balloon.gltf)", NULL, 0, 0},
    {"--sizes", VG_OPT_STRING, &o.sizes, "WxH,WxH", "the two frame sizes (default 960x540,1920x1080)", NULL, 0, 0},
    {"--frames", VG_OPT_INT, &o.frames, "N",
     "measured frames a run after a keyframe interval of warm-up; also the repetitions of each pass on its own "
     "(default 30)", NULL, 1, 10000},
    {"--runs", VG_OPT_INT, &o.runs, "R", "runs, each both sizes frame by frame in turn; medians of runs (default 3)",
     NULL, 1, 100},
    DISPLAY_CLI_OPTIONS(o.display),
    GPU_CLI_OPTIONS(o.gpu),
};

static double mean(const double *v, int n)
{
    double s = 0;
    for (int i = 0; i < n; i++)
        s += v[i];
    return n ? s / n : 0;
}

/* ------------------------------------------------------------------------- */
/* The frame                                                                 */
/* ------------------------------------------------------------------------- */

#define MAX_PASSES 64

typedef struct frame_result {
    int passes;
    char names[MAX_PASSES][48];  /* copied: the graph's names die with the frame */
    double median_ms[MAX_PASSES], mean_ms[MAX_PASSES];
    double frame_wall_ms;
} frame_result;

static int pass_index(const frame_result *r, const char *name)
{
    for (int p = 0; p < r->passes; p++)
        if (!strcmp(r->names[p], name))
            return p;
    return -1;
}

/* One run: both sizes frame by frame in turn, so both see the same load on a
 * shared machine. Frame i of size k, pass p goes to ms[(k MAX_PASSES + p) n +
 * first + i] and its wall time to wall[k n + first + i]. */
static vg_status run_frames(gpu *g, const scene *s, const uint32_t sizes[2][2], int frames, double *ms, double *wall,
                            size_t n, size_t first, frame_result *out, int *keyframe_stride)
{
    frame *f[2] = {0};
    vg_status st = VG_OK;
    /* Two real cameras: the cheapest stereo pair (the disparity passes are
     * the same whichever way the pair is made). */
    for (int k = 0; k < 2 && st == VG_OK; k++)
        st = frame_create(g, s, &(frame_desc){.width = sizes[k][0], .height = sizes[k][1],
                                              .stereo = FRAME_STEREO_CAMERAS, .mode = FRAME_MODE_OPTIMIZED,
                                              .diffuse = true, .display = display_cli_desc(&o.display)}, &f[k]);
    for (int k = 0; k < 2 && st == VG_OK; k++)
        frame_time_passes(f[k], true);
    /* Warm-up: the first frame solves its whole window, then one interval
     * of amortised solves; measured from the next keyframe on. */
    *keyframe_stride = st == VG_OK ? frame_get_desc(f[0])->keyframe_stride : 1;
    int warm = 2 * *keyframe_stride;
    for (int i = -warm; i < frames && st == VG_OK; i++)
        for (int k = 0; k < 2 && st == VG_OK; k++) {
            double t0 = vg_now_ms();
            st = frame_render(f[k], 60 + warm + i);
            if (i < 0 || st != VG_OK)
                continue;
            wall[(size_t)k * n + first + (size_t)i] = vg_now_ms() - t0;
            double row[MAX_PASSES];
            const char *names[MAX_PASSES];
            out[k].passes = (int)frame_pass_timings(f[k], names, row, MAX_PASSES);
            for (int p = 0; p < out[k].passes; p++) {
                snprintf(out[k].names[p], sizeof out[k].names[p], "%s", names[p]);
                ms[((size_t)k * MAX_PASSES + p) * n + first + (size_t)i] = row[p];
            }
        }
    frame_destroy(f[0]);
    frame_destroy(f[1]);
    return st;
}

/* The median over runs of each run's median of its frames (v: runs x frames). */
static double median_of_runs(const double *v, int runs, int frames)
{
    double *per_run = malloc((size_t)runs * sizeof *per_run);
    for (int r = 0; r < runs; r++)
        per_run[r] = vg_median(v + (size_t)r * frames, (size_t)frames, 1);
    double m = vg_median(per_run, (size_t)runs, 1);
    free(per_run);
    return m;
}

static void summarise(const double *ms, const double *wall, int runs, int frames, frame_result *out)
{
    size_t n = (size_t)runs * frames;
    for (int k = 0; k < 2; k++) {
        for (int p = 0; p < out[k].passes; p++) {
            const double *v = ms + ((size_t)k * MAX_PASSES + p) * n;
            out[k].median_ms[p] = median_of_runs(v, runs, frames);
            out[k].mean_ms[p] = mean(v, (int)n);
        }
        out[k].frame_wall_ms = median_of_runs(wall + (size_t)k * n, runs, frames);
    }
}

static double pass_ms(const frame_result *r, const char *name, bool use_mean)
{
    int p = pass_index(r, name);
    return p < 0 ? NAN : use_mean ? r->mean_ms[p] : r->median_ms[p];
}

/* ------------------------------------------------------------------------- */
/* Per-pixel passes on their own                                             */
/* ------------------------------------------------------------------------- */

typedef struct alone {
    gpu *gpu;
    uint32_t w, h, stride, nx, ny;
    upsample_gpu *ups;
    operator_gpu *op;
    gpu_buffer store, published;
    rg_res depth, motion, ids, hmap, fmap, g, color, ratio, r_store, r_pub, state;
} alone;

/* Clears the inputs: a flat scene 10 m away, h and g 300 arcmin, some motion. */
static void clear_execute(const rg_context *ctx, void *user)
{
    alone *a = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    struct { rg_res r; VkClearColorValue v; } items[] = {
        {a->depth, {.float32 = {10, 0, 0, 0}}}, {a->motion, {.float32 = {1.0f, 0.5f, -1.0f, -0.5f}}},
        {a->hmap, {.float32 = {300, 0, 0, 0}}}, {a->g, {.float32 = {300, 0, 0, 0}}},
        {a->color, {.float32 = {0, 0, 0, 0.5f}}}, {a->ids, {.uint32 = {1, 0, 0, 0}}}};
    VkImageSubresourceRange all = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (size_t i = 0; i < sizeof items / sizeof items[0]; i++)
        vkCmdClearColorImage(cmd, rg_ctx_image(ctx, items[i].r), rg_ctx_layout(ctx, items[i].r), &items[i].v, 1, &all);
}

static upsample_gpu_frame ups_frame(const alone *a)
{
    return (upsample_gpu_frame){.width = a->w, .height = a->h, .stride = a->stride, .tau = 0.3f, .has1 = true,
                           .slot0 = 0, .slot1 = 1};
}

static void time_execute(const rg_context *ctx, void *user)
{
    alone *a = user;
    upsample_gpu_frame fr = ups_frame(a);
    VkDescriptorImageInfo z = rg_ctx_image_info(ctx, a->depth);
    VkDescriptorImageInfo m = rg_ctx_image_info(ctx, a->motion);
    VkDescriptorImageInfo id = rg_ctx_image_info(ctx, a->ids);
    VkDescriptorImageInfo r = rg_ctx_image_info(ctx, a->ratio);
    VkDescriptorImageInfo g = rg_ctx_image_info(ctx, a->g);
    VkDescriptorImageInfo h = rg_ctx_image_info(ctx, a->hmap);
    upsample_gpu_record_time(a->ups, rg_ctx_cmd(ctx), &fr, &z, &m, &id, rg_ctx_buffer(ctx, a->r_store),
                             rg_ctx_buffer(ctx, a->r_pub), &g, &h, &r);
}

static void space_execute(const rg_context *ctx, void *user)
{
    alone *a = user;
    upsample_gpu_frame fr = ups_frame(a);
    VkDescriptorImageInfo h = rg_ctx_image_info(ctx, a->hmap);
    VkDescriptorImageInfo f = rg_ctx_image_info(ctx, a->fmap);
    VkDescriptorImageInfo r = rg_ctx_image_info(ctx, a->ratio);
    upsample_gpu_record_space(a->ups, rg_ctx_cmd(ctx), &fr, &h, rg_ctx_buffer(ctx, a->r_pub), &r, &f);
}

static void fit_execute(const rg_context *ctx, void *user)
{
    alone *a = user;
    VkDescriptorImageInfo g = rg_ctx_image_info(ctx, a->g), c = rg_ctx_image_info(ctx, a->color);
    operator_gpu_record_fit(a->op, rg_ctx_cmd(ctx), &g, &c, a->w, a->h);
}

static void map_execute(const rg_context *ctx, void *user)
{
    alone *a = user;
    VkDescriptorImageInfo g = rg_ctx_image_info(ctx, a->g), h = rg_ctx_image_info(ctx, a->hmap);
    operator_gpu_record_map(a->op, rg_ctx_cmd(ctx), &g, &h, a->w, a->h);
}

/* A graph of the clear and the first `passes` of: mid.upsample.time,
 * mid.upsample.space (chain 0) or disparity.operator.fit, disparity.operator
 * (chain 1). */
static rg_graph *alone_graph(alone *a, int chain, int passes)
{
    rg_graph *g = rg_create();
    a->depth = rg_image(g, &(rg_image_desc){"gbuffer.depth", VK_FORMAT_R32_SFLOAT, a->w, a->h, 1});
    a->motion = rg_image(g, &(rg_image_desc){"gbuffer.motion", VK_FORMAT_R32G32B32A32_SFLOAT, a->w, a->h, 1});
    a->ids = rg_image(g, &(rg_image_desc){"gbuffer.ids", VK_FORMAT_R32_UINT, a->w, a->h, 1});
    a->hmap = rg_image(g, &(rg_image_desc){"disparity.h", VK_FORMAT_R32_SFLOAT, a->w, a->h, 1});
    a->g = rg_image(g, &(rg_image_desc){"disparity.g", VK_FORMAT_R32_SFLOAT, a->w, a->h, 1});
    a->color = rg_image(g, &(rg_image_desc){"gbuffer.color", VK_FORMAT_R8G8B8A8_UNORM, a->w, a->h, 1});
    a->fmap = rg_image(g, &(rg_image_desc){"disparity.f", VK_FORMAT_R32_SFLOAT, a->w, a->h, 1});
    a->ratio = rg_image(g, &(rg_image_desc){"mid.ratio", VK_FORMAT_R32_SFLOAT, a->nx, a->ny, 1});
    rg_import_desc rw = {.initial = RG_STORAGE_READ_WRITE, .final = RG_STORAGE_READ_WRITE};
    a->r_store = rg_import_buffer(g, &(rg_buffer_desc){"mid.store", a->store.size}, &rw);
    a->r_pub = rg_import_buffer(g, &(rg_buffer_desc){"mid.published", a->published.size}, &rw);
    a->state = rg_import_buffer(g, &(rg_buffer_desc){"disparity.operator.state", operator_gpu_state_size(a->op)}, &rw);
    rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = "clear", .type = RG_PASS_TRANSFER, .execute = clear_execute,
                                               .user = a, .side_effects = true});
    rg_res cleared[] = {a->depth, a->motion, a->ids, a->hmap, a->g, a->color};
    for (size_t i = 0; i < sizeof cleared / sizeof cleared[0]; i++)
        rg_use(g, p, cleared[i], RG_TRANSFER_DST);
    if (chain == 0 && passes >= 1) {
        p = rg_pass_add(g, &(rg_pass_desc){.name = "mid.upsample.time", .type = RG_PASS_COMPUTE, .execute = time_execute,
                                           .user = a, .side_effects = true});
        rg_use(g, p, a->depth, RG_STORAGE_READ);
        rg_use(g, p, a->motion, RG_STORAGE_READ);
        rg_use(g, p, a->ids, RG_STORAGE_READ);
        rg_use(g, p, a->g, RG_STORAGE_READ);
        rg_use(g, p, a->hmap, RG_STORAGE_READ);
        rg_use(g, p, a->r_store, RG_STORAGE_READ);
        rg_use(g, p, a->r_pub, RG_STORAGE_READ);
        rg_use(g, p, a->ratio, RG_STORAGE_WRITE);
    }
    if (chain == 0 && passes >= 2) {
        p = rg_pass_add(g, &(rg_pass_desc){.name = "mid.upsample.space", .type = RG_PASS_COMPUTE,
                                           .execute = space_execute, .user = a, .side_effects = true});
        rg_use(g, p, a->hmap, RG_STORAGE_READ);
        rg_use(g, p, a->r_pub, RG_STORAGE_READ);
        rg_use(g, p, a->ratio, RG_STORAGE_READ);
        rg_use(g, p, a->fmap, RG_STORAGE_WRITE);
    }
    if (chain == 1 && passes >= 1) {
        p = rg_pass_add(g, &(rg_pass_desc){.name = "disparity.operator.fit", .type = RG_PASS_COMPUTE,
                                           .execute = fit_execute, .user = a, .side_effects = true});
        rg_use(g, p, a->g, RG_STORAGE_READ);
        rg_use(g, p, a->color, RG_STORAGE_READ);
        rg_use(g, p, a->state, RG_STORAGE_READ_WRITE);
    }
    if (chain == 1 && passes >= 2) {
        p = rg_pass_add(g, &(rg_pass_desc){.name = "disparity.operator", .type = RG_PASS_COMPUTE,
                                           .execute = map_execute, .user = a, .side_effects = true});
        rg_use(g, p, a->g, RG_STORAGE_READ);
        rg_use(g, p, a->state, RG_STORAGE_READ);
        rg_use(g, p, a->hmap, RG_STORAGE_WRITE);
    }
    if (rg_compile(g) != VG_OK || rg_realize(g, a->gpu) != VG_OK) {
        rg_destroy(g);
        return NULL;
    }
    rg_bind_buffer(g, a->r_store, a->store.buffer);
    rg_bind_buffer(g, a->r_pub, a->published.buffer);
    rg_bind_buffer(g, a->state, operator_gpu_state(a->op));
    return g;
}

/* Median wall ms of one graph, submitted and waited for reps times. */
static double graph_ms(gpu *g, rg_graph *graph, int reps)
{
    double *t = malloc((size_t)reps * sizeof *t);
    if (!t)
        return NAN;
    for (int i = 0; i < reps + 2; i++) {
        VkCommandBuffer cmd;
        double t0 = vg_now_ms();
        if (gpu_oneshot_begin(g, &cmd) != VG_OK)
            break;
        rg_execute(graph, cmd, 0);
        gpu_oneshot_submit(g, cmd);
        if (i >= 2)
            t[i - 2] = vg_now_ms() - t0;
    }
    double m = vg_median(t, (size_t)reps, 1);
    free(t);
    return m;
}

typedef struct alone_result {
    double time_ms, space_ms, fit_ms, map_ms;
} alone_result;

/* Each per-pixel pass's wall ms: the graph up to it minus the graph before it. */
static vg_status run_alone(gpu *g, uint32_t w, uint32_t h, uint32_t stride, int reps, alone_result *out)
{
    stereo_display disp;
    stereo_display_desc display = display_cli_desc(&o.display);
    stereo_display_init(&disp, &display);
    alone a = {.gpu = g, .w = w, .h = h, .stride = stride, .nx = (w + stride - 1) / stride, .ny = (h + stride - 1) / stride};
    size_t ns = (size_t)a.nx * a.ny;
    vg_status st = upsample_gpu_create(g, &a.ups);
    if (st == VG_OK)
        st = operator_gpu_create(g, &(operator_gpu_desc){.op = {.kind = DISP_OPERATOR_LANG, .screen_vergence = disp.screen_vergence},
                                             .stride = stride}, &a.op);
    if (st == VG_OK)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "store", .size = 2 * MID_STORE_FLOATS * ns * sizeof(float),
                                                     .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true},
                               &a.store);
    if (st == VG_OK)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "published", .size = sizeof(mid_published) + 2 * ns * sizeof(float),
                                                     .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true},
                               &a.published);
    if (st != VG_OK) {
        upsample_gpu_destroy(a.ups);
        operator_gpu_destroy(a.op);
        gpu_buffer_destroy(g, &a.store);
        gpu_buffer_destroy(g, &a.published);
        return st;
    }
    float *sf = a.store.mapped, *pf = (float *)((mid_published *)a.published.mapped + 1);
    for (size_t i = 0; i < 2 * MID_STORE_FLOATS * ns; i++)
        sf[i] = 10.0f;
    for (size_t i = 0; i < 2 * ns; i++)
        pf[i] = 1.0f + 0.01f * (float)(i % 7);
    *(mid_published *)a.published.mapped = (mid_published){.range_lo = 200, .range_hi = 360};
    double base[2] = {0}, one[2] = {0}, two[2] = {0};
    for (int chain = 0; chain < 2; chain++) {
        rg_graph *g0 = alone_graph(&a, chain, 0), *g1 = alone_graph(&a, chain, 1), *g2 = alone_graph(&a, chain, 2);
        if (g0 && g1 && g2) {
            base[chain] = graph_ms(g, g0, reps);
            one[chain] = graph_ms(g, g1, reps);
            two[chain] = graph_ms(g, g2, reps);
        }
        rg_destroy(g0);
        rg_destroy(g1);
        rg_destroy(g2);
    }
    *out = (alone_result){one[0] - base[0], two[0] - one[0], one[1] - base[1], two[1] - one[1]};
    upsample_gpu_destroy(a.ups);
    operator_gpu_destroy(a.op);
    gpu_buffer_destroy(g, &a.store);
    gpu_buffer_destroy(g, &a.published);
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Report                                                                    */
/* ------------------------------------------------------------------------- */

/* Both sizes' frames over all runs, then the per-pixel passes on their own. */
static vg_status report(gpu *g, const scene *s, const char *scene_path, const uint32_t sizes[2][2], int frames,
                        int runs)
{
    frame_result fr[2] = {0};
    alone_result ar[2];
    char size_name[2][32];
    uint32_t grid[2][2];
    for (int k = 0; k < 2; k++) {
        uint32_t stride = disparity_gpu_grid_stride(sizes[k][0], sizes[k][1], 0);
        snprintf(size_name[k], sizeof size_name[k], "%ux%u", sizes[k][0], sizes[k][1]);
        grid[k][0] = (sizes[k][0] + stride - 1) / stride, grid[k][1] = (sizes[k][1] + stride - 1) / stride;
    }
    vg_info("bench: %s and %s in turn, %d runs of %d frames of %s", size_name[0], size_name[1], runs, frames,
            scene_path);
    /* All runs' frames, run by run: ms[k][p][r * frames + i]. */
    size_t n = (size_t)runs * frames;
    double *ms = calloc(2 * n * MAX_PASSES, sizeof *ms), *wall = calloc(2 * n, sizeof *wall);
    double *solve_ratio = calloc((size_t)runs, sizeof *solve_ratio);
    vg_status st = ms && wall && solve_ratio ? VG_OK : VG_ERR_NOMEM;
    for (int r = 0; r < runs && st == VG_OK; r++) {
        int kstride;
        size_t first = (size_t)r * frames;
        st = run_frames(g, s, sizes, frames, ms, wall, n, first, fr, &kstride);
        if (st != VG_OK)
            break;
        /* The solve of whole keyframe intervals (the run starts at a keyframe):
         * what it costs at each size, side by side in this run. */
        double sum[2] = {0};
        for (int k = 0; k < 2; k++) {
            int p = pass_index(&fr[k], "mid.solve");
            int whole = frames < kstride ? frames : frames - frames % kstride;
            for (int i = 0; p >= 0 && i < whole; i++)
                sum[k] += ms[((size_t)k * MAX_PASSES + p) * n + first + (size_t)i];
        }
        solve_ratio[r] = sum[0] > 0 ? sum[1] / sum[0] : NAN;
        vg_info("run %d/%d: mid.solve %.1f vs %.1f ms over the run (x%.3f)", r + 1, runs, sum[0], sum[1], solve_ratio[r]);
    }
    for (int k = 0; k < 2 && st == VG_OK; k++)
        st = run_alone(g, sizes[k][0], sizes[k][1], disparity_gpu_grid_stride(sizes[k][0], sizes[k][1], 0), frames,
                       &ar[k]);
    if (st != VG_OK) {
        free(ms);
        free(wall);
        free(solve_ratio);
        return st;
    }
    summarise(ms, wall, runs, frames, fr);
    printf("vergence bench disparity: %s on %s (%s): GPU ms per pass of the frame graph,\n"
           "median of %d frames (median of %d runs) and mean of all\n", scene_path,
           g->props.deviceName, gpu_device_type_text(g->props.deviceType), frames, runs);
    printf("%-24s %18s %18s\n", "pass", size_name[0], size_name[1]);
    for (int p = 0; p < fr[0].passes; p++)
        printf("%-24s %9.2f (%6.2f) %9.2f (%6.2f)\n", fr[0].names[p], fr[0].median_ms[p], fr[0].mean_ms[p],
               pass_ms(&fr[1], fr[0].names[p], false), pass_ms(&fr[1], fr[0].names[p], true));
    printf("%-24s %9.1f          %9.1f\n", "frame (wall ms)", fr[0].frame_wall_ms, fr[1].frame_wall_ms);
    double mean_sum[2] = {0, 0};
    for (int k = 0; k < 2; k++)
        for (int p = 0; p < fr[k].passes; p++)
            mean_sum[k] += fr[k].mean_ms[p];
    printf("%-24s %9.1f          %9.1f\n", "all passes (mean ms)", mean_sum[0], mean_sum[1]);
    printf("%-24s %8.1f%%          %8.1f%%\n", "passes / frame wall", 100 * mean_sum[0] / mean(wall, (int)n),
           100 * mean_sum[1] / mean(wall + n, (int)n));
    printf("\nper-pixel passes on their own, wall ms (median of %d):\n", frames);
    const char *what[4] = {"mid.upsample.time", "mid.upsample.space", "disparity.operator.fit", "disparity.operator"};
    double v0[4] = {ar[0].time_ms, ar[0].space_ms, ar[0].fit_ms, ar[0].map_ms};
    double v1[4] = {ar[1].time_ms, ar[1].space_ms, ar[1].fit_ms, ar[1].map_ms};
    for (int i = 0; i < 4; i++)
        printf("%-24s %9.2f          %9.2f   x%.2f\n", what[i], v0[i], v1[i], v1[i] / v0[i]);
    double s0 = pass_ms(&fr[0], "mid.solve", true), s1 = pass_ms(&fr[1], "mid.solve", true);
    double m0 = pass_ms(&fr[0], "mid.solve", false), m1 = pass_ms(&fr[1], "mid.solve", false);
    printf("\nmid.solve per frame (grid %ux%u vs %ux%u): median %.2f vs %.2f ms (%+.1f %%), mean %.2f vs %.2f ms "
           "(%+.1f %%)\n", grid[0][0], grid[0][1], grid[1][0], grid[1][1], m0, m1, 100.0 * (m1 - m0) / m0, s0, s1,
           100.0 * (s1 - s0) / s0);
    printf("mid.solve over whole keyframe intervals, %s / %s side by side in each run:", size_name[1], size_name[0]);
    for (int r = 0; r < runs; r++)
        printf(" x%.3f", solve_ratio[r]);
    double ratio = vg_median(solve_ratio, (size_t)runs, 1);
    printf("; median x%.3f (%+.1f %%)\n", ratio, 100.0 * (ratio - 1.0));
    double up0 = ar[0].time_ms + ar[0].space_ms, up1 = ar[1].time_ms + ar[1].space_ms;
    printf("upsampling (time + space): %.2f vs %.2f ms: x%.2f for x%.2f pixels\n", up0, up1, up1 / up0,
           (double)sizes[1][0] * sizes[1][1] / ((double)sizes[0][0] * sizes[0][1]));
    free(ms);
    free(wall);
    free(solve_ratio);
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* The mode                                                                  */
/* ------------------------------------------------------------------------- */

static int run(int argc, char **argv)
{
    memset(&o, 0, sizeof o);
    o.scene = "content/balloon.gltf";
    o.sizes = "960x540,1920x1080";
    o.frames = 30;
    o.runs = 3;
    o.gpu.device = -1;
    bool help = false;
    if (vg_cli_parse(&vg_cmd_bench_disparity, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    uint32_t sizes[2][2];
    if (!bench_parse_sizes(vg_cmd_bench_disparity.name, o.sizes, sizes))
        return 2;
    vg_status st = display_cli_load(&o.display);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    const char *scene_path = o.scene;
    int frames = o.frames, runs = o.runs;
    scene *s;
    st = scene_load(scene_path, &s);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    gpu *g;
    st = gpu_cli_open(&o.gpu, false, &g);
    if (st != VG_OK) {
        scene_destroy(s);
        return vg_status_exit_code(st);
    }
    st = report(g, s, scene_path, sizes, frames, runs);
    if (st != VG_OK)
        vg_error("bench disparity: %s", vg_status_text(st));
    scene_destroy(s);
    return gpu_cli_close(g, st);
}

const vg_cmd vg_cmd_bench_disparity = {
    .name = "bench disparity",
    .summary = "the GPU disparity passes at two sizes: the solve flat in output resolution, the upsampling per pixel",
    .usage = "vergence bench disparity [--scene FILE] [--sizes WxH,WxH] [--frames N] [--runs R]",
    .details = "Renders a two-camera stereo pair (the disparity passes do not depend on how it is made) at\n"
               "both sizes frame by frame in turn and prints the frame graph's ms per pass, medians of N\n"
               "frames after a keyframe interval of warm-up (median of R runs) and means of all; then the\n"
               "per-pixel passes timed on their own (wall ms, a wait after each: lavapipe's timestamps time\n"
               "only the passes that wait for their own work), and the solve's and the upsampling's growth\n"
               "from the first size to the second.",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
