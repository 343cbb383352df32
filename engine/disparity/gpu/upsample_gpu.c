/* vergence — mid.upsample on the GPU. */
#include "upsample_gpu.h"

#include <math.h>
#include <stdlib.h>

#include "gpu/pipeline.h"
#include "disparity/mid_shared.h"

#include "mid_upsample_space_comp.h"
#include "mid_upsample_time_comp.h"

enum { P_TIME, P_SPACE, P_COUNT };

struct upsample_gpu {
    gpu *gpu;
    VkDescriptorSetLayout set[P_COUNT];
    VkPipelineLayout layout[P_COUNT];
    VkPipeline pipe[P_COUNT];
};

vg_status upsample_gpu_create(gpu *g, upsample_gpu **out)
{
    *out = NULL;
    upsample_gpu *u = calloc(1, sizeof *u);
    if (!u)
        return VG_ERR_NOMEM;
    u->gpu = g;
    static const VkDescriptorType IMG = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, BUF = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    static const VkDescriptorType types[P_COUNT][5] = {{IMG, IMG, BUF, BUF, BUF}, {IMG, BUF, BUF, IMG}};
    static const uint32_t counts[P_COUNT] = {5, 4};
    static const char *const names[P_COUNT] = {"mid.upsample.time", "mid.upsample.space"};
    const struct { const uint32_t *code; size_t size; } spv[P_COUNT] = {
        {spv_mid_upsample_time_comp, sizeof spv_mid_upsample_time_comp},
        {spv_mid_upsample_space_comp, sizeof spv_mid_upsample_space_comp},
    };
    vg_status st = VG_OK;
    for (int p = 0; p < P_COUNT && st == VG_OK; p++) {
        VkShaderModule m = VK_NULL_HANDLE;
        st = gpu_push_layout_create(g, names[p], types[p], counts[p], VK_SHADER_STAGE_COMPUTE_BIT,
                                    sizeof(disp_upsample_push), &u->set[p], &u->layout[p]);
        if (st == VG_OK)
            st = gpu_shader_create(g, spv[p].code, spv[p].size, names[p], &m);
        if (st == VG_OK)
            st = gpu_compute_pipeline_create(g, u->layout[p], m, names[p], &u->pipe[p]);
        if (m)
            vkDestroyShaderModule(g->device, m, NULL);
    }
    if (st != VG_OK) {
        upsample_gpu_destroy(u);
        return st;
    }
    *out = u;
    return VG_OK;
}

void upsample_gpu_destroy(upsample_gpu *u)
{
    if (!u)
        return;
    VkDevice dev = u->gpu->device;
    for (int p = 0; p < P_COUNT; p++) {
        if (u->pipe[p])
            vkDestroyPipeline(dev, u->pipe[p], NULL);
        if (u->layout[p])
            vkDestroyPipelineLayout(dev, u->layout[p], NULL);
        if (u->set[p])
            vkDestroyDescriptorSetLayout(dev, u->set[p], NULL);
    }
    free(u);
}

static disp_upsample_push push_of(const upsample_gpu_frame *f)
{
    uint32_t s = f->stride ? f->stride : MID_COARSE_STRIDE;
    float tol = f->occlusion_tolerance > 0 ? f->occlusion_tolerance : MID_OCCLUSION_TOLERANCE;
    float ss = f->sigma_spatial > 0 ? f->sigma_spatial : MID_SIGMA_SPATIAL;
    float sr = f->sigma_range > 0 ? f->sigma_range : MID_SIGMA_RANGE;
    return (disp_upsample_push){
        .full_w = f->width, .full_h = f->height, .stride = s,
        .nx = (f->width + s - 1) / s, .ny = (f->height + s - 1) / s,
        .slot0 = f->slot0, .slot1 = f->slot1, .has1 = f->has1,
        .tau = f->at_key ? 0.0f : f->tau, .log_tol = logf(1.0f + tol),
        .inv_2ss = 1.0f / (2.0f * ss * ss), .inv_2sr = 1.0f / (2.0f * sr * sr),
        .at_key = f->at_key, .store_cap = f->slots, .span = f->span,
    };
}

typedef struct binding {
    VkDescriptorType type;
    const VkDescriptorImageInfo *image;
    VkBuffer buffer;
} binding;

static void record(upsample_gpu *u, VkCommandBuffer cmd, int p, const binding *b, uint32_t n, const disp_upsample_push *pc)
{
    VkWriteDescriptorSet w[5];
    VkDescriptorBufferInfo bufs[5];
    for (uint32_t i = 0; i < n; i++) {
        bufs[i] = (VkDescriptorBufferInfo){b[i].buffer, 0, VK_WHOLE_SIZE};
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = i,
                                      .descriptorCount = 1, .descriptorType = b[i].type};
        if (b[i].image)
            w[i].pImageInfo = b[i].image;
        else
            w[i].pBufferInfo = &bufs[i];
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, u->pipe[p]);
    u->gpu->cmd_push_descriptor_set(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, u->layout[p], 0, n, w);
    vkCmdPushConstants(cmd, u->layout[p], VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof *pc, pc);
}

#define IMG(info) {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, (info), VK_NULL_HANDLE}
#define BUF(buf) {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, NULL, (buf)}

void upsample_gpu_record_time(upsample_gpu *u, VkCommandBuffer cmd, const upsample_gpu_frame *f, const VkDescriptorImageInfo *depth,
                         const VkDescriptorImageInfo *motion, VkBuffer store, VkBuffer published, VkBuffer ratio)
{
    disp_upsample_push pc = push_of(f);
    binding b[5] = {IMG(depth), IMG(motion), BUF(store), BUF(published), BUF(ratio)};
    record(u, cmd, P_TIME, b, 5, &pc);
    vkCmdDispatch(cmd, (pc.nx * pc.ny + 63) / 64, 1, 1);
}

void upsample_gpu_record_space(upsample_gpu *u, VkCommandBuffer cmd, const upsample_gpu_frame *f, const VkDescriptorImageInfo *h,
                          VkBuffer published, VkBuffer ratio, const VkDescriptorImageInfo *out)
{
    disp_upsample_push pc = push_of(f);
    binding b[4] = {IMG(h), BUF(published), BUF(ratio), IMG(out)};
    record(u, cmd, P_SPACE, b, 4, &pc);
    vkCmdDispatch(cmd, (f->width + 7) / 8, (f->height + 7) / 8, 1);
}
