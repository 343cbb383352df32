/* vergence — compose pass. */
#include "compose_gpu.h"

#include <stdlib.h>

#include "gpu/pipeline.h"
#include "shared.h"

#include "compose_comp.h"

struct compose_gpu {
    frame_ctx *fc;
    compose_gpu_desc desc;
    gpu_compute_kit kit;
    frame_resources *res;
    uint32_t out_w, out_h;
    /* Layouts that place whole eyes 1:1 and leave no pixel uncovered (side
     * by side, top-bottom, cross-eyed, one eye) are image copies: memcpy on
     * a CPU device, where the shader's storage-image loads cost 25 ms at
     * 960x540 (docs/PERFORMANCE.md). */
    int copies;                 /* 0: the compute shader */
    VkImageCopy copy[2];
    bool copy_right[2];         /* region i reads the right eye */
};

_Static_assert(FRAME_COMPOSE_SBS - 1 == VG_COMPOSE_SBS && FRAME_COMPOSE_RIGHT - 1 == VG_COMPOSE_RIGHT &&
                   FRAME_COMPOSE_CROSS_EYED - 1 == VG_COMPOSE_CROSS_EYED,
               "compose mode numbering differs between C and GLSL");

/* The copy regions of a layout, or 0 when it needs the shader. */
static int copy_regions(const compose_gpu *c, VkImageCopy copy[2], bool right[2])
{
    const compose_gpu_desc *d = &c->desc;
    uint32_t width = c->fc->width, height = c->fc->height;
    frame_layout l = frame_compose_layout(d->compose, d->swap_eyes, width, height);
    bool one = d->compose == FRAME_COMPOSE_LEFT || d->compose == FRAME_COMPOSE_RIGHT;
    if (l.overlaid && !one)
        return 0;
    int n = one ? 1 : 2;
    uint64_t covered = 0;
    for (int e = 0; e < n; e++) {
        const frame_eye_rect *r = &l.eye[e];
        if (r->w != width || r->h != height)
            return 0; /* halved: the shader averages */
        covered += (uint64_t)r->w * r->h;
        right[e] = one ? (d->compose == FRAME_COMPOSE_RIGHT) != d->swap_eyes : e == 1;
        copy[e] = (VkImageCopy){
            .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
            .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
            .dstOffset = {(int32_t)r->x, (int32_t)r->y, 0},
            .extent = {r->w, r->h, 1},
        };
    }
    return covered == (uint64_t)l.width * l.height ? n : 0; /* frame packing's band stays the shader's */
}

static void copy_execute(const rg_context *ctx, void *user)
{
    compose_gpu *c = user;
    const frame_resources *r = c->res;
    for (int i = 0; i < c->copies; i++) {
        rg_res eye = c->copy_right[i] ? r->right : r->left;
        vkCmdCopyImage(rg_ctx_cmd(ctx), rg_ctx_image(ctx, eye), rg_ctx_layout(ctx, eye), rg_ctx_image(ctx, r->stereo),
                       rg_ctx_layout(ctx, r->stereo), 1, &c->copy[i]);
    }
}

static void compose_execute(const rg_context *ctx, void *user)
{
    compose_gpu *c = user;
    const frame_resources *r = c->res;
    VkDescriptorImageInfo img[3] = {
        rg_ctx_image_info(ctx, r->left),
        rg_ctx_image_info(ctx, r->right),
        rg_ctx_image_info(ctx, r->stereo),
    };
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    const compose_gpu_desc *d = &c->desc;
    uint32_t width = c->fc->width, height = c->fc->height;
    frame_layout l = frame_compose_layout(d->compose, d->swap_eyes, width, height);
    vg_compose_push push = {.swap = d->swap_eyes, .width = width, .height = height};
    for (int e = 0; e < 2; e++) {
        const frame_eye_rect *r = &l.eye[e];
        push.rect[4 * e] = r->x, push.rect[4 * e + 1] = r->y, push.rect[4 * e + 2] = r->w, push.rect[4 * e + 3] = r->h;
    }
    gpu_binding b[3] = {GPU_STORAGE_IMAGE(&img[0]), GPU_STORAGE_IMAGE(&img[1]), GPU_STORAGE_IMAGE(&img[2])};
    gpu_compute_kit_bind_list(c->fc->gpu, cmd, &c->kit, 0, b, 3, &push);
    vkCmdDispatch(cmd, (c->out_w + 7) / 8, (c->out_h + 7) / 8, 1);
}

void compose_gpu_add(compose_gpu *c, rg_graph *g, frame_resources *res)
{
    c->res = res;
    frame_compose_size(c->desc.compose, c->fc->width, c->fc->height, &c->out_w, &c->out_h);
    res->stereo = rg_image(g, &(rg_image_desc){"stereo", VK_FORMAT_R8G8B8A8_UNORM, c->out_w, c->out_h, 1});
    c->copies = copy_regions(c, c->copy, c->copy_right);
    if (c->copies) {
        rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = "compose", .type = RG_PASS_TRANSFER,
                                                   .execute = copy_execute, .user = c});
        for (int i = 0; i < c->copies; i++)
            rg_use(g, p, c->copy_right[i] ? res->right : res->left, RG_TRANSFER_SRC);
        rg_use(g, p, res->stereo, RG_TRANSFER_DST);
        return;
    }
    rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = "compose", .type = RG_PASS_COMPUTE,
                                               .execute = compose_execute, .user = c});
    rg_use(g, p, res->left, RG_STORAGE_READ);
    rg_use(g, p, res->right, RG_STORAGE_READ);
    rg_use(g, p, res->stereo, RG_STORAGE_WRITE);
}

vg_status compose_gpu_create(frame_ctx *fc, const compose_gpu_desc *desc, compose_gpu **out)
{
    compose_gpu *c = calloc(1, sizeof *c);
    if (!c)
        return VG_ERR_NOMEM;
    c->fc = fc;
    c->desc = *desc;
    gpu *g = fc->gpu;
    static const VkDescriptorType types[3] = {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                              VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
    const compose_gpu_desc *d = desc;
    frame_layout l = frame_compose_layout(d->compose, d->swap_eyes, fc->width, fc->height);
    uint32_t layout[2] = {(uint32_t)(d->compose == FRAME_COMPOSE_DEFAULT ? FRAME_COMPOSE_SBS : d->compose) - 1,
                          !l.overlaid};
    vg_status st = gpu_compute_kit_create(g, &(gpu_compute_kit_desc){
        .name = "compose", .types = types, .count = 3, .push_size = sizeof(vg_compose_push),
        .kernels = {GPU_KERNEL_SPEC(spv_compose_comp, "compose", layout)}}, &c->kit);
    if (st != VG_OK) {
        compose_gpu_destroy(c);
        return st;
    }
    *out = c;
    return VG_OK;
}

void compose_gpu_destroy(compose_gpu *c)
{
    if (!c)
        return;
    gpu_compute_kit_destroy(c->fc->gpu, &c->kit);
    free(c);
}
