/* vergence — disparity.original on the GPU. */
#include "original_gpu.h"

#include "disparity_original_comp.h"

vg_status original_gpu_create(gpu *g, original_gpu *out)
{
    static const VkDescriptorType types[] = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                             VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
    return gpu_compute_kit_create(g, &(gpu_compute_kit_desc){
        .name = "disparity.original", .types = types, .count = 3,
        .kernels = {GPU_KERNEL(spv_disparity_original_comp, "disparity.original")}}, &out->kit);
}

void original_gpu_destroy(gpu *g, original_gpu *o)
{
    gpu_compute_kit_destroy(g, &o->kit);
}

void original_gpu_record(gpu *g, const original_gpu *o, VkCommandBuffer cmd, VkBuffer ubo,
                         const VkDescriptorImageInfo *depth, const VkDescriptorImageInfo *out_g, uint32_t width,
                         uint32_t height)
{
    gpu_binding b[3] = {GPU_UNIFORM_BUFFER(ubo), GPU_STORAGE_IMAGE(depth), GPU_STORAGE_IMAGE(out_g)};
    gpu_compute_kit_bind_list(g, cmd, &o->kit, 0, b, 3, NULL);
    vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, 1);
}
