/* vergence — disparity passes on the GPU. */
#include "disparity_gpu.h"

#include <stdlib.h>

#include "gpu/pipeline.h"
#include "shared.h"

#include "disparity_original_comp.h"

struct disparity_gpu {
    frame_ctx *fc;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline original;
    rg_res depth, g;
};

static void push_images(const disparity_gpu *d, const rg_context *ctx, rg_res in, rg_res out)
{
    const frame_ctx *fc = d->fc;
    VkDescriptorBufferInfo ubo = {fc->ubo[fc->slot].buffer, 0, sizeof(vg_frame_ubo)};
    VkDescriptorImageInfo src = {.imageView = rg_ctx_view(ctx, in), .imageLayout = rg_ctx_layout(ctx, in)};
    VkDescriptorImageInfo dst = {.imageView = rg_ctx_view(ctx, out), .imageLayout = rg_ctx_layout(ctx, out)};
    VkWriteDescriptorSet w[3] = {
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 0, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, .pBufferInfo = &ubo},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 1, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, .pImageInfo = &src},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 2, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, .pImageInfo = &dst},
    };
    fc->gpu->cmd_push_descriptor_set(rg_ctx_cmd(ctx), VK_PIPELINE_BIND_POINT_COMPUTE, d->layout, 0, 3, w);
}

static void original_execute(const rg_context *ctx, void *user)
{
    disparity_gpu *d = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, d->original);
    push_images(d, ctx, d->depth, d->g);
    vkCmdDispatch(cmd, (d->fc->desc.width + 7) / 8, (d->fc->desc.height + 7) / 8, 1);
}

void disparity_gpu_add(disparity_gpu *d, rg_graph *g, frame_resources *res)
{
    uint32_t w = d->fc->desc.width, h = d->fc->desc.height;
    d->depth = res->depth;
    d->g = res->g = rg_image(g, &(rg_image_desc){"disparity.g", VK_FORMAT_R32_SFLOAT, w, h, 1});
    rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = "disparity.original", .type = RG_PASS_COMPUTE,
                                               .execute = original_execute, .user = d});
    rg_use(g, p, res->ubo, RG_UNIFORM);
    rg_use(g, p, res->depth, RG_STORAGE_READ);
    rg_use(g, p, res->g, RG_STORAGE_WRITE);
}

vg_status disparity_gpu_prepare(disparity_gpu *d)
{
    (void)d;
    return VG_OK;
}

vg_status disparity_gpu_create(frame_ctx *fc, disparity_gpu **out)
{
    disparity_gpu *d = calloc(1, sizeof *d);
    if (!d)
        return VG_ERR_NOMEM;
    d->fc = fc;
    gpu *g = fc->gpu;
    static const VkDescriptorType types[] = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                             VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
    vg_status st = gpu_push_layout_create(g, "disparity", types, 3, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                                          &d->set_layout, &d->layout);
    VkShaderModule m = VK_NULL_HANDLE;
    if (st == VG_OK)
        st = GPU_SHADER(g, spv_disparity_original_comp, &m);
    if (st == VG_OK)
        st = gpu_compute_pipeline_create(g, d->layout, m, "disparity.original", &d->original);
    if (m)
        vkDestroyShaderModule(g->device, m, NULL);
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
    VkDevice dev = d->fc->gpu->device;
    if (d->original)
        vkDestroyPipeline(dev, d->original, NULL);
    if (d->layout)
        vkDestroyPipelineLayout(dev, d->layout, NULL);
    if (d->set_layout)
        vkDestroyDescriptorSetLayout(dev, d->set_layout, NULL);
    free(d);
}
