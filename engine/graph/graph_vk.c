/* vergence — frame graph: physical resources and command recording. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "graph_internal.h"

/* ------------------------------------------------------------------------- */
/* Physical resources                                                        */
/* ------------------------------------------------------------------------- */

void rg_unrealize(rg_graph *g)
{
    if (!g->gpu)
        return;
    for (uint32_t k = 0; k < g->phys_count; k++) {
        gpu_image_destroy(g->gpu, &g->phys[k].image);
        gpu_buffer_destroy(g->gpu, &g->phys[k].buffer);
    }
    for (int i = 0; i < RG_MAX_SLOTS; i++) {
        if (g->queries[i])
            vkDestroyQueryPool(g->gpu->device, g->queries[i], g->gpu->alloc);
        g->queries[i] = VK_NULL_HANDLE;
    }
    g->gpu = NULL;
}

vg_status rg_realize(rg_graph *g, gpu *gpu)
{
    if (!g->compiled) {
        vg_error("frame graph: realize before a successful compile");
        return VG_ERR_GRAPH;
    }
    rg_unrealize(g);
    g->gpu = gpu;
    for (uint32_t k = 0; k < g->phys_count; k++) {
        rg_physical *p = &g->phys[k];
        if (p->imported)
            continue;
        char name[96];
        snprintf(name, sizeof name, "rg %s", g->res[p->res].name);
        vg_status st = p->is_image
            ? gpu_image_create(gpu, &(gpu_image_desc){.name = name, .format = p->format, .width = p->width,
                                                      .height = p->height, .layers = p->layers,
                                                      .usage = p->image_usage}, &p->image)
            : gpu_buffer_create(gpu, &(gpu_buffer_desc){.name = name, .size = p->size,
                                                        .usage = p->buffer_usage}, &p->buffer);
        if (st != VG_OK)
            return st;
    }
    /* A CPU device's timestamps say when llvmpipe queued a pass's draws,
     * not when they ran: the frame times its passes by the wall clock there. */
    if (gpu->features.timestamps && !gpu->is_cpu && g->order_count) {
        VkQueryPoolCreateInfo q = {
            .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
            .queryType = VK_QUERY_TYPE_TIMESTAMP,
            .queryCount = 2 * g->order_count,
        };
        for (int i = 0; i < RG_MAX_SLOTS; i++) {
            VK_TRY(vkCreateQueryPool(gpu->device, &q, gpu->alloc, &g->queries[i]));
            GPU_NAME(gpu, VK_OBJECT_TYPE_QUERY_POOL, g->queries[i], "frame graph timestamps %d", i);
            /* Queries must be reset before their first use (hostQueryReset). */
            vkResetQueryPool(gpu->device, g->queries[i], 0, 2 * g->order_count);
        }
    }
    return VG_OK;
}

void rg_bind_image(rg_graph *g, rg_res res, VkImage image, VkImageView view)
{
    uint32_t k = rg_res_physical(g, res);
    if (k != RG_NONE && g->phys[k].imported) {
        g->phys[k].ext_image = image;
        g->phys[k].ext_view = view;
    }
}

void rg_bind_buffer(rg_graph *g, rg_res res, VkBuffer buffer)
{
    uint32_t k = rg_res_physical(g, res);
    if (k != RG_NONE && g->phys[k].imported)
        g->phys[k].ext_buffer = buffer;
}

static VkImage phys_image(const rg_physical *p) { return p->imported ? p->ext_image : p->image.image; }
static VkImageView phys_view(const rg_physical *p) { return p->imported ? p->ext_view : p->image.view; }
static VkBuffer phys_buffer(const rg_physical *p) { return p->imported ? p->ext_buffer : p->buffer.buffer; }

/* ------------------------------------------------------------------------- */
/* Recording                                                                 */
/* ------------------------------------------------------------------------- */

static void record_barriers(rg_graph *g, VkCommandBuffer cmd, uint32_t slot)
{
    uint32_t n;
    const rg_barrier *b = rg_barriers(g, slot, &n);
    if (!n)
        return;
    VkImageMemoryBarrier2 images[RG_MAX_RESOURCES];
    VkBufferMemoryBarrier2 buffers[RG_MAX_RESOURCES];
    uint32_t ni = 0, nb = 0;
    for (uint32_t i = 0; i < n && i < RG_MAX_RESOURCES; i++) {
        const rg_physical *p = &g->phys[b[i].physical];
        if (b[i].is_image) {
            images[ni++] = (VkImageMemoryBarrier2){
                .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
                .srcStageMask = b[i].src_stage,
                .srcAccessMask = b[i].src_access,
                .dstStageMask = b[i].dst_stage,
                .dstAccessMask = b[i].dst_access,
                .oldLayout = b[i].old_layout,
                .newLayout = b[i].new_layout,
                .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                .image = phys_image(p),
                .subresourceRange = {gpu_format_aspect(p->format), 0, 1, 0, p->layers},
            };
        } else {
            buffers[nb++] = (VkBufferMemoryBarrier2){
                .sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2,
                .srcStageMask = b[i].src_stage,
                .srcAccessMask = b[i].src_access,
                .dstStageMask = b[i].dst_stage,
                .dstAccessMask = b[i].dst_access,
                .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                .buffer = phys_buffer(p),
                .size = VK_WHOLE_SIZE,
            };
        }
    }
    vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){
                                   .sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                   .bufferMemoryBarrierCount = nb,
                                   .pBufferMemoryBarriers = buffers,
                                   .imageMemoryBarrierCount = ni,
                                   .pImageMemoryBarriers = images,
                               });
}

/* Begins dynamic rendering over the pass's attachments, in declaration order. */
static VkExtent2D begin_rendering(rg_graph *g, VkCommandBuffer cmd, uint32_t pass)
{
    VkRenderingAttachmentInfo colors[8], depth = {0};
    uint32_t nc = 0, layers = 1;
    bool has_depth = false;
    VkExtent2D extent = {0, 0};
    for (uint32_t i = 0; i < g->use_count; i++) {
        const rg_use_info *u = &g->use[i];
        if (u->pass != pass)
            continue;
        if (u->usage != RG_COLOR_WRITE && u->usage != RG_DEPTH_WRITE && u->usage != RG_DEPTH_READ)
            continue;
        const rg_resource *r = &g->res[u->res];
        extent = (VkExtent2D){r->width, r->height};
        layers = r->layers;
        VkRenderingAttachmentInfo a = {
            .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = phys_view(&g->phys[r->physical]),
            .imageLayout = u->layout,
            .loadOp = u->clear ? VK_ATTACHMENT_LOAD_OP_CLEAR
                      : (u->load || u->usage == RG_DEPTH_READ) ? VK_ATTACHMENT_LOAD_OP_LOAD
                                                               : VK_ATTACHMENT_LOAD_OP_DONT_CARE,
            .storeOp = u->usage == RG_DEPTH_READ ? VK_ATTACHMENT_STORE_OP_NONE : VK_ATTACHMENT_STORE_OP_STORE,
            .clearValue = u->clear_value,
        };
        if (u->usage == RG_COLOR_WRITE && nc < 8)
            colors[nc++] = a;
        else if (u->usage != RG_COLOR_WRITE) {
            depth = a;
            has_depth = true;
        }
    }
    VkRenderingInfo info = {
        .sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
        .renderArea = {{0, 0}, extent},
        .layerCount = layers,
        .colorAttachmentCount = nc,
        .pColorAttachments = colors,
        .pDepthAttachment = has_depth ? &depth : NULL,
    };
    vkCmdBeginRendering(cmd, &info);
    vkCmdSetViewport(cmd, 0, 1, &(VkViewport){0, 0, (float)extent.width, (float)extent.height, 0, 1});
    vkCmdSetScissor(cmd, 0, 1, &(VkRect2D){{0, 0}, extent});
    return extent;
}

/* The o-th ordered pass with the barriers before it (timestamps around it
 * when `queries` is given). */
static void execute_one(rg_graph *g, VkCommandBuffer cmd, VkQueryPool queries, uint32_t o)
{
    uint32_t p = g->order[o];
    const rg_pass_info *pass = &g->pass[p];
    record_barriers(g, cmd, o);
    if (queries)
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT, queries, 2 * o);
    rg_context ctx = {.graph = g, .pass = p, .cmd = cmd};
    bool rendering = pass->type == RG_PASS_GRAPHICS;
    gpu_cmd_label_begin(g->gpu, cmd, pass->name);
    if (rendering)
        ctx.extent = begin_rendering(g, cmd, p);
    if (pass->execute)
        pass->execute(&ctx, pass->user);
    if (rendering)
        vkCmdEndRendering(cmd);
    gpu_cmd_label_end(g->gpu, cmd);
    if (queries)
        vkCmdWriteTimestamp2(cmd, VK_PIPELINE_STAGE_2_BOTTOM_OF_PIPE_BIT, queries, 2 * o + 1);
}

void rg_execute(rg_graph *g, VkCommandBuffer cmd, uint32_t slot)
{
    VkQueryPool queries = g->queries[slot % RG_MAX_SLOTS];
    if (queries)
        vkCmdResetQueryPool(cmd, queries, 0, 2 * g->order_count);
    for (uint32_t o = 0; o < g->order_count; o++)
        execute_one(g, cmd, queries, o);
    record_barriers(g, cmd, g->order_count);
}

void rg_execute_pass(rg_graph *g, VkCommandBuffer cmd, uint32_t o)
{
    if (o >= g->order_count)
        return;
    execute_one(g, cmd, VK_NULL_HANDLE, o);
    if (o + 1 == g->order_count)
        record_barriers(g, cmd, g->order_count);
}

void rg_execute_range(rg_graph *g, VkCommandBuffer cmd, uint32_t first, uint32_t end)
{
    if (first == 0) {
        VkMemoryBarrier2 host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                                 .srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                 .srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT,
                                 .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                                 .dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT};
        vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                       .memoryBarrierCount = 1, .pMemoryBarriers = &host});
    }
    for (uint32_t o = first; o < end; o++)
        rg_execute_pass(g, cmd, o);
}

uint32_t rg_timings(rg_graph *g, uint32_t slot, double *ms, uint32_t cap)
{
    uint32_t n = g->order_count < cap ? g->order_count : cap;
    uint64_t stamps[2 * RG_MAX_PASSES];
    VkQueryPool queries = g->queries[slot % RG_MAX_SLOTS];
    bool ok = queries &&
              vkGetQueryPoolResults(g->gpu->device, queries, 0, 2 * g->order_count, sizeof stamps, stamps,
                                    sizeof(uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) ==
                  VK_SUCCESS;
    double period = g->gpu ? g->gpu->props.limits.timestampPeriod : 0;
    for (uint32_t i = 0; i < n; i++)
        ms[i] = ok ? (double)(stamps[2 * i + 1] - stamps[2 * i]) * period * 1e-6 : NAN;
    return n;
}

/* ------------------------------------------------------------------------- */
/* Pass context                                                              */
/* ------------------------------------------------------------------------- */

static const rg_physical *ctx_phys(const rg_context *ctx, rg_res res)
{
    uint32_t k = rg_res_physical(ctx->graph, res);
    return k == RG_NONE ? NULL : &ctx->graph->phys[k];
}

VkCommandBuffer rg_ctx_cmd(const rg_context *ctx) { return ctx->cmd; }
VkExtent2D rg_ctx_extent(const rg_context *ctx) { return ctx->extent; }
struct gpu *rg_ctx_gpu(const rg_context *ctx) { return ctx->graph->gpu; }

VkImage rg_ctx_image(const rg_context *ctx, rg_res res)
{
    const rg_physical *p = ctx_phys(ctx, res);
    return p ? phys_image(p) : VK_NULL_HANDLE;
}

VkImageView rg_ctx_view(const rg_context *ctx, rg_res res)
{
    const rg_physical *p = ctx_phys(ctx, res);
    return p ? phys_view(p) : VK_NULL_HANDLE;
}

VkBuffer rg_ctx_buffer(const rg_context *ctx, rg_res res)
{
    const rg_physical *p = ctx_phys(ctx, res);
    return p ? phys_buffer(p) : VK_NULL_HANDLE;
}

VkImageLayout rg_ctx_layout(const rg_context *ctx, rg_res res)
{
    for (uint32_t i = 0; i < ctx->graph->use_count; i++)
        if (ctx->graph->use[i].pass == ctx->pass && ctx->graph->use[i].res == res.id - 1)
            return ctx->graph->use[i].layout;
    return VK_IMAGE_LAYOUT_UNDEFINED;
}

VkDescriptorImageInfo rg_ctx_sampled_info(const rg_context *ctx, rg_res res, VkSampler sampler)
{
    return (VkDescriptorImageInfo){sampler, rg_ctx_view(ctx, res), rg_ctx_layout(ctx, res)};
}

VkDescriptorImageInfo rg_ctx_image_info(const rg_context *ctx, rg_res res)
{
    return rg_ctx_sampled_info(ctx, res, VK_NULL_HANDLE);
}

/* The executor owns the physical resources: they go first, then the graph. */
void rg_destroy(rg_graph *g)
{
    if (!g)
        return;
    rg_unrealize(g);
    free(g->barriers);
    free(g);
}
