/* vergence — blit to the swapchain. */
#include "present_gpu.h"

#include <stdlib.h>

struct present_gpu {
    frame_ctx *fc;
    present_gpu_desc desc;
    VkOffset2D blit_min, blit_max;   /* where the picture lands in the window */
    frame_resources *res;
    rg_res target;
};

/* Fit inside the window keeping the aspect ratio (game_click_to_image maps
 * clicks back the same way). */
static void place_picture(present_gpu *p)
{
    VkExtent2D src = p->desc.source;
    float s = (float)p->desc.extent.width / (float)src.width;
    if ((float)src.height * s > (float)p->desc.extent.height)
        s = (float)p->desc.extent.height / (float)src.height;
    int32_t w = (int32_t)((float)src.width * s + 0.5f), h = (int32_t)((float)src.height * s + 0.5f);
    p->blit_min = (VkOffset2D){((int32_t)p->desc.extent.width - w) / 2, ((int32_t)p->desc.extent.height - h) / 2};
    p->blit_max = (VkOffset2D){p->blit_min.x + w, p->blit_min.y + h};
}

/* The bars: black where the picture does not land (the whole image when it
 * does not fill the window; the blit then writes its middle). */
static void clear_execute(const rg_context *ctx, void *user)
{
    present_gpu *p = user;
    VkImageSubresourceRange all = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(rg_ctx_cmd(ctx), rg_ctx_image(ctx, p->target), rg_ctx_layout(ctx, p->target),
                         &(VkClearColorValue){{0, 0, 0, 1}}, 1, &all);
}

static void blit_execute(const rg_context *ctx, void *user)
{
    present_gpu *p = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    VkImage dst = rg_ctx_image(ctx, p->target);
    VkImageLayout dst_layout = rg_ctx_layout(ctx, p->target);
    VkExtent2D src = p->desc.source;
    rg_res from = p->res->stereo.id ? p->res->stereo : p->res->color;
    VkImageBlit blit = {
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .srcOffsets = {{0, 0, 0}, {(int32_t)src.width, (int32_t)src.height, 1}},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .dstOffsets = {{p->blit_min.x, p->blit_min.y, 0}, {p->blit_max.x, p->blit_max.y, 1}},
    };
    vkCmdBlitImage(cmd, rg_ctx_image(ctx, from), rg_ctx_layout(ctx, from), dst, dst_layout, 1, &blit,
                   VK_FILTER_LINEAR);
}

rg_res present_gpu_add(present_gpu *p, rg_graph *g, frame_resources *res)
{
    p->res = res;
    place_picture(p);
    p->target = rg_import_image(g, &(rg_image_desc){"swapchain", p->desc.format, p->desc.extent.width, p->desc.extent.height, 1},
                                &(rg_import_desc){.initial = RG_PRESENT, .final = RG_PRESENT});
    /* The window has no history: the clear and the blit cover every pixel. */
    if (p->blit_min.x > 0 || p->blit_min.y > 0) {
        rg_pass clear = rg_pass_add(g, &(rg_pass_desc){.name = "present.clear", .type = RG_PASS_TRANSFER,
                                                       .execute = clear_execute, .user = p});
        rg_use(g, clear, p->target, RG_TRANSFER_DST);
    }
    rg_pass blit = rg_pass_add(g, &(rg_pass_desc){.name = "present.blit", .type = RG_PASS_TRANSFER,
                                                  .execute = blit_execute, .user = p});
    rg_use(g, blit, res->stereo.id ? res->stereo : res->color, RG_TRANSFER_SRC);
    rg_use(g, blit, p->target, RG_TRANSFER_DST);
    return p->target;
}

vg_status present_gpu_create(frame_ctx *fc, const present_gpu_desc *desc, present_gpu **out)
{
    present_gpu *p = calloc(1, sizeof *p);
    if (!p)
        return VG_ERR_NOMEM;
    p->fc = fc;
    p->desc = *desc;
    *out = p;
    return VG_OK;
}

void present_gpu_destroy(present_gpu *p) { free(p); }
