/* vergence — helpers the frame shares with its pass modules. */
#include "frame_ctx.h"

#include <string.h>

#include "shared.h"

void frame_ctx_ubo_stereo(vg_frame_ubo *u, const stereo_camera *rig, const stereo_display *display, uint32_t width)
{
    memcpy(u->rig.v, (float[4]){(float)rig->gain_px, (float)rig->convergence_m, (float)rig->interaxial_m, 0}, 16);
    memcpy(u->display.v, (float[4]){(float)display->ipd_m, (float)display->distance_m,
                                    (float)(display->width_m / width), (float)display->screen_vergence}, 16);
}

void frame_ctx_push_scene(const frame_ctx *fc, const rg_context *ctx, rg_res shadow)
{
    VkDescriptorBufferInfo ubo = {fc->ubo[fc->slot].buffer, 0, sizeof(vg_frame_ubo)};
    VkDescriptorImageInfo map = {
        .sampler = fc->shadow_sampler,
        .imageView = shadow.id ? rg_ctx_view(ctx, shadow) : VK_NULL_HANDLE,
        .imageLayout = shadow.id ? rg_ctx_layout(ctx, shadow) : VK_IMAGE_LAYOUT_UNDEFINED,
    };
    VkWriteDescriptorSet writes[2] = {
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 0, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, .pBufferInfo = &ubo},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 1, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, .pImageInfo = &map},
    };
    fc->gpu->cmd_push_descriptor_set(rg_ctx_cmd(ctx), VK_PIPELINE_BIND_POINT_GRAPHICS, fc->scene_layout, 0,
                                     shadow.id ? 2 : 1, writes);
}
