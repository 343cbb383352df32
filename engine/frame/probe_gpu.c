/* vergence — the probe pass (probe_gpu.h). */
#include "probe_gpu.h"

#include <stdlib.h>
#include <string.h>

#include "gpu/pipeline.h"
#include "shared.h"

#include "probe_comp.h"

_Static_assert(FRAME_PROBE_MAX_IDS == VG_PROBE_MAX_IDS, "probe id counts differ between C and GLSL");

struct probe_gpu {
    frame_ctx *fc;
    uint32_t probe_ids[FRAME_PROBE_MAX_IDS]; /* the probed instances, 0-terminated */
    gpu_compute_kit kit;
    gpu_buffer partials[VG_FRAMES_IN_FLIGHT];
    uint32_t groups_x, groups_y;
    rg_res r_partials, ids, g, shown;
};

static void probe_execute(const rg_context *ctx, void *user)
{
    probe_gpu *p = user;
    const frame_ctx *fc = p->fc;
    VkDescriptorImageInfo img[3] = {
        rg_ctx_sampled_info(ctx, p->ids, fc->nearest_clamp),
        rg_ctx_sampled_info(ctx, p->g, fc->nearest_clamp),
        rg_ctx_sampled_info(ctx, p->shown, fc->nearest_clamp),
    };
    vg_probe_push push = {.width = fc->width, .height = fc->height, .groups_x = p->groups_x};
    memcpy(push.ids, p->probe_ids, sizeof push.ids);
    gpu_binding b[4] = {
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &img[0], VK_NULL_HANDLE, NULL},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &img[1], VK_NULL_HANDLE, NULL},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &img[2], VK_NULL_HANDLE, NULL},
        GPU_STORAGE_BUFFER(rg_ctx_buffer(ctx, p->r_partials)),
    };
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    gpu_compute_kit_bind_list(fc->gpu, cmd, &p->kit, 0, b, 4, &push);
    vkCmdDispatch(cmd, p->groups_x, p->groups_y, 1);
}

void probe_gpu_add(probe_gpu *p, rg_graph *g, const frame_resources *res, rg_res shown)
{
    p->ids = res->ids, p->g = res->g, p->shown = shown;
    p->r_partials = rg_import_buffer(g, &(rg_buffer_desc){"probe.partials", p->partials[0].size},
                                     &(rg_import_desc){.final = RG_HOST_READ});
    rg_pass pass = rg_pass_add(g, &(rg_pass_desc){.name = "probe", .type = RG_PASS_COMPUTE,
                                                  .execute = probe_execute, .user = p});
    rg_use(g, pass, res->ids, RG_SAMPLED);
    rg_use(g, pass, res->g, RG_SAMPLED);
    if (shown.id != res->g.id)
        rg_use(g, pass, shown, RG_SAMPLED);
    rg_use(g, pass, p->r_partials, RG_STORAGE_WRITE);
}

void probe_gpu_bind(probe_gpu *p, rg_graph *g)
{
    rg_bind_buffer(g, p->r_partials, p->partials[p->fc->slot].buffer);
}

frame_probe probe_gpu_read(const probe_gpu *p, int slot, long index)
{
    const vg_probe_partial *q = p->partials[slot].mapped;
    double sum = 0;
    uint32_t pixels = 0;
    for (uint32_t i = 0; i < p->groups_x * p->groups_y; i++)
        sum += q[i].sum, pixels += q[i].pixels;
    return (frame_probe){index, pixels, pixels ? sum / pixels : 0.0};
}

vg_status probe_gpu_create(frame_ctx *fc, const uint32_t ids[FRAME_PROBE_MAX_IDS], probe_gpu **out)
{
    *out = NULL;
    probe_gpu *p = calloc(1, sizeof *p);
    if (!p)
        return VG_ERR_NOMEM;
    p->fc = fc;
    memcpy(p->probe_ids, ids, sizeof p->probe_ids);
    p->groups_x = (fc->width + VG_PROBE_GROUP - 1) / VG_PROBE_GROUP;
    p->groups_y = (fc->height + VG_PROBE_GROUP - 1) / VG_PROBE_GROUP;
    static const VkDescriptorType types[4] = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                              VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                              VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                              VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    vg_status st = gpu_compute_kit_create(fc->gpu, &(gpu_compute_kit_desc){
        .name = "probe", .types = types, .count = 4, .push_size = sizeof(vg_probe_push),
        .kernels = {GPU_KERNEL(spv_probe_comp, "probe")}}, &p->kit);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT && st == VG_OK; i++) {
        st = gpu_buffer_create(fc->gpu, &(gpu_buffer_desc){
            .name = "probe partials", .size = (VkDeviceSize)p->groups_x * p->groups_y * sizeof(vg_probe_partial),
            .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true}, &p->partials[i]);
        if (st == VG_OK)
            memset(p->partials[i].mapped, 0, p->partials[i].size);
    }
    if (st != VG_OK) {
        probe_gpu_destroy(p);
        return st;
    }
    *out = p;
    return VG_OK;
}

void probe_gpu_destroy(probe_gpu *p)
{
    if (!p)
        return;
    gpu_compute_kit_destroy(p->fc->gpu, &p->kit);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT; i++)
        gpu_buffer_destroy(p->fc->gpu, &p->partials[i]);
    free(p);
}
