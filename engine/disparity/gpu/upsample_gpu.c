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
    gpu_compute_kit kit[P_COUNT];
};

vg_status upsample_gpu_create(gpu *g, upsample_gpu **out)
{
    *out = NULL;
    upsample_gpu *u = calloc(1, sizeof *u);
    if (!u)
        return VG_ERR_NOMEM;
    u->gpu = g;
    static const VkDescriptorType IMG = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, BUF = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    static const VkDescriptorType time_types[] = {IMG, IMG, BUF, BUF, IMG, IMG, IMG, IMG}, space_types[] = {IMG, BUF, IMG, IMG};
    vg_status st = gpu_compute_kit_create(g, &(gpu_compute_kit_desc){
        .name = "mid.upsample.time", .types = time_types, .count = 8, .push_size = sizeof(disp_upsample_push),
        .kernels = {GPU_KERNEL(spv_mid_upsample_time_comp, "mid.upsample.time")}}, &u->kit[P_TIME]);
    if (st == VG_OK)
        st = gpu_compute_kit_create(g, &(gpu_compute_kit_desc){
            .name = "mid.upsample.space", .types = space_types, .count = 4, .push_size = sizeof(disp_upsample_push),
            .kernels = {GPU_KERNEL(spv_mid_upsample_space_comp, "mid.upsample.space")}}, &u->kit[P_SPACE]);
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
    for (int p = 0; p < P_COUNT; p++)
        gpu_compute_kit_destroy(u->gpu, &u->kit[p]);
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
        .at_key = f->at_key, .store_cap = f->slots, .span = f->span, .depth_only = f->depth_only,
    };
}

void upsample_gpu_record_time(upsample_gpu *u, VkCommandBuffer cmd, const upsample_gpu_frame *f, const VkDescriptorImageInfo *depth,
                         const VkDescriptorImageInfo *motion, const VkDescriptorImageInfo *ids, VkBuffer store,
                         VkBuffer published, const VkDescriptorImageInfo *g, const VkDescriptorImageInfo *h,
                         const VkDescriptorImageInfo *ratio)
{
    disp_upsample_push pc = push_of(f);
    gpu_binding b[8] = {GPU_STORAGE_IMAGE(depth), GPU_STORAGE_IMAGE(motion), GPU_STORAGE_BUFFER(store),
                        GPU_STORAGE_BUFFER(published), GPU_STORAGE_IMAGE(ratio), GPU_STORAGE_IMAGE(ids),
                        GPU_STORAGE_IMAGE(g), GPU_STORAGE_IMAGE(h)};
    gpu_compute_kit_bind_list(u->gpu, cmd, &u->kit[P_TIME], 0, b, 8, &pc);
    vkCmdDispatch(cmd, (pc.nx * pc.ny + 63) / 64, 1, 1);
}

void upsample_gpu_record_space(upsample_gpu *u, VkCommandBuffer cmd, const upsample_gpu_frame *f, const VkDescriptorImageInfo *h,
                          VkBuffer published, const VkDescriptorImageInfo *ratio, const VkDescriptorImageInfo *out)
{
    disp_upsample_push pc = push_of(f);
    gpu_binding b[4] = {GPU_STORAGE_IMAGE(h), GPU_STORAGE_BUFFER(published), GPU_STORAGE_IMAGE(ratio),
                        GPU_STORAGE_IMAGE(out)};
    gpu_compute_kit_bind_list(u->gpu, cmd, &u->kit[P_SPACE], 0, b, 4, &pc);
    vkCmdDispatch(cmd, (f->width + 7) / 8, (f->height + 7) / 8, 1);
}
