/* vergence — a stereo pair without tessellation (eyes_gpu.h). */
#include "eyes_gpu.h"

#include <stdlib.h>

#include "eyes_clear_comp.h"
#include "eyes_color_comp.h"
#include "eyes_depth_comp.h"
#include "eyes_fill_comp.h"

/* shaders/eyes.glsl's EyesPush. */
typedef struct eyes_push {
    uint32_t width, height;
    float same_surface;
    uint32_t max_span;
} eyes_push;

/* Neighbours within 1 % of their depth are one surface (the cascade's own
 * test, warp.md); a pixel stretches over at most 16 eye pixels. */
#define EYES_SAME_SURFACE 0.01f
#define EYES_MAX_SPAN 16u

enum { K_CLEAR, K_DEPTH, K_COLOR, K_FILL, K_COUNT };

struct eyes_gpu {
    gpu *gpu;
    gpu_compute_kit kit;
    VkSampler sampler;
    uint32_t width, height;
    rg_res ubo, depth, target, color, nearest, left, right;
    struct eyes_step {
        eyes_gpu *eyes;
        uint32_t kernel;
    } steps[K_COUNT];
};

vg_status eyes_gpu_create(gpu *g, uint32_t width, uint32_t height, VkSampler sampler, eyes_gpu **out)
{
    *out = NULL;
    eyes_gpu *e = calloc(1, sizeof *e);
    if (!e)
        return VG_ERR_NOMEM;
    e->gpu = g;
    e->width = width;
    e->height = height;
    e->sampler = sampler;
    static const VkDescriptorType types[7] = {
        VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
    vg_status st = gpu_compute_kit_create(g, &(gpu_compute_kit_desc){
        .name = "vgx.eyes", .types = types, .count = 7, .push_size = sizeof(eyes_push),
        .kernels = {[K_CLEAR] = GPU_KERNEL(spv_eyes_clear_comp, "vgx.eyes.clear"),
                    [K_DEPTH] = GPU_KERNEL(spv_eyes_depth_comp, "vgx.eyes.depth"),
                    [K_COLOR] = GPU_KERNEL(spv_eyes_color_comp, "vgx.eyes.color"),
                    [K_FILL] = GPU_KERNEL(spv_eyes_fill_comp, "vgx.eyes.fill")}}, &e->kit);
    if (st != VG_OK) {
        eyes_gpu_destroy(e);
        return st;
    }
    *out = e;
    return VG_OK;
}

void eyes_gpu_destroy(eyes_gpu *e)
{
    if (!e)
        return;
    gpu_compute_kit_destroy(e->gpu, &e->kit);
    free(e);
}

static void step_execute(const rg_context *ctx, void *user)
{
    const struct eyes_step *step = user;
    const eyes_gpu *e = step->eyes;
    VkDescriptorImageInfo depth = rg_ctx_image_info(ctx, e->depth);
    VkDescriptorImageInfo target = rg_ctx_image_info(ctx, e->target);
    VkDescriptorImageInfo color = rg_ctx_sampled_info(ctx, e->color, e->sampler);
    VkDescriptorImageInfo left = rg_ctx_image_info(ctx, e->left);
    VkDescriptorImageInfo right = rg_ctx_image_info(ctx, e->right);
    gpu_binding b[7] = {
        GPU_UNIFORM_BUFFER(rg_ctx_buffer(ctx, e->ubo)),
        GPU_STORAGE_IMAGE(&depth),
        GPU_STORAGE_IMAGE(&target),
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &color, VK_NULL_HANDLE, NULL},
        GPU_STORAGE_BUFFER(rg_ctx_buffer(ctx, e->nearest)),
        GPU_STORAGE_IMAGE(&left),
        GPU_STORAGE_IMAGE(&right),
    };
    eyes_push push = {e->width, e->height, EYES_SAME_SURFACE, EYES_MAX_SPAN};
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    gpu_compute_kit_bind_list(e->gpu, cmd, &e->kit, step->kernel, b, 7, &push);
    vkCmdDispatch(cmd, (e->width + 63) / 64, e->height, 2);
}

void eyes_gpu_add(eyes_gpu *e, rg_graph *g, rg_res ubo, rg_res depth, rg_res target, rg_res color, rg_res left,
                  rg_res right)
{
    e->ubo = ubo, e->depth = depth, e->target = target, e->color = color, e->left = left, e->right = right;
    e->nearest = rg_buffer(g, &(rg_buffer_desc){"vgx.eyes.nearest", 2ull * e->width * e->height * sizeof(uint32_t)});
    static const char *const names[K_COUNT] = {"vgx.eyes.clear", "vgx.eyes.depth", "vgx.eyes.color", "vgx.eyes.fill"};
    for (uint32_t k = 0; k < K_COUNT; k++) {
        e->steps[k] = (struct eyes_step){e, k};
        rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = names[k], .type = RG_PASS_COMPUTE,
                                                   .execute = step_execute, .user = &e->steps[k]});
        /* Every step binds every resource (one descriptor layout); each
         * declares what it reads and writes. */
        rg_use(g, p, ubo, RG_UNIFORM);
        rg_use(g, p, depth, RG_STORAGE_READ);
        rg_use(g, p, target, RG_STORAGE_READ);
        rg_use(g, p, color, RG_SAMPLED);
        rg_use(g, p, e->nearest, k == K_CLEAR ? RG_STORAGE_WRITE : k == K_DEPTH ? RG_STORAGE_READ_WRITE
                                                                                  : RG_STORAGE_READ);
        rg_usage eyes = k == K_COLOR ? RG_STORAGE_READ_WRITE : k == K_FILL ? RG_STORAGE_READ_WRITE : RG_STORAGE_READ;
        rg_use(g, p, left, eyes);
        rg_use(g, p, right, eyes);
    }
}
