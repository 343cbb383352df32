/* vergence — one-frame test graphs (see harness.h). */
#include "harness.h"

#include <stdio.h>
#include <string.h>

int harness_open(harness *h)
{
    memset(h, 0, sizeof *h);
    if (gpu_create(&(gpu_desc){0}, &h->gpu) != VG_OK) {
        fprintf(stderr, "gpu_create failed\n");
        return 1;
    }
    h->graph = rg_create();
    return h->graph ? 0 : 1;
}

rg_res harness_image_add(harness *h, const char *name, VkFormat format, uint32_t w, uint32_t hgt, bool upload,
                         bool download)
{
    rg_res r = rg_image(h->graph, &(rg_image_desc){name, format, w, hgt, 1});
    harness_image *im = &h->images[h->count++];
    *im = (harness_image){.res = r, .width = w, .height = hgt, .texel = gpu_format_size(format),
                          .offset = h->size, .upload = upload, .download = download};
    h->size += ((VkDeviceSize)w * hgt * im->texel + 255) & ~(VkDeviceSize)255;
    return r;
}

static void copy_execute(const rg_context *ctx, void *user, bool down)
{
    harness *h = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    for (int i = 0; i < h->count; i++) {
        const harness_image *im = &h->images[i];
        if (down ? !im->download : !im->upload)
            continue;
        VkBufferImageCopy region = {.bufferOffset = im->offset,
                                    .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                                    .imageExtent = {im->width, im->height, 1}};
        if (down)
            vkCmdCopyImageToBuffer(cmd, rg_ctx_image(ctx, im->res), rg_ctx_layout(ctx, im->res),
                                   rg_ctx_buffer(ctx, h->r_host), 1, &region);
        else
            vkCmdCopyBufferToImage(cmd, rg_ctx_buffer(ctx, h->r_host), rg_ctx_image(ctx, im->res),
                                   rg_ctx_layout(ctx, im->res), 1, &region);
    }
}

static void upload_execute(const rg_context *ctx, void *user) { copy_execute(ctx, user, false); }
static void download_execute(const rg_context *ctx, void *user) { copy_execute(ctx, user, true); }

int harness_upload(harness *h)
{
    if (gpu_buffer_create(h->gpu, &(gpu_buffer_desc){.name = "harness host", .size = h->size,
                                                      .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                                               VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                      .host_visible = true}, &h->host) != VG_OK)
        return 1;
    memset(h->host.mapped, 0, h->size);
    h->r_host = rg_import_buffer(h->graph, &(rg_buffer_desc){"host", h->size},
                                 &(rg_import_desc){.initial = RG_TRANSFER_SRC, .final = RG_HOST_READ});
    rg_pass up = rg_pass_add(h->graph, &(rg_pass_desc){.name = "upload", .type = RG_PASS_TRANSFER,
                                                        .execute = upload_execute, .user = h});
    rg_use(h->graph, up, h->r_host, RG_TRANSFER_SRC);
    for (int i = 0; i < h->count; i++)
        if (h->images[i].upload)
            rg_use(h->graph, up, h->images[i].res, RG_TRANSFER_DST);
    return 0;
}

int harness_build(harness *h)
{
    rg_pass down = rg_pass_add(h->graph, &(rg_pass_desc){.name = "download", .type = RG_PASS_TRANSFER,
                                                          .execute = download_execute, .user = h});
    for (int i = 0; i < h->count; i++)
        if (h->images[i].download)
            rg_use(h->graph, down, h->images[i].res, RG_TRANSFER_SRC);
    rg_use(h->graph, down, h->r_host, RG_TRANSFER_DST);
    if (rg_compile(h->graph) != VG_OK || rg_realize(h->graph, h->gpu) != VG_OK)
        return 1;
    rg_bind_buffer(h->graph, h->r_host, h->host.buffer);
    return 0;
}

void *harness_data(harness *h, rg_res image)
{
    for (int i = 0; i < h->count; i++)
        if (h->images[i].res.id == image.id)
            return (uint8_t *)h->host.mapped + h->images[i].offset;
    return NULL;
}

int harness_run(harness *h)
{
    VkCommandBuffer cmd;
    if (gpu_oneshot_begin(h->gpu, &cmd) != VG_OK)
        return 1;
    rg_execute(h->graph, cmd, 0);
    return gpu_oneshot_submit(h->gpu, cmd) == VG_OK ? 0 : 1;
}

int harness_close(harness *h)
{
    rg_destroy(h->graph);
    gpu_buffer_destroy(h->gpu, &h->host);
    gpu_destroy(h->gpu);
    int messages = gpu_validation_messages();
    if (messages)
        fprintf(stderr, "validation reported %d WARNING/ERROR message(s)\n", messages);
    return messages;
}
