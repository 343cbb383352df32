/* vergence — buffers, images, one-shot commands, shader modules. */
#include <string.h>

#include "core/log.h"
#include "gpu.h"

/* ------------------------------------------------------------------------- */
/* Memory                                                                    */
/* ------------------------------------------------------------------------- */

static int find_memory_type(const gpu *g, uint32_t bits, VkMemoryPropertyFlags want)
{
    for (uint32_t i = 0; i < g->mem.memoryTypeCount; i++)
        if ((bits & (1u << i)) && (g->mem.memoryTypes[i].propertyFlags & want) == want)
            return (int)i;
    return -1;
}

static void count(gpu *g, VkDeviceSize size, bool host_visible)
{
    g->memory_bytes += size;
    g->host_visible_bytes += host_visible ? size : 0;
    g->allocations++;
    if (g->memory_bytes > g->memory_peak)
        g->memory_peak = g->memory_bytes;
}

static void uncount(gpu *g, VkDeviceSize size, bool host_visible)
{
    g->memory_bytes -= size;
    g->host_visible_bytes -= host_visible ? size : 0;
    g->allocations--;
}

/* A resource's memory: one dedicated allocation, or a block of the host's
 * allocator (gpu.hooks), which says its offset and, host-visible, its
 * mapping. */
static vg_status allocate(gpu *g, VkMemoryRequirements req, bool host_visible, const char *name,
                          gpu_memory_block *out, VkDeviceSize *size)
{
    *out = (gpu_memory_block){0};
    VkMemoryPropertyFlags want = host_visible
        ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
        : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    if (g->hooks.allocate) {
        VkResult r = g->hooks.allocate(g->hooks.user, name, &req, want, out);
        if (r != VK_SUCCESS || !out->memory) {
            vg_error("%s: the host's memory hook gave no memory (VkResult %d) for %llu bytes", name, (int)r,
                     (unsigned long long)req.size);
            *out = (gpu_memory_block){0};
            return r == VK_ERROR_OUT_OF_HOST_MEMORY ? VG_ERR_NOMEM : VG_ERR_VULKAN;
        }
        if (out->offset % (req.alignment ? req.alignment : 1) || (host_visible && !out->mapped)) {
            vg_error("%s: the host's memory hook gave offset %llu (alignment %llu)%s", name,
                     (unsigned long long)out->offset, (unsigned long long)req.alignment,
                     host_visible && !out->mapped ? " and no mapping for a host-visible request" : "");
            g->hooks.free(g->hooks.user, out);
            *out = (gpu_memory_block){0};
            return VG_ERR_VULKAN;
        }
        *size = req.size;
        count(g, req.size, host_visible);
        return VG_OK;
    }
    int type = find_memory_type(g, req.memoryTypeBits, want);
    if (type < 0 && !host_visible)
        type = find_memory_type(g, req.memoryTypeBits, 0);
    if (type < 0) {
        vg_error("%s: no suitable Vulkan memory type", name);
        return VG_ERR_DEVICE;
    }
    VkMemoryAllocateInfo info = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = req.size,
        .memoryTypeIndex = (uint32_t)type,
    };
    VK_TRY(vkAllocateMemory(g->device, &info, g->alloc, &out->memory));
    GPU_NAME(g, VK_OBJECT_TYPE_DEVICE_MEMORY, out->memory, "%s memory", name);
    *size = req.size;
    count(g, req.size, host_visible);
    return VG_OK;
}

static void release(gpu *g, VkDeviceMemory memory, VkDeviceSize offset, void *mapped, void *user, VkDeviceSize size,
                    bool host_visible)
{
    if (!memory)
        return;
    if (g->hooks.allocate)
        g->hooks.free(g->hooks.user, &(gpu_memory_block){memory, offset, mapped, user});
    else
        vkFreeMemory(g->device, memory, g->alloc);
    uncount(g, size, host_visible);
}

/* ------------------------------------------------------------------------- */
/* Buffers                                                                   */
/* ------------------------------------------------------------------------- */

vg_status gpu_buffer_create(gpu *g, const gpu_buffer_desc *desc, gpu_buffer *out)
{
    *out = (gpu_buffer){0};
    const char *name = desc->name ? desc->name : "buffer";
    VkBufferCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .size = desc->size ? desc->size : 4,
        .usage = desc->usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
    };
    VK_TRY(vkCreateBuffer(g->device, &info, g->alloc, &out->buffer));
    GPU_NAME(g, VK_OBJECT_TYPE_BUFFER, out->buffer, "%s", name);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(g->device, out->buffer, &req);
    gpu_memory_block block;
    vg_status st = allocate(g, req, desc->host_visible, name, &block, &out->memory_size);
    out->memory = block.memory;
    out->memory_offset = block.offset;
    out->memory_user = block.user;
    out->mapped = block.mapped;
    out->host_visible = desc->host_visible;
    if (st != VG_OK) {
        gpu_buffer_destroy(g, out);
        return st;
    }
    VK_TRY(vkBindBufferMemory(g->device, out->buffer, out->memory, out->memory_offset));
    if (desc->host_visible && !g->hooks.allocate)
        VK_TRY(vkMapMemory(g->device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped));
    out->size = info.size;
    return VG_OK;
}

void gpu_buffer_destroy(gpu *g, gpu_buffer *b)
{
    if (!b)
        return;
    if (b->buffer)
        vkDestroyBuffer(g->device, b->buffer, g->alloc);
    release(g, b->memory, b->memory_offset, b->mapped, b->memory_user, b->memory_size, b->host_visible);
    *b = (gpu_buffer){0};
}

vg_status gpu_buffer_view_create(gpu *g, VkBuffer buffer, VkFormat format, VkDeviceSize range, const char *name,
                                 VkBufferView *out)
{
    *out = VK_NULL_HANDLE;
    uint32_t texel = gpu_format_size(format);
    uint64_t elements = range / (texel ? texel : 1), limit = g->props.limits.maxTexelBufferElements;
    if (elements > limit) {
        vg_error("%s: %llu texels, more than the device's texel buffer limit (%llu)", name,
                 (unsigned long long)elements, (unsigned long long)limit);
        return VG_ERR_DEVICE;
    }
    VK_TRY(vkCreateBufferView(g->device, &(VkBufferViewCreateInfo){.sType = VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO,
                                                                   .buffer = buffer, .format = format, .range = range},
                              g->alloc, out));
    GPU_NAME(g, VK_OBJECT_TYPE_BUFFER_VIEW, *out, "%s", name);
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Images                                                                    */
/* ------------------------------------------------------------------------- */

VkImageAspectFlags gpu_format_aspect(VkFormat f)
{
    switch (f) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_D32_SFLOAT:
        return VK_IMAGE_ASPECT_DEPTH_BIT;
    case VK_FORMAT_D24_UNORM_S8_UINT:
    case VK_FORMAT_D32_SFLOAT_S8_UINT:
        return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
    default:
        return VK_IMAGE_ASPECT_COLOR_BIT;
    }
}

uint32_t gpu_format_size(VkFormat f)
{
    switch (f) {
    case VK_FORMAT_R8_UNORM: case VK_FORMAT_R8_UINT: return 1;
    case VK_FORMAT_R16_SFLOAT: case VK_FORMAT_D16_UNORM: case VK_FORMAT_R8G8_UNORM: return 2;
    case VK_FORMAT_R8G8B8A8_UNORM: case VK_FORMAT_R8G8B8A8_SRGB: case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_SRGB: case VK_FORMAT_R32_SFLOAT: case VK_FORMAT_R32_UINT:
    case VK_FORMAT_D32_SFLOAT: case VK_FORMAT_R16G16_SFLOAT: case VK_FORMAT_A2B10G10R10_UNORM_PACK32:
        return 4;
    case VK_FORMAT_R32G32_SFLOAT: case VK_FORMAT_R16G16B16A16_SFLOAT: return 8;
    case VK_FORMAT_R32G32B32A32_SFLOAT: case VK_FORMAT_R32G32B32A32_UINT: return 16;
    default: return 0;
    }
}

vg_status gpu_image_create(gpu *g, const gpu_image_desc *desc, gpu_image *out)
{
    *out = (gpu_image){0};
    const char *name = desc->name ? desc->name : "image";
    uint32_t layers = desc->layers ? desc->layers : 1;
    VkImageCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
        .imageType = VK_IMAGE_TYPE_2D,
        .format = desc->format,
        .extent = {desc->width, desc->height, 1},
        .mipLevels = 1,
        .arrayLayers = layers,
        .samples = VK_SAMPLE_COUNT_1_BIT,
        .tiling = VK_IMAGE_TILING_OPTIMAL,
        .usage = desc->usage,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
    };
    VK_TRY(vkCreateImage(g->device, &info, g->alloc, &out->image));
    GPU_NAME(g, VK_OBJECT_TYPE_IMAGE, out->image, "%s", name);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(g->device, out->image, &req);
    gpu_memory_block block;
    vg_status st = allocate(g, req, false, name, &block, &out->memory_size);
    out->memory = block.memory;
    out->memory_offset = block.offset;
    out->memory_user = block.user;
    if (st != VG_OK) {
        gpu_image_destroy(g, out);
        return st;
    }
    VK_TRY(vkBindImageMemory(g->device, out->image, out->memory, out->memory_offset));
    out->format = desc->format;
    out->width = desc->width;
    out->height = desc->height;
    out->layers = layers;
    /* An image only copied to and from has no view. */
    const VkImageUsageFlags viewed = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
                                     VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT;
    if (!(desc->usage & viewed))
        return VG_OK;
    VkImageViewCreateInfo view = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = out->image,
        .viewType = layers > 1 ? VK_IMAGE_VIEW_TYPE_2D_ARRAY : VK_IMAGE_VIEW_TYPE_2D,
        .format = desc->format,
        .subresourceRange = {gpu_format_aspect(desc->format), 0, 1, 0, layers},
    };
    VK_TRY(vkCreateImageView(g->device, &view, g->alloc, &out->view));
    GPU_NAME(g, VK_OBJECT_TYPE_IMAGE_VIEW, out->view, "%s view", name);
    return VG_OK;
}

void gpu_image_destroy(gpu *g, gpu_image *img)
{
    if (!img)
        return;
    if (img->view)
        vkDestroyImageView(g->device, img->view, g->alloc);
    if (img->image)
        vkDestroyImage(g->device, img->image, g->alloc);
    release(g, img->memory, img->memory_offset, NULL, img->memory_user, img->memory_size, false);
    *img = (gpu_image){0};
}

/* ------------------------------------------------------------------------- */
/* One-shot commands                                                         */
/* ------------------------------------------------------------------------- */

vg_status gpu_oneshot_begin(gpu *g, VkCommandBuffer *cmd)
{
    VkCommandBufferAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = g->pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    VK_TRY(vkAllocateCommandBuffers(g->device, &alloc, cmd));
    GPU_NAME(g, VK_OBJECT_TYPE_COMMAND_BUFFER, *cmd, "one-shot commands");
    VkCommandBufferBeginInfo begin = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
    };
    VK_TRY(vkBeginCommandBuffer(*cmd, &begin));
    return VG_OK;
}

vg_status gpu_oneshot_submit(gpu *g, VkCommandBuffer cmd)
{
    VK_TRY(vkEndCommandBuffer(cmd));
    VkFence fence;
    VkFenceCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VK_TRY(vkCreateFence(g->device, &fi, g->alloc, &fence));
    GPU_NAME(g, VK_OBJECT_TYPE_FENCE, fence, "one-shot fence");
    VkResult r = gpu_queue_submit(g, cmd, VK_NULL_HANDLE, 0, VK_NULL_HANDLE, fence);
    if (r == VK_SUCCESS)
        r = vkWaitForFences(g->device, 1, &fence, VK_TRUE, UINT64_MAX);
    vkDestroyFence(g->device, fence, g->alloc);
    vkFreeCommandBuffers(g->device, g->pool, 1, &cmd);
    VK_TRY(r);
    return VG_OK;
}

void gpu_cmd_enter_layout(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout layout)
{
    VkImageMemoryBarrier2 b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
        .srcStageMask = VK_PIPELINE_STAGE_2_NONE,
        .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
        .dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
        .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
        .newLayout = layout,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = image,
        .subresourceRange = {aspect, 0, VK_REMAINING_MIP_LEVELS, 0, VK_REMAINING_ARRAY_LAYERS},
    };
    vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                   .imageMemoryBarrierCount = 1, .pImageMemoryBarriers = &b});
}

void gpu_cmd_mark(VkCommandBuffer cmd, VkBuffer buffer, uint32_t value)
{
    VkMemoryBarrier2 before = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                               .srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                               .dstStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT};
    vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                   .memoryBarrierCount = 1, .pMemoryBarriers = &before});
    vkCmdFillBuffer(cmd, buffer, 0, 4, value);
    VkBufferMemoryBarrier2 after = {.sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2,
                                    .srcStageMask = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT,
                                    .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                    .dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT,
                                    .dstAccessMask = VK_ACCESS_2_HOST_READ_BIT,
                                    .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                    .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                    .buffer = buffer, .offset = 0, .size = 4};
    vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                   .bufferMemoryBarrierCount = 1, .pBufferMemoryBarriers = &after});
}

vg_status gpu_image_upload(gpu *g, gpu_image *img, const void *pixels, size_t size)
{
    gpu_buffer staging;
    vg_status st = gpu_buffer_create(g, &(gpu_buffer_desc){
        .name = "upload staging", .size = size, .usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
        .host_visible = true}, &staging);
    if (st != VG_OK)
        return st;
    memcpy(staging.mapped, pixels, size);
    VkCommandBuffer cmd;
    st = gpu_oneshot_begin(g, &cmd);
    if (st != VG_OK) {
        gpu_buffer_destroy(g, &staging);
        return st;
    }
    VkImageSubresourceRange range = {gpu_format_aspect(img->format), 0, 1, 0, img->layers};
    VkImageMemoryBarrier2 to_dst = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
        .srcStageMask = VK_PIPELINE_STAGE_2_NONE,
        .dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
        .dstAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
        .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
        .newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = img->image,
        .subresourceRange = range,
    };
    vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                   .imageMemoryBarrierCount = 1,
                                                   .pImageMemoryBarriers = &to_dst});
    VkBufferImageCopy region = {
        .imageSubresource = {gpu_format_aspect(img->format), 0, 0, img->layers},
        .imageExtent = {img->width, img->height, 1},
    };
    vkCmdCopyBufferToImage(cmd, staging.buffer, img->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    VkImageMemoryBarrier2 to_read = to_dst;
    to_read.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    to_read.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
    to_read.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    to_read.dstAccessMask = VK_ACCESS_2_SHADER_SAMPLED_READ_BIT;
    to_read.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    to_read.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                   .imageMemoryBarrierCount = 1,
                                                   .pImageMemoryBarriers = &to_read});
    st = gpu_oneshot_submit(g, cmd);
    gpu_buffer_destroy(g, &staging);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Shaders                                                                   */
/* ------------------------------------------------------------------------- */

vg_status gpu_shader_create(gpu *g, const uint32_t *code, size_t size, const char *name,
                            VkShaderModule *out)
{
    VkShaderModuleCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
        .codeSize = size,
        .pCode = code,
    };
    VK_TRY(vkCreateShaderModule(g->device, &info, g->alloc, out));
    GPU_NAME(g, VK_OBJECT_TYPE_SHADER_MODULE, *out, "%s", name);
    return VG_OK;
}
