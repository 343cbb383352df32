/* vergence — GPU passes against their CPU reference on the same inputs
 * (issue 4: max |GPU - CPU| < 0.05 arcmin): the operators, upsampling and
 * the global curve. Run one case: test_passes_gpu NAME. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "disparity/disp_operator.h"
#include "disparity/operator_gpu.h"
#include "disparity/testlib.h"
#include "harness.h"
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
    op_gpu *o;
    rg_res g, color, h, state;
    uint32_t w, hgt;
} op_test;

static VkDescriptorImageInfo image_info(const rg_context *ctx, rg_res r)
{
    return (VkDescriptorImageInfo){.imageView = rg_ctx_view(ctx, r), .imageLayout = rg_ctx_layout(ctx, r)};
}

static void op_fit_execute(const rg_context *ctx, void *user)
{
    op_test *t = user;
    VkDescriptorImageInfo g = image_info(ctx, t->g), c = image_info(ctx, t->color);
    op_gpu_record_fit(t->o, rg_ctx_cmd(ctx), &g, &c, t->w, t->hgt);
}

static void op_map_execute(const rg_context *ctx, void *user)
{
    op_test *t = user;
    VkDescriptorImageInfo g = image_info(ctx, t->g), h = image_info(ctx, t->h);
    op_gpu_record_map(t->o, rg_ctx_cmd(ctx), &g, &h, t->w, t->hgt);
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
    CHECK(op_gpu_create(hs.gpu, &(op_gpu_desc){.op = od, .stride = 1}, &t.o) == VG_OK, "GPU operator");
    t.g = harness_image_add(&hs, "g", VK_FORMAT_R32_SFLOAT, OP_W, OP_H, true, false);
    t.color = harness_image_add(&hs, "color", VK_FORMAT_R8G8B8A8_UNORM, OP_W, OP_H, true, false);
    t.h = harness_image_add(&hs, "h", VK_FORMAT_R32_SFLOAT, OP_W, OP_H, false, true);
    CHECK(harness_upload(&hs) == 0, "upload");
    rg_import_desc rw = {.initial = RG_STORAGE_READ_WRITE, .final = RG_STORAGE_READ_WRITE};
    t.state = rg_import_buffer(hs.graph, &(rg_buffer_desc){"operator.state", op_gpu_state_size(t.o)}, &rw);
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
    rg_bind_buffer(hs.graph, t.state, op_gpu_state(t.o));
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
    op_gpu_destroy(t.o);
    disp_operator_destroy(cpu);
    CHECK(harness_close(&hs) == 0, "validation messages");
    return 0;
}

static int operator_none(void) { return operator_agrees(DISP_OPERATOR_NONE, 1); }
static int operator_linear(void) { return operator_agrees(DISP_OPERATOR_LINEAR, 2); }
static int operator_lang(void) { return operator_agrees(DISP_OPERATOR_LANG, 2); }
static int operator_lang_smoothed(void) { return operator_agrees(DISP_OPERATOR_LANG_SMOOTHED, 4); }

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"operator_none", operator_none},
        {"operator_linear", operator_linear},
        {"operator_lang", operator_lang},
        {"operator_lang_smoothed", operator_lang_smoothed},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
