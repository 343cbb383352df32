/* vergence — disparity passes on the GPU: the frame's disparity pipeline. */
#include "disparity_gpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "gpu/pipeline.h"
#include "disparity/mid_shared.h"
#include "disparity/mid_window.h"
#include "operator_gpu.h"
#include "original_gpu.h"
#include "shared.h"
#include "solve_gpu.h"
#include "upsample_gpu.h"

/* The solver's grid never exceeds this (paper 4.5: its resolution is chosen
 * by content, not by the screen, so the solve takes the same time at any
 * output resolution); 960 x 540 at the default stride of 5. */
#define GRID_MAX_X 192
#define GRID_MAX_Y 108

struct disparity_gpu {
    disparity_gpu_desc desc;
    gpu *gpu;
    original_gpu original;            /* disparity.original */
    operator_gpu *op;
    solve_gpu *mid;
    upsample_gpu *ups;
    gpu_buffer store, published;

    uint32_t stride, nx, ny, ns;
    int past, future, ring, interval; /* window keyframes behind / ahead; ring slots; frames per keyframe */
    bool causal;                      /* the future keyframes are predictions, rendered again at each move */
    double lo, hi;
    solve_gpu_params solve;              /* the current window's */

    /* this frame's graph resources */
    rg_graph *graph;
    frame_resources *res;
    rg_res state, r_store, r_published, arena, args, ratio;
    disparity_gpu_atlas atlas;
    int slot;                         /* this frame's in flight */

    /* timeline */
    bool started;
    long first_kf, cur_k;             /* history starts at first_kf; the frame is in interval cur_k */
    long win_first;                   /* the window's first keyframe */
    int *slice;                       /* interval + 1 item boundaries of the amortised solve */
    long last_index;                  /* the frame rendered last */
    long store_hi, final_hi;          /* newest keyframe in the store; newest whose ratio is final */
    int done;                         /* items of the current solve recorded so far */
    int frames_in;                    /* frames rendered since the window moved (budgeted) */
    int tail_first, tail_last;        /* the last solve's items this frame (before the build) */
    bool tail_publish;                /* ... then its publish step (budgeted: the solve as it stands) */
    bool build;                       /* mid.window runs this frame */
    int rec_first, rec_last;          /* mid.solve's items this frame */
    long tiles_first;                 /* keyframes rendered this frame */
    int tiles;
    upsample_gpu_frame up;
};

uint32_t disparity_gpu_grid_stride(uint32_t width, uint32_t height, int coarse_stride)
{
    uint32_t s = coarse_stride > 0 ? (uint32_t)coarse_stride : MID_COARSE_STRIDE;
    while ((width + s - 1) / s > GRID_MAX_X || (height + s - 1) / s > GRID_MAX_Y)
        s++;
    return s;
}

static uint32_t ring_slot(const disparity_gpu *d, long kf)
{
    long r = kf % d->ring;
    return (uint32_t)(r < 0 ? r + d->ring : r);
}

/* ------------------------------------------------------------------------- */
/* Passes                                                                    */
/* ------------------------------------------------------------------------- */

static void original_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    VkDescriptorImageInfo src = rg_ctx_image_info(ctx, d->res->depth), dst = rg_ctx_image_info(ctx, d->res->g);
    original_gpu_record(d->gpu, &d->original, rg_ctx_cmd(ctx), rg_ctx_buffer(ctx, d->res->ubo), &src, &dst,
                        d->desc.width, d->desc.height);
}

static void fit_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    VkDescriptorImageInfo g = rg_ctx_image_info(ctx, d->res->g), c = rg_ctx_image_info(ctx, d->res->color);
    operator_gpu_record_fit(d->op, rg_ctx_cmd(ctx), &g, &c, d->desc.width, d->desc.height);
}

static void map_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    VkDescriptorImageInfo g = rg_ctx_image_info(ctx, d->res->g), h = rg_ctx_image_info(ctx, d->res->h);
    operator_gpu_record_map(d->op, rg_ctx_cmd(ctx), &g, &h, d->desc.width, d->desc.height);
}

static operator_gpu_tiles tiles_of(disparity_gpu *d, const rg_context *ctx, VkDescriptorImageInfo *img)
{
    img[0] = rg_ctx_image_info(ctx, d->atlas.depth);
    img[1] = rg_ctx_image_info(ctx, d->atlas.color);
    img[2] = rg_ctx_image_info(ctx, d->atlas.motion);
    img[3] = rg_ctx_image_info(ctx, d->atlas.ids);
    return (operator_gpu_tiles){.ubo = rg_ctx_buffer(ctx, d->res->ubo), .depth = &img[0], .color = &img[1],
                          .motion = &img[2], .ids = &img[3], .tiles = (uint32_t)d->tiles, .tile_w = d->nx, .tile_h = d->ny,
                          .store = rg_ctx_buffer(ctx, d->r_store), .store_first = ring_slot(d, d->tiles_first),
                          .store_cap = (uint32_t)d->ring};
}

static void tiles_fit_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    VkDescriptorImageInfo img[4];
    operator_gpu_tiles t = tiles_of(d, ctx, img);
    if (d->tiles > 0)
        operator_gpu_record_tiles_fit(d->op, rg_ctx_cmd(ctx), &t);
}

static void tiles_store_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    VkDescriptorImageInfo img[4];
    operator_gpu_tiles t = tiles_of(d, ctx, img);
    if (d->tiles > 0)
        operator_gpu_record_tiles_store(d->op, rg_ctx_cmd(ctx), &t);
}

static void window_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    uint32_t slot = (uint32_t)d->slot;
    solve_gpu_record_previous(d->mid, rg_ctx_cmd(ctx), slot, d->tail_first, d->tail_last);
    if (d->tail_publish) {
        int n = solve_gpu_previous_item_count(d->mid);
        solve_gpu_record_previous(d->mid, rg_ctx_cmd(ctx), slot, n - 1, n);
    }
    if (d->build)
        solve_gpu_record(d->mid, rg_ctx_cmd(ctx), slot, 0, 1);
}

static void solve_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    solve_gpu_record(d->mid, rg_ctx_cmd(ctx), (uint32_t)d->slot, d->rec_first, d->rec_last);
}

static void time_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    VkDescriptorImageInfo z = rg_ctx_image_info(ctx, d->res->depth), m = rg_ctx_image_info(ctx, d->res->motion);
    VkDescriptorImageInfo ids = rg_ctx_image_info(ctx, d->res->ids), ratio = rg_ctx_image_info(ctx, d->ratio);
    VkDescriptorImageInfo g = rg_ctx_image_info(ctx, d->res->g), h = rg_ctx_image_info(ctx, d->res->h);
    upsample_gpu_record_time(d->ups, rg_ctx_cmd(ctx), &d->up, &z, &m, &ids, rg_ctx_buffer(ctx, d->r_store),
                             rg_ctx_buffer(ctx, d->r_published), &g, &h, &ratio);
}

static void space_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    VkDescriptorImageInfo h = rg_ctx_image_info(ctx, d->res->h);
    VkDescriptorImageInfo f = rg_ctx_image_info(ctx, d->res->f);
    VkDescriptorImageInfo ratio = rg_ctx_image_info(ctx, d->ratio);
    upsample_gpu_record_space(d->ups, rg_ctx_cmd(ctx), &d->up, &h, rg_ctx_buffer(ctx, d->r_published), &ratio, &f);
}

static rg_pass compute_pass(rg_graph *g, const char *name, rg_execute_fn fn, disparity_gpu *d)
{
    return rg_pass_add(g, &(rg_pass_desc){.name = name, .type = RG_PASS_COMPUTE, .execute = fn, .user = d});
}

static void add_keyframes(disparity_gpu *d, rg_graph *g, const frame_resources *res)
{
    rg_pass p = compute_pass(g, "mid.keyframes.fit", tiles_fit_execute, d);
    rg_use(g, p, res->ubo, RG_UNIFORM);
    rg_use(g, p, d->atlas.depth, RG_STORAGE_READ);
    rg_use(g, p, d->atlas.color, RG_STORAGE_READ);
    rg_use(g, p, d->state, RG_STORAGE_READ_WRITE);
    p = compute_pass(g, "mid.keyframes.store", tiles_store_execute, d);
    rg_use(g, p, res->ubo, RG_UNIFORM);
    rg_use(g, p, d->atlas.depth, RG_STORAGE_READ);
    rg_use(g, p, d->atlas.motion, RG_STORAGE_READ);
    rg_use(g, p, d->atlas.ids, RG_STORAGE_READ);
    rg_use(g, p, d->state, RG_STORAGE_READ);
    rg_use(g, p, d->r_store, RG_STORAGE_READ_WRITE);
}

void disparity_gpu_add(disparity_gpu *d, rg_graph *g, frame_resources *res, const disparity_gpu_atlas *atlas)
{
    uint32_t w = d->desc.width, h = d->desc.height;
    rg_import_desc rw = {.initial = RG_STORAGE_READ_WRITE, .final = RG_STORAGE_READ_WRITE};
    d->res = res;
    d->atlas = atlas ? *atlas : (disparity_gpu_atlas){.color = {0}};
    if (!res->g.id)
        res->g = rg_image(g, &(rg_image_desc){"disparity.g", VK_FORMAT_R32_SFLOAT, w, h, 1});
    if (!res->h.id)
        res->h = rg_image(g, &(rg_image_desc){"disparity.h", VK_FORMAT_R32_SFLOAT, w, h, 1});
    d->state = rg_import_buffer(g, &(rg_buffer_desc){"disparity.operator.state", operator_gpu_state_size(d->op)}, &rw);
    d->r_store = rg_import_buffer(g, &(rg_buffer_desc){"mid.store", d->store.size}, &rw);
    d->r_published = rg_import_buffer(g, &(rg_buffer_desc){"mid.published", d->published.size}, &rw);
    d->arena = rg_import_buffer(g, &(rg_buffer_desc){"mid.arena", solve_gpu_arena_size(d->mid)}, &rw);
    d->args = rg_import_buffer(g, &(rg_buffer_desc){"mid.args", MID_ARGS_COUNT * 12},
                               &(rg_import_desc){.initial = RG_INDIRECT, .final = RG_INDIRECT});
    d->ratio = rg_image(g, &(rg_image_desc){"mid.ratio", VK_FORMAT_R32_SFLOAT, d->nx, d->ny, 1});

    rg_pass p = compute_pass(g, "disparity.original", original_execute, d);
    rg_use(g, p, res->ubo, RG_UNIFORM);
    rg_use(g, p, res->depth, RG_STORAGE_READ);
    rg_use(g, p, res->g, RG_STORAGE_WRITE);
    /* Step 5: the keyframe window; the keyframes entering it (rendered into
     * the atlas before) come first, as a frame's mapping blends with its
     * keyframe's (lang-smoothed). */
    if (d->desc.keyframes)
        add_keyframes(d, g, res);
    /* Step 4: h = M(g, saliency). */
    p = compute_pass(g, "disparity.operator.fit", fit_execute, d);
    rg_use(g, p, res->g, RG_STORAGE_READ);
    rg_use(g, p, res->color, RG_STORAGE_READ);
    rg_use(g, p, d->state, RG_STORAGE_READ_WRITE);
    p = compute_pass(g, "disparity.operator", map_execute, d);
    rg_use(g, p, res->g, RG_STORAGE_READ);
    rg_use(g, p, d->state, RG_STORAGE_READ);
    rg_use(g, p, res->h, RG_STORAGE_WRITE);
    d->graph = g;
    /* Steps 6 and 7 only where f is shown or measured: a frame showing g or
     * h (the game's other modes, and their maps alone) leaves the solve out. */
    if (!d->desc.f || !d->desc.keyframes)
        return;
    if (!res->f.id)
        res->f = rg_image(g, &(rg_image_desc){"disparity.f", VK_FORMAT_R32_SFLOAT, w, h, 1});
    /* The last window's unfinished items (frames were skipped), then the
     * new window's build. */
    p = compute_pass(g, "mid.window", window_execute, d);
    rg_use(g, p, d->r_store, RG_STORAGE_READ);
    rg_use(g, p, d->arena, RG_STORAGE_READ_WRITE);
    rg_use(g, p, d->args, RG_STORAGE_READ_WRITE);
    rg_use(g, p, d->r_published, RG_STORAGE_READ_WRITE);
    /* Step 6: the solve, and the publication of its ratios. */
    p = compute_pass(g, "mid.solve", solve_execute, d);
    rg_use(g, p, d->arena, RG_STORAGE_READ_WRITE);
    rg_use(g, p, d->args, RG_STORAGE_READ_WRITE);
    rg_use(g, p, d->r_published, RG_STORAGE_READ_WRITE);
    /* Step 7: f for this frame. */
    p = compute_pass(g, "mid.upsample.time", time_execute, d);
    rg_use(g, p, res->depth, RG_STORAGE_READ);
    rg_use(g, p, res->motion, RG_STORAGE_READ);
    rg_use(g, p, res->ids, RG_STORAGE_READ);
    rg_use(g, p, res->g, RG_STORAGE_READ);
    rg_use(g, p, res->h, RG_STORAGE_READ);
    rg_use(g, p, d->r_store, RG_STORAGE_READ);
    rg_use(g, p, d->r_published, RG_STORAGE_READ);
    rg_use(g, p, d->ratio, RG_STORAGE_WRITE);
    p = compute_pass(g, "mid.upsample.space", space_execute, d);
    rg_use(g, p, res->h, RG_STORAGE_READ);
    rg_use(g, p, d->r_published, RG_STORAGE_READ);
    rg_use(g, p, d->ratio, RG_STORAGE_READ);
    rg_use(g, p, res->f, RG_STORAGE_WRITE);
}

/* ------------------------------------------------------------------------- */
/* Timeline                                                                  */
/* ------------------------------------------------------------------------- */

/* A new window [win_first, k + future]: its solve starts from the last one
 * (paper 4.5) shifted by the keyframes the window slid. */
static void window_begin(disparity_gpu *d, long k, bool restart)
{
    long prev_first = d->win_first;
    int prev_nt = d->solve.keyframes;
    d->win_first = restart ? k : (k - d->past > d->first_kf ? k - d->past : d->first_kf);
    const disparity_gpu_desc *fd = &d->desc;
    d->solve = (solve_gpu_params){
        .keyframes = (int)(k + d->future - d->win_first + 1),
        .range_lo = (float)d->lo, .range_hi = (float)d->hi, .range_hull = fd->op == DISP_OPERATOR_NONE,
        .gather = true, .keyframe_seconds = (float)(fd->keyframe_stride / fd->fps),
        .store_first = ring_slot(d, d->win_first), .store_cap = (uint32_t)d->ring,
        .solver = fd->solver,
        .iterations = fd->solver_iterations ? fd->solver_iterations
                      : !restart && fd->solver == MID_SOLVER_GAUSS_NEWTON ? (int)MID_GN_WARM_ITERATIONS : 0,
        .warm = !restart, .shift = (int)(d->win_first - prev_first), .prev_keyframes = restart ? 0 : prev_nt,
        .publish = true,
        /* Keyframes k and k + 1 were already used as the ends of a keyframe
         * interval: publishing them again would make f jump (a pop). */
        .publish_from = restart ? 0 : (int)(k + 2 - d->win_first),
        /* A predicted future: keyframe k - 1 is realized (mid_shared.h MID_GATE_*). */
        .gate = d->causal, .gate_keyframe = restart ? -1 : (int)(k - 1 - d->win_first),
    };
    solve_gpu_begin(d->mid, &d->solve);
}

/* Items of the solve (after the build) spread over the interval's frames by
 * estimated cost: each frame does about the same share (amortised). */
static void slices_plan(disparity_gpu *d)
{
    int n = solve_gpu_item_count(d->mid);
    double total = 0, at = 0;
    for (int i = 1; i < n; i++)
        total += solve_gpu_item_cost(d->mid, i);
    int s = 0;
    d->slice[0] = 1;
    for (int i = 1; i < n; i++) {
        double c = solve_gpu_item_cost(d->mid, i);
        int want = total > 0 ? (int)((at + 0.5 * c) / total * d->interval) : 0;
        want = want >= d->interval ? d->interval - 1 : want;
        while (s < want)
            d->slice[++s] = i;
        at += c;
    }
    while (s < d->interval)
        d->slice[++s] = n;
}

vg_status disparity_gpu_prepare(disparity_gpu *d, long index, int slot)
{
    d->slot = slot;
    long k = frame_keyframe_of(index, d->interval);
    int phase = (int)(index - k * d->interval);
    d->build = false;
    d->rec_first = d->rec_last = 0;
    d->tail_first = d->tail_last = 0;
    d->tail_publish = false;
    d->tiles = 0;
    if (d->started && index == d->last_index) {
        /* The same frame again (a pause that keeps drawing, a display faster
         * than the frame rate, a redraw): its work was recorded once, and
         * nothing it reads has changed since, so f is the same. */
    } else if (!d->started || index < d->last_index || k > d->cur_k + 1) {
        /* No history, or a jump back or past the window (a seek, a replay
         * restart): the window starts here, and the frame waits for its
         * whole solve (once). */
        d->started = true;
        d->first_kf = d->cur_k = k;
        d->tiles_first = k;
        d->tiles = d->future + 1;
        operator_gpu_reset(d->op);
        window_begin(d, k, true);
        d->build = true;
        d->rec_first = 1;
        d->done = d->rec_last = solve_gpu_item_count(d->mid);
        for (int s = 0; s <= d->interval; s++)
            d->slice[s] = d->rec_last; /* nothing more in this interval */
    } else {
        if (k == d->cur_k + 1) {
            /* The window slides by one keyframe: the newest predicted
             * keyframe enters, the oldest leaves. The last window's solve
             * is finished first (the items of frames that were not
             * rendered), so what it published is a finished solve and the
             * new one starts from it. */
            d->tail_first = d->done;
            d->tail_last = solve_gpu_item_count(d->mid);
            d->final_hi = d->cur_k + 2;
            d->cur_k = k;
            if (d->causal) {
                /* Causal: keyframe k is observed now (the scene up to this
                 * frame), and every later one is predicted again from it. */
                d->tiles_first = k;
                d->tiles = d->future + 1;
                operator_gpu_tiles_chain(d->op, ring_slot(d, k - 1));
            } else {
                d->tiles_first = k + d->future;
                d->tiles = 1;
            }
            window_begin(d, k, false);
            if (d->desc.budgeted) {
                /* The last solve as it stands: at least
                 * MID_GN_BUDGET_ITERATIONS and the iteration under way
                 * finished, then its publish. */
                int n = solve_gpu_previous_item_count(d->mid);
                d->tail_last = solve_gpu_previous_settled(d->mid, d->tail_first, MID_GN_BUDGET_ITERATIONS);
                d->tail_publish = d->tail_last < n;
            }
            slices_plan(d);
            d->build = true;
            d->done = 1;
            d->frames_in = 0;
        }
        /* Every item due by this phase, also those of skipped phases; with
         * a budget, one phase's share a rendered frame. */
        int due = d->desc.budgeted ? (d->frames_in < d->interval ? d->frames_in : d->interval - 1) : phase;
        d->frames_in++;
        d->rec_first = d->done;
        d->rec_last = d->slice[due + 1] > d->done ? d->slice[due + 1] : d->done;
        d->done = d->rec_last;
    }
    d->last_index = index;
    /* lang-smoothed: h from keyframe k's mapping and this frame alone
     * (without keyframes, from the last frame's). */
    if (d->desc.keyframes)
        operator_gpu_frame_anchor(d->op, ring_slot(d, k), phase);
    else
        d->tiles = 0;
    if (d->tiles > 0)
        d->store_hi = d->tiles_first + d->tiles - 1;
    /* A finished solve of interval k publishes keyframes k + 2 on (its first
     * window: k on); later windows publish from k + 3: k + 2 is final. */
    if (d->done >= solve_gpu_item_count(d->mid))
        d->final_hi = d->cur_k + 2;
    if (d->graph)
        disparity_gpu_bind(d, d->graph);
    /* Where this frame is between keyframes k and k + 1 (Fig. 4). */
    d->up = (upsample_gpu_frame){
        .width = d->desc.width, .height = d->desc.height, .stride = d->stride,
        .tau = (float)phase / (float)d->interval, .at_key = phase == 0, .has1 = true,
        .slot0 = ring_slot(d, k), .slot1 = ring_slot(d, k + 1), .slots = (uint32_t)d->ring,
        .span = (float)(d->desc.keyframe_stride / d->desc.fps),
        .depth_only = d->desc.temporal_depth_only,
    };
    return VG_OK;
}

void disparity_gpu_bind(disparity_gpu *d, rg_graph *g)
{
    d->graph = g;
    rg_bind_buffer(g, d->state, operator_gpu_state(d->op));
    rg_bind_buffer(g, d->r_store, d->store.buffer);
    rg_bind_buffer(g, d->r_published, d->published.buffer);
    rg_bind_buffer(g, d->arena, solve_gpu_arena(d->mid));
    rg_bind_buffer(g, d->args, solve_gpu_args(d->mid));
}

void disparity_gpu_restart(disparity_gpu *d) { d->started = false; }

void disparity_gpu_atlas_matrix(const disparity_gpu *d, int tile, float m[16])
{
    double w = d->desc.width, h = d->desc.height, s = d->stride, half = floor(s / 2.0) + 0.5;
    double nx = d->nx, ny = d->ny, rows = (double)d->ny * (d->future + 1);
    memset(m, 0, 16 * sizeof(float));
    m[0] = (float)(w / (nx * s));
    m[5] = (float)(h / (s * rows));
    m[10] = m[15] = 1.0f;
    m[12] = (float)(2.0 / nx * ((w / 2.0 - half) / s + 0.5) - 1.0);
    m[13] = (float)(2.0 / rows * ((h / 2.0 - half) / s + 0.5 + tile * ny) - 1.0);
}

void disparity_gpu_keyframes(const disparity_gpu *d, long *first, int *count)
{
    *first = d->tiles_first;
    *count = d->tiles;
}

/* ------------------------------------------------------------------------- */
/* Lifetime                                                                  */
/* ------------------------------------------------------------------------- */

disparity_gpu_desc disparity_gpu_desc_defaults(const disparity_gpu_desc *desc)
{
    disparity_gpu_desc d = *desc;
    if (!(d.fps > 0))
        d.fps = MID_FPS;
    if (d.keyframe_stride <= 0)
        d.keyframe_stride = MID_KEYFRAME_STRIDE;
    if (d.coarse_stride <= 0)
        d.coarse_stride = MID_COARSE_STRIDE;
    if (!(d.window_seconds > 0))
        d.window_seconds = MID_WINDOW_SECONDS;
    if (!(d.window_future > 0) || d.window_future >= 1)
        d.window_future = MID_WINDOW_FUTURE;
    d.op = disp_operator_desc_defaults(&(disp_operator_desc){.kind = d.op}).kind;
    if (d.solver == MID_SOLVER_DEFAULT)
        d.solver = MID_SOLVER_GAUSS_NEWTON;
    return d;
}

vg_status disparity_gpu_create(const disparity_gpu_desc *desc, disparity_gpu **out)
{
    *out = NULL;
    disparity_gpu *d = calloc(1, sizeof *d);
    if (!d)
        return VG_ERR_NOMEM;
    d->desc = disparity_gpu_desc_defaults(desc);
    const disparity_gpu_desc *fd = &d->desc;
    gpu *g = d->gpu = fd->gpu;
    uint32_t s = d->stride = disparity_gpu_grid_stride(fd->width, fd->height, fd->coarse_stride);
    d->nx = (fd->width + s - 1) / s;
    d->ny = (fd->height + s - 1) / s;
    d->ns = d->nx * d->ny;
    d->interval = fd->keyframe_stride;
    d->causal = fd->causal;
    mid_window_split(fd->window_seconds, fd->keyframe_stride / fd->fps, fd->window_future, &d->past, &d->future);
    if (d->past + d->future + 1 > (int)MID_MAX_KEYFRAMES) {
        vg_error("a %.1f s window is %d keyframes (at most %u)", fd->window_seconds, d->past + d->future + 1,
                 MID_MAX_KEYFRAMES);
        free(d);
        return VG_ERR_ARG;
    }
    d->ring = d->past + d->future + 2;
    d->slice = calloc((size_t)d->interval + 1, sizeof(int));
    vg_status st = d->slice ? VG_OK : VG_ERR_NOMEM;
    if (st == VG_OK)
        st = original_gpu_create(g, &d->original);
    if (st == VG_OK)
        st = operator_gpu_create(g, &(operator_gpu_desc){
            .op = {.kind = fd->op, .preset = fd->op_preset, .screen_vergence = fd->screen_vergence,
                   .range = fd->target_range, .frame_seconds = 1.0 / fd->fps},
            .keyframe_seconds = fd->keyframe_stride / fd->fps, .stride = s,
            .max_tiles = (uint32_t)d->future + 1, .ring = (uint32_t)d->ring, .no_saliency = fd->no_saliency}, &d->op);
    if (st == VG_OK)
        operator_gpu_range(d->op, &d->lo, &d->hi);
    VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    if (st == VG_OK)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "mid.store",
                                                     .size = (VkDeviceSize)d->ring * MID_STORE_FLOATS * d->ns * sizeof(float),
                                                     .usage = usage, .host_visible = fd->readback}, &d->store);
    if (st == VG_OK)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "mid.published",
                                                     .size = sizeof(mid_published) + 3 * (VkDeviceSize)d->ring * d->ns * sizeof(float),
                                                     .usage = usage, .host_visible = fd->readback}, &d->published);
    if (st == VG_OK)
        st = solve_gpu_create(g, &(solve_gpu_desc){.nx = (int)d->nx, .ny = (int)d->ny,
                                               .max_keyframes = d->past + d->future + 1,
                                               .store = d->store.buffer, .published = d->published.buffer,
                                               .store_size = d->store.size, .published_size = d->published.size},
                            &d->mid);
    if (st == VG_OK)
        st = upsample_gpu_create(g, &d->ups);
    if (st != VG_OK) {
        disparity_gpu_destroy(d);
        return st;
    }
    *out = d;
    return VG_OK;
}

void disparity_gpu_destroy(disparity_gpu *d)
{
    if (!d)
        return;
    gpu *g = d->gpu;
    upsample_gpu_destroy(d->ups);
    solve_gpu_destroy(d->mid);
    operator_gpu_destroy(d->op);
    gpu_buffer_destroy(g, &d->store);
    gpu_buffer_destroy(g, &d->published);
    original_gpu_destroy(g, &d->original);
    free(d->slice);
    free(d);
}

void disparity_gpu_get_info(const disparity_gpu *d, disparity_gpu_info *info)
{
    *info = (disparity_gpu_info){.stride = d->stride, .nx = d->nx, .ny = d->ny, .past = d->past,
                                 .future = d->future, .max_tiles = (uint32_t)d->future + 1, .range_lo = d->lo, .range_hi = d->hi,
                                 .items = solve_gpu_item_count(d->mid)};
}

void disparity_gpu_keyframe_free(disparity_gpu_keyframe *k)
{
    if (!k)
        return;
    free(k->g);
    *k = (disparity_gpu_keyframe){0};
}

vg_status disparity_gpu_keyframe_read(const disparity_gpu *d, long keyframe, disparity_gpu_keyframe *out)
{
    if (!d->store.mapped || !d->published.mapped) {
        vg_error("the solve's keyframes are read back only from a frame with readback");
        return VG_ERR_ARG;
    }
    /* Causal: keyframe K's samples are predictions until interval K. */
    if (!d->started || keyframe < d->first_kf || keyframe > d->store_hi || keyframe <= d->store_hi - d->ring ||
        keyframe > d->final_hi || (d->causal && keyframe > d->cur_k)) {
        vg_error("keyframe %ld is not in the store with a final ratio (store %ld..%ld, final up to %ld)", keyframe,
                 d->store_hi - d->ring + 1 > d->first_kf ? d->store_hi - d->ring + 1 : d->first_kf, d->store_hi,
                 d->final_hi);
        return VG_ERR_ARG;
    }
    size_t ns = d->ns;
    if (out->ns != (int)ns) {
        disparity_gpu_keyframe_free(out);
        float *mem = malloc(9 * ns * sizeof(float));
        if (!mem)
            return VG_ERR_NOMEM;
        *out = (disparity_gpu_keyframe){.ns = (int)ns, .g = mem, .h = mem + ns, .f = mem + 2 * ns,
                                        .depth = mem + 3 * ns, .id = mem + 4 * ns, .flow_fwd = mem + 5 * ns,
                                        .flow_bwd = mem + 7 * ns};
    }
    uint32_t slot = ring_slot(d, keyframe);
    const float *st = (const float *)d->store.mapped + (size_t)slot * MID_STORE_FLOATS * ns;
    const mid_published *pub = d->published.mapped;
    const float *ratio = (const float *)(pub + 1) + (size_t)slot * ns;
    memcpy(out->g, st + MID_STORE_G * ns, ns * sizeof(float));
    memcpy(out->h, st + MID_STORE_H * ns, ns * sizeof(float));
    memcpy(out->depth, st + MID_STORE_DEPTH * ns, ns * sizeof(float));
    memcpy(out->id, st + MID_STORE_ID * ns, ns * sizeof(float));
    memcpy(out->flow_fwd, st + MID_STORE_FLOW_F * ns, 2 * ns * sizeof(float));
    memcpy(out->flow_bwd, st + MID_STORE_FLOW_B * ns, 2 * ns * sizeof(float));
    /* f as the upsampling makes it at the keyframe's samples (Fig. 4): the
     * published correction is f / g (f / h under the causal gate). */
    for (size_t q = 0; q < ns; q++) {
        float f = (pub->of_h ? out->h[q] : out->g[q]) * ratio[q];
        if (pub->range_hi > pub->range_lo)
            f = fminf(fmaxf(f, pub->range_lo), pub->range_hi);
        out->f[q] = f;
    }
    return VG_OK;
}
