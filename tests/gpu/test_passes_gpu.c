/* vergence — GPU passes against their CPU reference on the same inputs
 * (issue 4: max |GPU - CPU| < 0.05 arcmin): the operators, upsampling and
 * the global curve. Run one case: test_passes_gpu NAME. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "disparity/disp_curve.h"
#include "vergence/curve.h"
#include "disparity/disp_operator.h"
#include "disparity/disp_upsample.h"
#include "disparity/mid_shared.h"
#include "disparity/gpu/operator_gpu.h"
#include "disparity/gpu/upsample_gpu.h"
#include "disparity/testlib.h"
#include "gpu/pipeline.h"
#include "harness.h"
#include "shared.h"

#include "curve_bins_comp.h"
#include "curve_range_comp.h"
#include "curve_resolve_comp.h"
#include "stereo/stereo_display.h"
#include "test.h"

#define AGREEMENT_ARCMIN 0.05

/* ------------------------------------------------------------------------- */
/* Operators                                                                 */
/* ------------------------------------------------------------------------- */

#define OP_W 160
#define OP_H 90

/* Layers at several vergences, a ramp, a disc that moves with the frame
 * number, and 8-bit saliency (as the G-buffer stores it). */
static void op_inputs(int frame, float *g, uint8_t *rgba, float *sal)
{
    unsigned s = 17u + (unsigned)frame;
    for (int y = 0; y < OP_H; y++)
        for (int x = 0; x < OP_W; x++) {
            int i = y * OP_W + x;
            double v = y < OP_H / 3 ? 205.0 + 0.2 * x : y < 2 * OP_H / 3 ? 290.0 + 0.05 * y : 330.0 + 0.3 * x;
            double dx = x - (40 + 6 * frame), dy = y - 45;
            bool disc = dx * dx + dy * dy < 150;
            if (disc)
                v = 380.0 - 4.0 * frame;
            g[i] = (float)(v + rnd_uniform(&s, -0.5f, 0.5f));
            int a = disc ? 255 : (x * 7 + y * 3) % 60;
            sal[i] = (float)a / 255.0f;
            rgba[4 * i + 3] = (uint8_t)a;
        }
}

typedef struct op_test {
    operator_gpu *o;
    rg_res g, color, h, state;
    uint32_t w, hgt;
} op_test;

static void op_fit_execute(const rg_context *ctx, void *user)
{
    op_test *t = user;
    VkDescriptorImageInfo g = rg_ctx_image_info(ctx, t->g), c = rg_ctx_image_info(ctx, t->color);
    operator_gpu_record_fit(t->o, rg_ctx_cmd(ctx), &g, &c, t->w, t->hgt);
}

static void op_map_execute(const rg_context *ctx, void *user)
{
    op_test *t = user;
    VkDescriptorImageInfo g = rg_ctx_image_info(ctx, t->g), h = rg_ctx_image_info(ctx, t->h);
    operator_gpu_record_map(t->o, rg_ctx_cmd(ctx), &g, &h, t->w, t->hgt);
}

static int operator_agrees(disp_operator_kind kind, int frames)
{
    stereo_display disp;
    stereo_display_init(&disp, &(stereo_display_desc){0});
    disp_operator_desc od = {.kind = kind, .screen_vergence = disp.screen_vergence};
    disp_operator *cpu;
    CHECK(disp_operator_create(&od, &cpu) == VG_OK, "CPU operator");
    harness hs;
    CHECK(harness_open(&hs) == 0, "harness");
    op_test t = {.w = OP_W, .hgt = OP_H};
    CHECK(operator_gpu_create(hs.gpu, &(operator_gpu_desc){.op = od, .stride = 1}, &t.o) == VG_OK, "GPU operator");
    t.g = harness_image_add(&hs, "g", VK_FORMAT_R32_SFLOAT, OP_W, OP_H, true, false);
    t.color = harness_image_add(&hs, "color", VK_FORMAT_R8G8B8A8_UNORM, OP_W, OP_H, true, false);
    t.h = harness_image_add(&hs, "h", VK_FORMAT_R32_SFLOAT, OP_W, OP_H, false, true);
    CHECK(harness_upload(&hs) == 0, "upload");
    rg_import_desc rw = {.initial = RG_STORAGE_READ_WRITE, .final = RG_STORAGE_READ_WRITE};
    t.state = rg_import_buffer(hs.graph, &(rg_buffer_desc){"operator.state", operator_gpu_state_size(t.o)}, &rw);
    rg_pass fit = rg_pass_add(hs.graph, &(rg_pass_desc){.name = "disparity.operator.fit", .type = RG_PASS_COMPUTE,
                                                         .execute = op_fit_execute, .user = &t});
    rg_use(hs.graph, fit, t.g, RG_STORAGE_READ);
    rg_use(hs.graph, fit, t.color, RG_STORAGE_READ);
    rg_use(hs.graph, fit, t.state, RG_STORAGE_READ_WRITE);
    rg_pass map = rg_pass_add(hs.graph, &(rg_pass_desc){.name = "disparity.operator", .type = RG_PASS_COMPUTE,
                                                         .execute = op_map_execute, .user = &t});
    rg_use(hs.graph, map, t.g, RG_STORAGE_READ);
    rg_use(hs.graph, map, t.state, RG_STORAGE_READ);
    rg_use(hs.graph, map, t.h, RG_STORAGE_WRITE);
    CHECK(harness_build(&hs) == 0, "graph");
    rg_bind_buffer(hs.graph, t.state, operator_gpu_state(t.o));
    float *g = malloc(OP_W * OP_H * sizeof(float)), *sal = malloc(OP_W * OP_H * sizeof(float));
    float *h = malloc(OP_W * OP_H * sizeof(float));
    double worst = 0, moved = 0;
    for (int f = 0; f < frames; f++) {
        op_inputs(f, g, harness_data(&hs, t.color), sal);
        memcpy(harness_data(&hs, t.g), g, OP_W * OP_H * sizeof(float));
        disp_operator_apply(cpu, g, sal, OP_W * OP_H, h, NULL);
        CHECK(harness_run(&hs) == 0, "run");
        const float *hg = harness_data(&hs, t.h);
        double frame_worst = 0;
        for (int i = 0; i < OP_W * OP_H; i++) {
            frame_worst = fmax(frame_worst, fabs((double)hg[i] - h[i]));
            moved = fmax(moved, fabs((double)h[i] - g[i]));
        }
        printf("%s frame %d: max |h_gpu - h_cpu| %.3g arcmin\n", disp_operator_kind_name(kind), f, frame_worst);
        worst = fmax(worst, frame_worst);
    }
    printf("%s: max |h_gpu - h_cpu| %.3g arcmin over %d frames (h departs from g by up to %.1f arcmin)\n",
           disp_operator_kind_name(kind), worst, frames, moved);
    CHECK(worst < AGREEMENT_ARCMIN, "GPU and CPU operators differ by %.3g arcmin", worst);
    CHECK(kind == DISP_OPERATOR_NONE || moved > 10, "the operator must compress for the test to mean something");
    free(g);
    free(sal);
    free(h);
    operator_gpu_destroy(t.o);
    disp_operator_destroy(cpu);
    CHECK(harness_close(&hs) == 0, "validation messages");
    return 0;
}

static int operator_none(void) { return operator_agrees(DISP_OPERATOR_NONE, 1); }
static int operator_linear(void) { return operator_agrees(DISP_OPERATOR_LINEAR, 2); }
static int operator_lang(void) { return operator_agrees(DISP_OPERATOR_LANG, 2); }
static int operator_lang_smoothed(void) { return operator_agrees(DISP_OPERATOR_LANG_SMOOTHED, 4); }


/* ------------------------------------------------------------------------- */
/* Upsampling                                                                */
/* ------------------------------------------------------------------------- */

#define UP_W 160
#define UP_H 90
#define UP_STRIDE 5

typedef struct up_test {
    upsample_gpu *u;
    upsample_gpu_frame fr;
    rg_res depth, motion, ids, g, h, f, ratio, store, published;
} up_test;

static void up_time_execute(const rg_context *ctx, void *user)
{
    up_test *t = user;
    VkDescriptorImageInfo d = rg_ctx_image_info(ctx, t->depth);
    VkDescriptorImageInfo m = rg_ctx_image_info(ctx, t->motion);
    VkDescriptorImageInfo id = rg_ctx_image_info(ctx, t->ids);
    VkDescriptorImageInfo r = rg_ctx_image_info(ctx, t->ratio);
    VkDescriptorImageInfo g = rg_ctx_image_info(ctx, t->g);
    VkDescriptorImageInfo h = rg_ctx_image_info(ctx, t->h);
    upsample_gpu_record_time(t->u, rg_ctx_cmd(ctx), &t->fr, &d, &m, &id, rg_ctx_buffer(ctx, t->store),
                             rg_ctx_buffer(ctx, t->published), &g, &h, &r);
}

static void up_space_execute(const rg_context *ctx, void *user)
{
    up_test *t = user;
    VkDescriptorImageInfo h = rg_ctx_image_info(ctx, t->h);
    VkDescriptorImageInfo f = rg_ctx_image_info(ctx, t->f);
    VkDescriptorImageInfo r = rg_ctx_image_info(ctx, t->ratio);
    upsample_gpu_record_space(t->u, rg_ctx_cmd(ctx), &t->fr, &h, rg_ctx_buffer(ctx, t->published), &r, &f);
}

/* A frame between two keyframes: a far slanted background, a near box and a
 * disc that move (some pixels leave the frame), keyframe depths that differ
 * where the frame disoccludes, smooth keyframe ratios. */
static void up_inputs(float *depth, float *motion, float *h, uint32_t *ids, const disp_grid *grid, float *z0,
                      float *z1, float *r0, float *r1, float *id0, float *id1, float *fl0, float *fl1)
{
    unsigned s = 5u;
    for (int y = 0; y < UP_H; y++)
        for (int x = 0; x < UP_W; x++) {
            int i = y * UP_W + x;
            bool box = x >= 40 && x < 80 && y >= 20 && y < 60;
            double dx = x - 120, dy = y - 40;
            bool disc = dx * dx + dy * dy < 300;
            depth[i] = disc ? 6.0f : box ? 3.0f : 20.0f + 0.05f * (float)y;
            float *m = motion + 4 * (size_t)i;
            m[0] = disc ? 8.0f : box ? -3.0f : 0.0f;
            m[1] = disc ? -2.0f : 0.0f;
            m[2] = disc ? 40.0f : box ? 4.0f : 0.0f; /* the disc leaves the frame towards k1 */
            m[3] = disc ? 3.0f : box ? 1.0f : 0.0f;
            h[i] = (float)(330.0 - 300.0 / depth[i] + rnd_uniform(&s, -1.0f, 1.0f) + 2.0 * sin(0.3 * x));
            ids[i] = disc ? 2u : box ? 1u : 0u;
        }
    for (int q = 0; q < grid->nx * grid->ny; q++) {
        int qx = q % grid->nx, qy = q / grid->nx;
        float zc = depth[disp_grid_py(grid, qy) * UP_W + disp_grid_px(grid, qx)];
        z0[q] = qx > 20 && qx < 24 ? zc * 1.6f : zc; /* disoccluded strip in k0 */
        z1[q] = qy < 3 ? zc * 0.5f : zc;
        r0[q] = (float)(1.0 + 0.06 * sin(0.2 * qx + 0.3 * qy));
        r1[q] = (float)(1.0 + 0.05 * cos(0.25 * qx - 0.1 * qy));
        /* The keyframes' instances (another one on a strip of k1) and their
         * flows to each other in coarse px: the box's along its motion (its
         * trajectory test passes where a depth test would not), the rest
         * still, a band of k0 astray. */
        uint32_t idq = ids[disp_grid_py(grid, qy) * UP_W + disp_grid_px(grid, qx)];
        id0[q] = (float)idq;
        id1[q] = qx > 10 && qx < 13 ? 5.0f : (float)idq;
        bool box = idq == 1u;
        fl0[2 * q] = box ? 7.0f / UP_STRIDE : qy > 12 && qy < 15 ? 2.5f : 0.0f;
        fl0[2 * q + 1] = box ? 1.0f / UP_STRIDE : 0.0f;
        fl1[2 * q] = box ? -7.0f / UP_STRIDE : 0.0f;
        fl1[2 * q + 1] = box ? -1.0f / UP_STRIDE : 0.0f;
        if (box)
            z1[q] = zc * 1.5f; /* the box moves away fast: no depth test passes at k1 */
    }
}

static int upsample_agrees(float tau, bool at_key)
{
    disp_grid grid;
    disp_grid_init(&grid, UP_W, UP_H, UP_STRIDE);
    int nc = grid.nx * grid.ny, np = UP_W * UP_H;
    float *depth = malloc(np * sizeof(float)), *motion = malloc(4 * (size_t)np * sizeof(float));
    float *h = malloc(np * sizeof(float)), *f = malloc(np * sizeof(float)), *flow = malloc(2 * (size_t)np * sizeof(float));
    float *g = malloc(np * sizeof(float)), *gc = malloc(nc * sizeof(float)), *hc = malloc(nc * sizeof(float));
    float *z0 = malloc(nc * sizeof(float)), *z1 = malloc(nc * sizeof(float)), *r0 = malloc(nc * sizeof(float));
    float *r1 = malloc(nc * sizeof(float)), *zc = malloc(nc * sizeof(float)), *rt = malloc(nc * sizeof(float));
    float *s0 = malloc(nc * sizeof(float)), *s1 = malloc(nc * sizeof(float));
    float *id0 = malloc(nc * sizeof(float)), *id1 = malloc(nc * sizeof(float)), *idc = malloc(nc * sizeof(float));
    float *fl0 = malloc(2 * (size_t)nc * sizeof(float)), *fl1 = malloc(2 * (size_t)nc * sizeof(float));
    uint32_t *ids = malloc(np * sizeof(uint32_t));
    const float span = 1.0f / 6.0f;
    float *pos0 = malloc(2 * (size_t)nc * sizeof(float)), *pos1 = malloc(2 * (size_t)nc * sizeof(float));
    up_inputs(depth, motion, h, ids, &grid, z0, z1, r0, r1, id0, id1, fl0, fl1);
    /* The original: not a multiple of h, so the correction's move from
     * f / g to f / h (mid_ratio_to_h) is checked too. */
    for (int i = 0; i < np; i++)
        g[i] = h[i] * (float)(1.0 + 0.03 * sin(0.07 * (i % UP_W) + 0.11 * (i / UP_W)));
    disp_grid_sample(&grid, g, 1, gc);
    disp_grid_sample(&grid, h, 1, hc);
    for (int q = 0; q < nc; q++)
        idc[q] = (float)ids[disp_grid_py(&grid, q / grid.nx) * UP_W + disp_grid_px(&grid, q % grid.nx)];
    for (int q = 0; q < nc; q++) { /* slopes per second: up to 0.05 of the ratio over the interval */
        s0[q] = (float)(0.3 * sin(0.15 * (q % grid.nx) - 0.2 * (q / grid.nx)));
        s1[q] = (float)(-0.25 * cos(0.1 * (q % grid.nx) + 0.3 * (q / grid.nx)));
    }
    /* CPU: positions tracked by one step of the flow to each keyframe. */
    disp_upsample_desc ud = {.grid = grid, .range_lo = 200, .range_hi = 345};
    disp_grid_sample(&grid, depth, 1, zc);
    disp_grid_positions(&grid, pos0);
    disp_grid_positions(&grid, pos1);
    for (int c = 0; c < 2 && !at_key; c++) {
        for (int i = 0; i < np; i++) {
            flow[2 * i] = motion[4 * i + 2 * c];
            flow[2 * i + 1] = motion[4 * i + 2 * c + 1];
        }
        disp_flow_advect(flow, UP_W, UP_H, c ? pos1 : pos0, nc);
    }
    /* The keyframes' own g and h (their f / h where no tap is the sample's
     * surface): this frame's, shifted apart. */
    float *gk = malloc(2 * (size_t)nc * sizeof(float)), *hk = malloc(2 * (size_t)nc * sizeof(float));
    for (int q = 0; q < nc; q++)
        for (int k = 0; k < 2; k++) {
            gk[k * nc + q] = gc[q] + (k ? 1.5f : -1.0f);
            hk[k * nc + q] = hc[q] + (k ? 0.5f : -2.0f);
        }
    disp_keyframe_view k0 = {pos0, r0, s0, z0, id0, fl0, gk, hk};
    disp_keyframe_view k1 = {pos1, r1, s1, z1, id1, fl1, gk + nc, hk + nc};
    disp_upsample_temporal(&ud, tau, span, zc, idc, gc, hc, &k0, at_key ? NULL : &k1, rt, NULL);
    disp_upsample_spatial(&ud, h, rt, f, NULL);

    harness hs;
    CHECK(harness_open(&hs) == 0, "harness");
    up_test t = {.fr = {.width = UP_W, .height = UP_H, .stride = UP_STRIDE, .tau = tau, .at_key = at_key,
                        .has1 = true, .slot0 = 1, .slot1 = 0, .slots = 2, .span = span}};
    CHECK(upsample_gpu_create(hs.gpu, &t.u) == VG_OK, "GPU upsampling");
    t.depth = harness_image_add(&hs, "depth", VK_FORMAT_R32_SFLOAT, UP_W, UP_H, true, false);
    t.motion = harness_image_add(&hs, "motion", VK_FORMAT_R32G32B32A32_SFLOAT, UP_W, UP_H, true, false);
    t.ids = harness_image_add(&hs, "ids", VK_FORMAT_R32_UINT, UP_W, UP_H, true, false);
    t.g = harness_image_add(&hs, "g", VK_FORMAT_R32_SFLOAT, UP_W, UP_H, true, false);
    t.h = harness_image_add(&hs, "h", VK_FORMAT_R32_SFLOAT, UP_W, UP_H, true, false);
    t.f = harness_image_add(&hs, "f", VK_FORMAT_R32_SFLOAT, UP_W, UP_H, false, true);
    CHECK(harness_upload(&hs) == 0, "upload");
    /* The keyframe store and the published ratios and slopes, two ring slots each. */
    gpu_buffer store, pub;
    size_t store_floats = 2 * MID_STORE_FLOATS * (size_t)nc;
    CHECK(gpu_buffer_create(hs.gpu, &(gpu_buffer_desc){.name = "store", .size = store_floats * sizeof(float),
                                                        .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true},
                            &store) == VG_OK, "store");
    CHECK(gpu_buffer_create(hs.gpu, &(gpu_buffer_desc){.name = "published", .size = sizeof(mid_published) + 4 * nc * sizeof(float),
                                                        .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true},
                            &pub) == VG_OK, "published");
    float *sf = store.mapped, *pr = (float *)((mid_published *)pub.mapped + 1);
    memcpy(sf + (1 * MID_STORE_FLOATS + MID_STORE_G) * (size_t)nc, gk, nc * sizeof(float));
    memcpy(sf + (1 * MID_STORE_FLOATS + MID_STORE_H) * (size_t)nc, hk, nc * sizeof(float));
    memcpy(sf + (0 * MID_STORE_FLOATS + MID_STORE_G) * (size_t)nc, gk + nc, nc * sizeof(float));
    memcpy(sf + (0 * MID_STORE_FLOATS + MID_STORE_H) * (size_t)nc, hk + nc, nc * sizeof(float));
    memcpy(sf + (1 * MID_STORE_FLOATS + MID_STORE_DEPTH) * (size_t)nc, z0, nc * sizeof(float));
    memcpy(sf + (0 * MID_STORE_FLOATS + MID_STORE_DEPTH) * (size_t)nc, z1, nc * sizeof(float));
    memcpy(sf + (1 * MID_STORE_FLOATS + MID_STORE_ID) * (size_t)nc, id0, nc * sizeof(float));
    memcpy(sf + (0 * MID_STORE_FLOATS + MID_STORE_ID) * (size_t)nc, id1, nc * sizeof(float));
    memcpy(sf + (1 * MID_STORE_FLOATS + MID_STORE_FLOW_F) * (size_t)nc, fl0, 2 * nc * sizeof(float));
    memcpy(sf + (0 * MID_STORE_FLOATS + MID_STORE_FLOW_B) * (size_t)nc, fl1, 2 * nc * sizeof(float));
    memcpy(pr + nc, r0, nc * sizeof(float));
    memcpy(pr, r1, nc * sizeof(float));
    memcpy(pr + 3 * (size_t)nc, s0, nc * sizeof(float));
    memcpy(pr + 2 * (size_t)nc, s1, nc * sizeof(float));
    *(mid_published *)pub.mapped = (mid_published){.range_lo = ud.range_lo, .range_hi = ud.range_hi};
    rg_import_desc rw = {.initial = RG_STORAGE_READ_WRITE, .final = RG_STORAGE_READ_WRITE};
    t.store = rg_import_buffer(hs.graph, &(rg_buffer_desc){"mid.store", store.size}, &rw);
    t.published = rg_import_buffer(hs.graph, &(rg_buffer_desc){"mid.published", pub.size}, &rw);
    t.ratio = rg_image(hs.graph, &(rg_image_desc){"mid.ratio", VK_FORMAT_R32_SFLOAT, grid.nx, grid.ny, 1});
    rg_pass time = rg_pass_add(hs.graph, &(rg_pass_desc){.name = "mid.upsample.time", .type = RG_PASS_COMPUTE,
                                                          .execute = up_time_execute, .user = &t});
    rg_use(hs.graph, time, t.depth, RG_STORAGE_READ);
    rg_use(hs.graph, time, t.motion, RG_STORAGE_READ);
    rg_use(hs.graph, time, t.ids, RG_STORAGE_READ);
    rg_use(hs.graph, time, t.g, RG_STORAGE_READ);
    rg_use(hs.graph, time, t.h, RG_STORAGE_READ);
    rg_use(hs.graph, time, t.store, RG_STORAGE_READ);
    rg_use(hs.graph, time, t.published, RG_STORAGE_READ);
    rg_use(hs.graph, time, t.ratio, RG_STORAGE_WRITE);
    rg_pass space = rg_pass_add(hs.graph, &(rg_pass_desc){.name = "mid.upsample.space", .type = RG_PASS_COMPUTE,
                                                           .execute = up_space_execute, .user = &t});
    rg_use(hs.graph, space, t.h, RG_STORAGE_READ);
    rg_use(hs.graph, space, t.published, RG_STORAGE_READ);
    rg_use(hs.graph, space, t.ratio, RG_STORAGE_READ);
    rg_use(hs.graph, space, t.f, RG_STORAGE_WRITE);
    CHECK(harness_build(&hs) == 0, "graph");
    rg_bind_buffer(hs.graph, t.store, store.buffer);
    rg_bind_buffer(hs.graph, t.published, pub.buffer);
    memcpy(harness_data(&hs, t.depth), depth, np * sizeof(float));
    memcpy(harness_data(&hs, t.motion), motion, 4 * (size_t)np * sizeof(float));
    memcpy(harness_data(&hs, t.ids), ids, np * sizeof(uint32_t));
    memcpy(harness_data(&hs, t.g), g, np * sizeof(float));
    memcpy(harness_data(&hs, t.h), h, np * sizeof(float));
    CHECK(harness_run(&hs) == 0, "run");
    const float *fg = harness_data(&hs, t.f);
    double worst = 0, corr = 0;
    int at = 0, clamped = 0;
    for (int i = 0; i < np; i++) {
        double e = fabs((double)fg[i] - f[i]);
        if (e > worst) {
            worst = e;
            at = i;
        }
        corr = fmax(corr, fabs((double)f[i] - h[i]));
        clamped += f[i] == ud.range_lo || f[i] == ud.range_hi;
    }
    printf("upsampling tau %.2f%s: max |f_gpu - f_cpu| %.3g arcmin at (%d, %d): %.4f vs %.4f; correction up to %.1f arcmin, %d clamped\n",
           tau, at_key ? " (keyframe)" : "", worst, at % UP_W, at / UP_W, fg[at], f[at], corr, clamped);
    CHECK(worst < AGREEMENT_ARCMIN, "GPU and CPU upsampling differ by %.3g arcmin", worst);
    upsample_gpu_destroy(t.u);
    gpu_buffer_destroy(hs.gpu, &store);
    gpu_buffer_destroy(hs.gpu, &pub);
    CHECK(harness_close(&hs) == 0, "validation messages");
    free(depth); free(motion); free(h); free(f); free(flow); free(z0); free(z1); free(r0); free(r1);
    free(zc); free(rt); free(pos0); free(pos1); free(s0); free(s1);
    free(id0); free(id1); free(idc); free(fl0); free(fl1); free(ids); free(g); free(gc); free(hc); free(gk); free(hk);
    return 0;
}

static int upsample_between(void) { return upsample_agrees(0.3f, false); }
static int upsample_late(void) { return upsample_agrees(0.8f, false); }
static int upsample_keyframe(void) { return upsample_agrees(0.0f, true); }


/* ------------------------------------------------------------------------- */
/* Global curve                                                              */
/* ------------------------------------------------------------------------- */

#define CV_W 320
#define CV_H 180
#define CV_FAR 150.0f
#define CV_TILE 64 /* = curve.glsl */

typedef struct curve_test {
    gpu *gpu;
    VkDescriptorSetLayout set;
    VkPipelineLayout layout;
    VkPipeline pipe[4]; /* range per tile, range over the tiles, bins, resolve */
    rg_res depth, target, curve, count, sum, offset;
    uint32_t tiles_x, tiles_y;
} curve_test;

/* warp.curve's three passes, dispatched as warp_gpu.c does (its shaders,
 * bindings and push constants; the module itself needs a whole frame). */
static void curve_execute(const rg_context *ctx, void *user, int which)
{
    curve_test *t = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    VkDescriptorImageInfo depth = rg_ctx_image_info(ctx, t->depth), target = rg_ctx_image_info(ctx, t->target);
    VkDescriptorBufferInfo b[4] = {{rg_ctx_buffer(ctx, t->curve), 0, VK_WHOLE_SIZE}, {rg_ctx_buffer(ctx, t->count), 0, VK_WHOLE_SIZE},
                                   {rg_ctx_buffer(ctx, t->sum), 0, VK_WHOLE_SIZE}, {rg_ctx_buffer(ctx, t->offset), 0, VK_WHOLE_SIZE}};
    VkWriteDescriptorSet w[6];
    for (uint32_t i = 0; i < 6; i++) {
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = i, .descriptorCount = 1,
                                      .descriptorType = i < 2 ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
        if (i < 2)
            w[i].pImageInfo = i ? &target : &depth;
        else
            w[i].pBufferInfo = &b[i - 2];
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, t->pipe[which == 0 ? 0 : which + 1]);
    t->gpu->cmd_push_descriptor_set(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, t->layout, 0, which == 2 ? 4 : 6,
                                    which == 2 ? w + 2 : w);
    struct { float far_depth; uint32_t tiles_x, tiles_y, pad; } pc = {CV_FAR, t->tiles_x, t->tiles_y, 0};
    vkCmdPushConstants(cmd, t->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
    if (which == 2) {
        vkCmdDispatch(cmd, 1, 1, 1);
        return;
    }
    vkCmdDispatch(cmd, t->tiles_x, t->tiles_y, 1);
    if (which == 0) { /* the range: per tile, then over the tiles (the shader's other specialisation) */
        /* The test's own graph pass runs both stages (the engine's are two steps). */
        VkMemoryBarrier2 mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                               .srcStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                               .srcAccessMask = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                               .dstStageMask = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                               .dstAccessMask = VK_ACCESS_2_SHADER_STORAGE_READ_BIT};
        vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                       .memoryBarrierCount = 1, .pMemoryBarriers = &mb});
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, t->pipe[1]);
        vkCmdDispatch(cmd, 1, 1, 1);
    }
}

static void curve_range_execute(const rg_context *ctx, void *user) { curve_execute(ctx, user, 0); }
static void curve_bins_execute(const rg_context *ctx, void *user) { curve_execute(ctx, user, 1); }
static void curve_resolve_execute(const rg_context *ctx, void *user) { curve_execute(ctx, user, 2); }

/* A frame's (depth, target) pairs as a target map makes them: a ground plane
 * (3-40 m down the image), boxes at 8-12 m, sky; the target is a compressive
 * mapping of depth with a correction per object and a gradient inside the
 * ground, so several vergences share a depth (as f's do). */
static void curve_inputs(float *depth, float *target)
{
    for (int y = 0; y < CV_H; y++)
        for (int x = 0; x < CV_W; x++) {
            int i = y * CV_W + x;
            float z = y < 50 ? CV_FAR : 3.0f + 37.0f * powf((float)(CV_H - 1 - y) / (CV_H - 51), 2.0f);
            float corr = 0.0f;
            for (int b = 0; b < 4; b++) {
                int bx = 30 + 75 * b;
                if (x >= bx && x < bx + 40 && y >= 70 && y < 120) {
                    z = 8.0f + 1.3f * (float)b;
                    corr = 2.5f * (float)(b - 1.5f);
                }
            }
            depth[i] = z;
            double a = 2.0 * atan(0.065 / (2.0 * z)) * STEREO_ARCMIN_PER_RAD;
            target[i] = (float)(220.0 + 40.0 * tanh((a - 280.0) / 120.0) + corr + 0.01 * (x - CV_W / 2));
        }
}

static int curve_agrees(void)
{
    harness hs;
    CHECK(harness_open(&hs) == 0, "harness");
    curve_test t = {.gpu = hs.gpu, .tiles_x = (CV_W + CV_TILE - 1) / CV_TILE, .tiles_y = (CV_H + CV_TILE - 1) / CV_TILE};
    static const VkDescriptorType types[6] = {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                              VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                              VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    CHECK(gpu_push_layout_create(hs.gpu, "curve test", types, 6, VK_SHADER_STAGE_COMPUTE_BIT, 16, &t.set, &t.layout) == VG_OK,
          "layout");
    const uint32_t *code[4] = {spv_curve_range_comp, spv_curve_range_comp, spv_curve_bins_comp, spv_curve_resolve_comp};
    size_t size[4] = {sizeof spv_curve_range_comp, sizeof spv_curve_range_comp, sizeof spv_curve_bins_comp,
                      sizeof spv_curve_resolve_comp};
    for (uint32_t i = 0; i < 4; i++) {
        VkShaderModule m;
        uint32_t stage = i; /* the range's STAGE: 0 per tile, 1 over the tiles */
        VkSpecializationMapEntry entry = {0, 0, sizeof stage};
        VkSpecializationInfo spec = {1, &entry, sizeof stage, &stage};
        CHECK(gpu_shader_create(hs.gpu, code[i], size[i], "curve", &m) == VG_OK, "shader");
        CHECK(gpu_compute_pipeline_create(hs.gpu, t.layout, m, i < 2 ? &spec : NULL, "curve", &t.pipe[i]) == VG_OK,
              "pipeline");
        vkDestroyShaderModule(hs.gpu->device, m, NULL);
    }
    t.depth = harness_image_add(&hs, "depth", VK_FORMAT_R32_SFLOAT, CV_W, CV_H, true, false);
    t.target = harness_image_add(&hs, "target", VK_FORMAT_R32_SFLOAT, CV_W, CV_H, true, false);
    CHECK(harness_upload(&hs) == 0, "upload");
    gpu_buffer out;
    CHECK(gpu_buffer_create(hs.gpu, &(gpu_buffer_desc){.name = "curve", .size = sizeof(vgx_curve_data),
                                                        .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true},
                            &out) == VG_OK, "curve buffer");
    t.curve = rg_import_buffer(hs.graph, &(rg_buffer_desc){"warp.curve", sizeof(vgx_curve_data)},
                               &(rg_import_desc){.initial = RG_STORAGE_READ_WRITE, .final = RG_HOST_READ});
    uint64_t tiles = (uint64_t)t.tiles_x * t.tiles_y * VGX_CURVE_BINS * 4;
    t.count = rg_buffer(hs.graph, &(rg_buffer_desc){"tile_count", tiles});
    t.sum = rg_buffer(hs.graph, &(rg_buffer_desc){"tile_sum", tiles});
    t.offset = rg_buffer(hs.graph, &(rg_buffer_desc){"tile_offset", tiles});
    rg_pass range = rg_pass_add(hs.graph, &(rg_pass_desc){.name = "warp.curve.range", .type = RG_PASS_COMPUTE,
                                                           .execute = curve_range_execute, .user = &t});
    rg_use(hs.graph, range, t.depth, RG_STORAGE_READ);
    rg_use(hs.graph, range, t.target, RG_STORAGE_READ);
    rg_use(hs.graph, range, t.curve, RG_STORAGE_WRITE);
    rg_use(hs.graph, range, t.count, RG_STORAGE_WRITE); /* the tiles' ranges, read back in the pass */
    rg_pass bins = rg_pass_add(hs.graph, &(rg_pass_desc){.name = "warp.curve.bins", .type = RG_PASS_COMPUTE,
                                                          .execute = curve_bins_execute, .user = &t});
    rg_use(hs.graph, bins, t.depth, RG_STORAGE_READ);
    rg_use(hs.graph, bins, t.target, RG_STORAGE_READ);
    rg_use(hs.graph, bins, t.curve, RG_STORAGE_READ);
    rg_use(hs.graph, bins, t.count, RG_STORAGE_WRITE);
    rg_use(hs.graph, bins, t.sum, RG_STORAGE_WRITE);
    rg_use(hs.graph, bins, t.offset, RG_STORAGE_WRITE);
    rg_pass resolve = rg_pass_add(hs.graph, &(rg_pass_desc){.name = "warp.curve.resolve", .type = RG_PASS_COMPUTE,
                                                             .execute = curve_resolve_execute, .user = &t});
    rg_use(hs.graph, resolve, t.count, RG_STORAGE_READ);
    rg_use(hs.graph, resolve, t.sum, RG_STORAGE_READ);
    rg_use(hs.graph, resolve, t.offset, RG_STORAGE_READ);
    rg_use(hs.graph, resolve, t.curve, RG_STORAGE_READ_WRITE);
    CHECK(harness_build(&hs) == 0, "graph");
    rg_bind_buffer(hs.graph, t.curve, out.buffer);
    float *depth = harness_data(&hs, t.depth), *target = harness_data(&hs, t.target);
    curve_inputs(depth, target);
    CHECK(harness_run(&hs) == 0, "run");
    const vgx_curve_data *gc = out.mapped;
    /* The CPU reference on the same pairs: the geometry pixels (curve.glsl). */
    int np = CV_W * CV_H, n = 0;
    float *z = malloc(np * sizeof(float)), *v = malloc(np * sizeof(float));
    for (int i = 0; i < np; i++)
        if (depth[i] > 0 && depth[i] < CV_FAR * 0.999f) {
            z[n] = depth[i];
            v[n++] = target[i];
        }
    vgx_curve_data cc;
    CHECK(disp_curve_build(z, v, (size_t)n, &cc) == VG_OK, "CPU curve");
    double worst = 0, worst_z = 0;
    for (int i = 0; i < n; i++) {
        double e = fabs((double)vgx_curve_vergence(gc, z[i]) - vgx_curve_vergence(&cc, z[i]));
        if (e > worst) {
            worst = e;
            worst_z = z[i];
        }
    }
    /* ... and across the whole domain, empty bins included. */
    double lo = 1.0 / gc->inv_depth_near, hi = 1.0 / gc->inv_depth_far, sweep = 0;
    for (int k = 0; k <= 4000; k++) {
        float zz = (float)(1.0 / (1.0 / hi + (1.0 / lo - 1.0 / hi) * k / 4000.0));
        sweep = fmax(sweep, fabs((double)vgx_curve_vergence(gc, zz) - vgx_curve_vergence(&cc, zz)));
    }
    printf("curve over %d pairs (%.1f .. %.1f m): max |GPU - CPU| %.4f arcmin at the pairs (worst at %.2f m), %.4f over the domain\n",
           n, lo, hi, worst, worst_z, sweep);
    CHECK(worst < AGREEMENT_ARCMIN && sweep < AGREEMENT_ARCMIN, "GPU and CPU curves differ by %.4f / %.4f arcmin", worst, sweep);
    free(z);
    free(v);
    gpu_buffer_destroy(hs.gpu, &out);
    for (int i = 0; i < 4; i++)
        vkDestroyPipeline(hs.gpu->device, t.pipe[i], NULL);
    vkDestroyPipelineLayout(hs.gpu->device, t.layout, NULL);
    vkDestroyDescriptorSetLayout(hs.gpu->device, t.set, NULL);
    CHECK(harness_close(&hs) == 0, "validation messages");
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"operator_none", operator_none},
        {"operator_linear", operator_linear},
        {"operator_lang", operator_lang},
        {"operator_lang_smoothed", operator_lang_smoothed},
        {"upsample_between", upsample_between},
        {"upsample_late", upsample_late},
        {"upsample_keyframe", upsample_keyframe},
        {"curve", curve_agrees},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
