/* vergence — blit to the swapchain and draw the HUD. */
#include "present_gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_easy_font.h>

#include "compose_gpu.h"
#include "gpu/pipeline.h"

#include "hud_frag.h"
#include "hud_vert.h"

#define HUD_MAX_QUADS 8192

/* stb_easy_font's vertex: x, y, z floats and an RGBA8 colour. */
typedef struct hud_vertex {
    float x, y, z;
    uint8_t rgba[4];
} hud_vertex;

typedef struct hud_push {
    float inv_half_extent[2];
    float scale;
    float pad;
} hud_push;

struct present_gpu {
    frame_ctx *fc;
    VkFormat format;
    VkExtent2D extent;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    gpu_buffer vertices[VG_FRAMES_IN_FLIGHT];
    gpu_buffer indices;
    uint32_t quads[VG_FRAMES_IN_FLIGHT];
    float scale;
    VkOffset2D blit_min, blit_max;   /* where the picture lands in the window */
    frame_resources *res;
    rg_res target;
};

/* ------------------------------------------------------------------------- */
/* HUD geometry                                                              */
/* ------------------------------------------------------------------------- */

static uint32_t add_quad(hud_vertex *v, uint32_t n, float x0, float y0, float x1, float y1, const uint8_t c[4])
{
    if (n >= HUD_MAX_QUADS)
        return n;
    hud_vertex *q = v + 4 * n;
    const float xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1};
    for (int i = 0; i < 4; i++)
        q[i] = (hud_vertex){xs[i], ys[i], 0, {c[0], c[1], c[2], c[3]}};
    return n + 1;
}

static uint32_t add_text(hud_vertex *v, uint32_t n, float x, float y, const char *text, const uint8_t c[4])
{
    if (n >= HUD_MAX_QUADS)
        return n;
    char buf[FRAME_HUD_LINE];
    snprintf(buf, sizeof buf, "%s", text);
    unsigned char color[4] = {c[0], c[1], c[2], c[3]};
    return n + (uint32_t)stb_easy_font_print(x, y, buf, color, v + 4 * n,
                                             (int)((HUD_MAX_QUADS - n) * 4 * sizeof(hud_vertex)));
}

void present_gpu_update(present_gpu *p, const frame_hud *hud)
{
    int slot = p->fc->slot;
    hud_vertex *v = p->vertices[slot].mapped;
    uint32_t n = 0;
    p->scale = hud && hud->scale > 0 ? hud->scale : 2.0f;
    static const uint8_t panel[4] = {12, 16, 24, 170}, title[4] = {255, 214, 110, 255}, text[4] = {236, 240, 245, 255};
    static const uint8_t black[4] = {0, 0, 0, 255};
    /* Letterbox bars (in font units: the vertex shader scales by p->scale). */
    float sx = 1.0f / p->scale, ex = (float)p->extent.width * sx, ey = (float)p->extent.height * sx;
    if (p->blit_min.x > 0) {
        n = add_quad(v, n, 0, 0, (float)p->blit_min.x * sx, ey, black);
        n = add_quad(v, n, (float)p->blit_max.x * sx, 0, ex, ey, black);
    }
    if (p->blit_min.y > 0) {
        n = add_quad(v, n, 0, 0, ex, (float)p->blit_min.y * sx, black);
        n = add_quad(v, n, 0, (float)p->blit_max.y * sx, ex, ey, black);
    }
    if (hud && hud->visible && hud->line_count > 0) {
        /* Font units: about 6 wide and 12 tall per character line at scale 1. */
        float width = 0;
        for (int i = 0; i < hud->line_count; i++) {
            char buf[FRAME_HUD_LINE];
            snprintf(buf, sizeof buf, "%s", hud->lines[i]);
            float w = (float)stb_easy_font_width(buf);
            width = w > width ? w : width;
        }
        n = add_quad(v, n, 4, 4, 12 + width, 8 + 12.0f * (float)hud->line_count, panel);
        for (int i = 0; i < hud->line_count; i++)
            n = add_text(v, n, 8, 7 + 12.0f * (float)i, hud->lines[i], i == 0 ? title : text);
    }
    if (hud && hud->banner[0]) {
        char buf[FRAME_HUD_LINE];
        snprintf(buf, sizeof buf, "%s", hud->banner);
        float w = (float)stb_easy_font_width(buf);
        float cx = (float)p->extent.width / p->scale * 0.5f, cy = (float)p->extent.height / p->scale * 0.5f;
        n = add_quad(v, n, cx - w * 0.5f - 8, cy - 10, cx + w * 0.5f + 8, cy + 12, panel);
        n = add_text(v, n, cx - w * 0.5f, cy - 4, hud->banner, title);
    }
    p->quads[slot] = n;
}

/* ------------------------------------------------------------------------- */
/* Passes                                                                    */
/* ------------------------------------------------------------------------- */

/* Size of what the frame composes (the stereo image, or the centre colour). */
static VkExtent2D source_size(const present_gpu *p)
{
    const frame_desc *d = &p->fc->desc;
    VkExtent2D e = {d->width, d->height};
    if (d->stereo != FRAME_STEREO_OFF)
        frame_compose_size(d->compose, d->width, d->height, &e.width, &e.height);
    return e;
}

/* Fit inside the window keeping the aspect ratio; the HUD pass paints the
 * bars around it black. */
static void place_picture(present_gpu *p)
{
    VkExtent2D src = source_size(p);
    float s = (float)p->extent.width / (float)src.width;
    if ((float)src.height * s > (float)p->extent.height)
        s = (float)p->extent.height / (float)src.height;
    int32_t w = (int32_t)((float)src.width * s + 0.5f), h = (int32_t)((float)src.height * s + 0.5f);
    p->blit_min = (VkOffset2D){((int32_t)p->extent.width - w) / 2, ((int32_t)p->extent.height - h) / 2};
    p->blit_max = (VkOffset2D){p->blit_min.x + w, p->blit_min.y + h};
}

static void blit_execute(const rg_context *ctx, void *user)
{
    present_gpu *p = user;
    VkExtent2D src = source_size(p);
    rg_res from = p->res->stereo.id ? p->res->stereo : p->res->color;
    VkImageBlit blit = {
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .srcOffsets = {{0, 0, 0}, {(int32_t)src.width, (int32_t)src.height, 1}},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .dstOffsets = {{p->blit_min.x, p->blit_min.y, 0}, {p->blit_max.x, p->blit_max.y, 1}},
    };
    vkCmdBlitImage(rg_ctx_cmd(ctx), rg_ctx_image(ctx, from), rg_ctx_layout(ctx, from), rg_ctx_image(ctx, p->target),
                   rg_ctx_layout(ctx, p->target), 1, &blit, VK_FILTER_LINEAR);
}

static void hud_execute(const rg_context *ctx, void *user)
{
    present_gpu *p = user;
    int slot = p->fc->slot;
    if (!p->quads[slot])
        return;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->pipeline);
    VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &p->vertices[slot].buffer, &offset);
    vkCmdBindIndexBuffer(cmd, p->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
    hud_push push = {{2.0f / (float)p->extent.width, 2.0f / (float)p->extent.height}, p->scale, 0};
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof push, &push);
    vkCmdDrawIndexed(cmd, 6 * p->quads[slot], 1, 0, 0, 0);
}

rg_res present_gpu_add(present_gpu *p, rg_graph *g, frame_resources *res)
{
    p->res = res;
    place_picture(p);
    p->target = rg_import_image(g, &(rg_image_desc){"swapchain", p->format, p->extent.width, p->extent.height, 1},
                                &(rg_import_desc){.initial = RG_PRESENT, .final = RG_PRESENT});
    rg_pass blit = rg_pass_add(g, &(rg_pass_desc){.name = "present.blit", .type = RG_PASS_TRANSFER,
                                                  .execute = blit_execute, .user = p});
    rg_use(g, blit, res->stereo.id ? res->stereo : res->color, RG_TRANSFER_SRC);
    /* The window has no history: the blit and the bars cover every pixel. */
    rg_use(g, blit, p->target, RG_TRANSFER_DST);
    rg_pass hud = rg_pass_add(g, &(rg_pass_desc){.name = "hud", .type = RG_PASS_GRAPHICS,
                                                 .execute = hud_execute, .user = p});
    rg_use(g, hud, p->target, RG_COLOR_WRITE);
    return p->target;
}

/* ------------------------------------------------------------------------- */
/* Lifetime                                                                  */
/* ------------------------------------------------------------------------- */

vg_status present_gpu_create(frame_ctx *fc, VkFormat format, VkExtent2D extent, present_gpu **out)
{
    *out = NULL;
    present_gpu *p = calloc(1, sizeof *p);
    if (!p)
        return VG_ERR_NOMEM;
    p->fc = fc;
    p->format = format;
    p->extent = extent;
    gpu *g = fc->gpu;
    VkPushConstantRange push = {VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(hud_push)};
    VkPipelineLayoutCreateInfo li = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .pushConstantRangeCount = 1,
        .pPushConstantRanges = &push,
    };
    vg_status st = VG_OK;
    if (vkCreatePipelineLayout(g->device, &li, NULL, &p->layout) != VK_SUCCESS)
        st = VG_ERR_VULKAN;
    else
        GPU_NAME(g, VK_OBJECT_TYPE_PIPELINE_LAYOUT, p->layout, "hud layout");
    VkShaderModule vs = 0, fs = 0;
    if (st == VG_OK) st = GPU_SHADER(g, spv_hud_vert, &vs);
    if (st == VG_OK) st = GPU_SHADER(g, spv_hud_frag, &fs);
    VkVertexInputBindingDescription vb = {0, sizeof(hud_vertex), VK_VERTEX_INPUT_RATE_VERTEX};
    VkVertexInputAttributeDescription va[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
        {1, 0, VK_FORMAT_R8G8B8A8_UNORM, 12},
    };
    if (st == VG_OK)
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "hud", .layout = p->layout, .vert = vs, .frag = fs, .bindings = &vb, .binding_count = 1,
            .attributes = va, .attribute_count = 2, .blend = true, .color_formats = &p->format,
            .color_count = 1}, &p->pipeline);
    if (vs)
        vkDestroyShaderModule(g->device, vs, NULL);
    if (fs)
        vkDestroyShaderModule(g->device, fs, NULL);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT && st == VG_OK; i++)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "hud vertices",
                                                     .size = HUD_MAX_QUADS * 4 * sizeof(hud_vertex),
                                                     .usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                                     .host_visible = true}, &p->vertices[i]);
    if (st == VG_OK)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "hud quad indices",
                                                     .size = HUD_MAX_QUADS * 6 * sizeof(uint32_t),
                                                     .usage = VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                                     .host_visible = true}, &p->indices);
    if (st == VG_OK) {
        uint32_t *idx = p->indices.mapped;
        for (uint32_t q = 0; q < HUD_MAX_QUADS; q++) {
            const uint32_t quad[6] = {0, 1, 2, 0, 2, 3};
            for (int k = 0; k < 6; k++)
                idx[6 * q + (uint32_t)k] = 4 * q + quad[k];
        }
    }
    if (st != VG_OK) {
        present_gpu_destroy(p);
        return st;
    }
    *out = p;
    return VG_OK;
}

void present_gpu_destroy(present_gpu *p)
{
    if (!p)
        return;
    gpu *g = p->fc->gpu;
    if (p->pipeline)
        vkDestroyPipeline(g->device, p->pipeline, NULL);
    if (p->layout)
        vkDestroyPipelineLayout(g->device, p->layout, NULL);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT; i++)
        gpu_buffer_destroy(g, &p->vertices[i]);
    gpu_buffer_destroy(g, &p->indices);
    free(p);
}
