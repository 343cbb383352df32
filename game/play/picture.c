/* vergence — CPU pictures in the window. */
#include "picture.h"

#include <stdlib.h>
#include <string.h>

#include <stb_easy_font.h>

#include "graph/graph.h"
#include "window.h"

struct picture {
    gpu *gpu;
    VkFormat format;
    VkExtent2D extent;
    gpu_buffer pixels;
    rg_graph *graph;
    rg_res r_pixels, r_target;
    VkCommandBuffer cmd;
    VkFence fence;
    bool submitted;
};

static void copy_execute(const rg_context *ctx, void *user)
{
    picture *p = user;
    VkBufferImageCopy region = {
        .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .imageExtent = {p->extent.width, p->extent.height, 1},
    };
    vkCmdCopyBufferToImage(rg_ctx_cmd(ctx), rg_ctx_buffer(ctx, p->r_pixels), rg_ctx_image(ctx, p->r_target),
                           rg_ctx_layout(ctx, p->r_target), 1, &region);
}

vg_status picture_create(gpu *g, VkFormat format, VkExtent2D extent, picture **out)
{
    *out = NULL;
    picture *p = calloc(1, sizeof *p);
    if (!p)
        return VG_ERR_NOMEM;
    p->gpu = g;
    p->format = format;
    p->extent = extent;
    VkDeviceSize size = (VkDeviceSize)extent.width * extent.height * 4;
    vg_status st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "picture pixels", .size = size,
                                                           .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                           .host_visible = true}, &p->pixels);
    if (st == VG_OK && !(p->graph = rg_create()))
        st = VG_ERR_NOMEM;
    if (st == VG_OK) {
        /* Written by the host before the submit, which makes it visible. */
        p->r_pixels = rg_import_buffer(p->graph, &(rg_buffer_desc){"picture.pixels", size},
                                       &(rg_import_desc){.initial = RG_TRANSFER_SRC});
        p->r_target = rg_import_image(p->graph, &(rg_image_desc){"swapchain", format, extent.width, extent.height, 1},
                                      &(rg_import_desc){.initial = RG_PRESENT, .final = RG_PRESENT});
        rg_pass copy = rg_pass_add(p->graph, &(rg_pass_desc){.name = "picture.copy", .type = RG_PASS_TRANSFER,
                                                             .execute = copy_execute, .user = p});
        rg_use(p->graph, copy, p->r_pixels, RG_TRANSFER_SRC);
        rg_use(p->graph, copy, p->r_target, RG_TRANSFER_DST);
        st = rg_compile(p->graph);
    }
    if (st == VG_OK)
        st = rg_realize(p->graph, g);
    if (st == VG_OK) {
        VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                          .commandPool = g->pool, .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                          .commandBufferCount = 1};
        VkFenceCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        if (vkAllocateCommandBuffers(g->device, &ai, &p->cmd) != VK_SUCCESS ||
            vkCreateFence(g->device, &fi, NULL, &p->fence) != VK_SUCCESS)
            st = VG_ERR_VULKAN;
        else {
            GPU_NAME(g, VK_OBJECT_TYPE_COMMAND_BUFFER, p->cmd, "picture commands");
            GPU_NAME(g, VK_OBJECT_TYPE_FENCE, p->fence, "picture fence");
        }
    }
    if (st != VG_OK) {
        picture_destroy(p);
        return st;
    }
    memset(p->pixels.mapped, 0, size);
    *out = p;
    return VG_OK;
}

void picture_destroy(picture *p)
{
    if (!p)
        return;
    VkDevice dev = p->gpu->device;
    vkDeviceWaitIdle(dev);
    rg_destroy(p->graph);
    if (p->fence)
        vkDestroyFence(dev, p->fence, NULL);
    if (p->cmd)
        vkFreeCommandBuffers(dev, p->gpu->pool, 1, &p->cmd);
    gpu_buffer_destroy(p->gpu, &p->pixels);
    free(p);
}

uint8_t *picture_begin(picture *p)
{
    if (p->submitted) {
        vkWaitForFences(p->gpu->device, 1, &p->fence, VK_TRUE, UINT64_MAX);
        vkResetFences(p->gpu->device, 1, &p->fence);
        p->submitted = false;
    }
    return p->pixels.mapped;
}

void picture_channels(const picture *p, int *r, int *g, int *b)
{
    bool bgr = p->format == VK_FORMAT_B8G8R8A8_UNORM || p->format == VK_FORMAT_B8G8R8A8_SRGB;
    *r = bgr ? 2 : 0, *g = 1, *b = bgr ? 0 : 2;
}

VkExtent2D picture_extent(const picture *p) { return p->extent; }

vg_status picture_present(picture *p, const frame_target *t)
{
    picture_begin(p);
    rg_bind_buffer(p->graph, p->r_pixels, p->pixels.buffer);
    rg_bind_image(p->graph, p->r_target, t->image, t->view);
    VK_TRY(vkResetCommandBuffer(p->cmd, 0));
    VK_TRY(vkBeginCommandBuffer(p->cmd, &(VkCommandBufferBeginInfo){
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO, .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT}));
    rg_execute(p->graph, p->cmd, 0);
    VK_TRY(vkEndCommandBuffer(p->cmd));
    /* The acquire is waited on where the graph expects the image (colour output). */
    VK_TRY(gpu_queue_submit(p->gpu, p->cmd, t->wait, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, t->signal,
                            p->fence));
    p->submitted = true;
    return VG_OK;
}

vg_status picture_fit(picture **p, window *w)
{
    VkExtent2D e = window_extent(w);
    if (*p) {
        VkExtent2D pe = picture_extent(*p);
        if (pe.width == e.width && pe.height == e.height)
            return VG_OK;
        picture_destroy(*p);
        *p = NULL;
    }
    return picture_create(window_gpu(w), window_format(w), e, p);
}

vg_status picture_show(picture **p, window *w, bool *rebuilt)
{
    frame_target t;
    bool stale;
    *rebuilt = false;
    vg_status st = window_acquire(w, &t, &stale);
    if (st == VG_OK && !stale) {
        st = picture_present(*p, &t);
        if (st == VG_OK)
            st = window_present(w, &stale);
    }
    if (st == VG_OK && stale) {
        *rebuilt = true;
        picture_destroy(*p);
        *p = NULL;
        st = window_rebuild(w);
        if (st == VG_OK)
            st = picture_fit(p, w);
    }
    return st;
}

/* ------------------------------------------------------------------------- */
/* Drawing                                                                   */
/* ------------------------------------------------------------------------- */

void picture_fill(picture *p, int x, int y, int w, int h, const uint8_t rgb[3])
{
    int W = (int)p->extent.width, H = (int)p->extent.height, r, g, b;
    picture_channels(p, &r, &g, &b);
    uint8_t *px = p->pixels.mapped;
    for (int j = y < 0 ? 0 : y; j < y + h && j < H; j++)
        for (int i = x < 0 ? 0 : x; i < x + w && i < W; i++) {
            uint8_t *q = px + ((size_t)j * W + i) * 4;
            q[r] = rgb[0], q[g] = rgb[1], q[b] = rgb[2], q[3] = 255;
        }
}

typedef struct font_vertex {
    float x, y, z;
    uint8_t rgba[4];
} font_vertex;

int picture_text_width(const char *text, int scale)
{
    return stb_easy_font_width((char *)text) * scale;
}

int picture_text(picture *p, int x, int y, int scale, const char *text, const uint8_t rgb[3])
{
    static font_vertex v[4 * 2048];
    int quads = stb_easy_font_print(0, 0, (char *)text, NULL, v, (int)sizeof v);
    for (int q = 0; q < quads; q++) {
        const font_vertex *a = &v[4 * q], *c = &v[4 * q + 2];
        picture_fill(p, x + (int)a->x * scale, y + (int)a->y * scale, (int)(c->x - a->x) * scale,
                     (int)(c->y - a->y) * scale, rgb);
    }
    return picture_text_width(text, scale);
}
