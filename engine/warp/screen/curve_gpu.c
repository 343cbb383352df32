/* vergence — warp.curve on the GPU. */
#include "curve_gpu.h"

#include <stdlib.h>

#include "shared.h"

#include "curve_bins_comp.h"
#include "curve_range_comp.h"
#include "curve_resolve_comp.h"

#define CURVE_TILE 64 /* = curve.glsl */

typedef struct curve_push {
    float far_depth;
    uint32_t tiles_x, tiles_y, pad;
} curve_push;

/* The range's two stages are one shader specialised (curve_range.comp). */
enum { K_RANGE_TILES, K_RANGE, K_BINS, K_RESOLVE };

struct curve_gpu {
    gpu *gpu;
    gpu_compute_kit kit;
    uint32_t tiles_x, tiles_y;
    float background;
    rg_res depth, target, curve, tiles_count, tiles_sum, tiles_offset;
    struct curve_step {
        curve_gpu *curve;
        uint32_t kernel;
    } steps[4];                  /* by kernel */
};

vg_status curve_gpu_create(gpu *g, uint32_t width, uint32_t height, curve_gpu **out)
{
    *out = NULL;
    curve_gpu *c = calloc(1, sizeof *c);
    if (!c)
        return VG_ERR_NOMEM;
    c->gpu = g;
    c->tiles_x = (width + CURVE_TILE - 1) / CURVE_TILE;
    c->tiles_y = (height + CURVE_TILE - 1) / CURVE_TILE;
    static const VkDescriptorType types[6] = {
        VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    static const uint32_t k_stage0[1] = {0}, k_stage1[1] = {1};
    vg_status st = gpu_compute_kit_create(g, &(gpu_compute_kit_desc){
        .name = "warp.curve", .types = types, .count = 6, .push_size = sizeof(curve_push),
        .kernels = {[K_RANGE_TILES] = GPU_KERNEL_SPEC(spv_curve_range_comp, "warp.curve.range.tiles", k_stage0),
                    [K_RANGE] = GPU_KERNEL_SPEC(spv_curve_range_comp, "warp.curve.range", k_stage1),
                    [K_BINS] = GPU_KERNEL(spv_curve_bins_comp, "warp.curve.bins"),
                    [K_RESOLVE] = GPU_KERNEL(spv_curve_resolve_comp, "warp.curve.resolve")}}, &c->kit);
    if (st != VG_OK) {
        curve_gpu_destroy(c);
        return st;
    }
    *out = c;
    return VG_OK;
}

void curve_gpu_destroy(curve_gpu *c)
{
    if (!c)
        return;
    gpu_compute_kit_destroy(c->gpu, &c->kit);
    free(c);
}

void curve_gpu_set_background(curve_gpu *c, float depth) { c->background = depth; }

static void bind(const curve_gpu *c, const rg_context *ctx, uint32_t kernel)
{
    bool images = kernel != K_RESOLVE; /* the resolve pass reads no images */
    VkDescriptorImageInfo depth = rg_ctx_image_info(ctx, c->depth);
    VkDescriptorImageInfo target = rg_ctx_image_info(ctx, c->target);
    VkDescriptorBufferInfo curve = {rg_ctx_buffer(ctx, c->curve), 0, VK_WHOLE_SIZE};
    VkDescriptorBufferInfo count = {rg_ctx_buffer(ctx, c->tiles_count), 0, VK_WHOLE_SIZE};
    VkDescriptorBufferInfo sum = {rg_ctx_buffer(ctx, c->tiles_sum), 0, VK_WHOLE_SIZE};
    VkDescriptorBufferInfo offset = {rg_ctx_buffer(ctx, c->tiles_offset), 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet wr[6] = {
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 0, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, .pImageInfo = &depth},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 1, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, .pImageInfo = &target},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 2, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &curve},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 3, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &count},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 4, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &sum},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 5, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &offset},
    };
    curve_push pc = {c->background, c->tiles_x, c->tiles_y, 0};
    gpu_compute_kit_bind(c->gpu, rg_ctx_cmd(ctx), &c->kit, kernel, images ? wr : wr + 2, images ? 6 : 4, &pc);
}

/* Each step one kernel of the kit: the per-tile kernels over the tiles, the
 * others one workgroup. The inverse-depth range takes two steps: each
 * 64x64 tile's into tile_count (the bins step overwrites it next), then one
 * workgroup over the tiles; one workgroup over every pixel took 2.4 ms at
 * 1920x1080 on an H200 and ran on one core of lavapipe. */
static void step_execute(const rg_context *ctx, void *user)
{
    const struct curve_step *step = user;
    curve_gpu *c = step->curve;
    bind(c, ctx, step->kernel);
    bool tiled = step->kernel == K_RANGE_TILES || step->kernel == K_BINS;
    vkCmdDispatch(rg_ctx_cmd(ctx), tiled ? c->tiles_x : 1, tiled ? c->tiles_y : 1, 1);
}

void curve_gpu_add(curve_gpu *c, rg_graph *g, rg_res depth, rg_res target, rg_res curve)
{
    c->depth = depth, c->target = target, c->curve = curve;
    for (uint32_t k = 0; k < 4; k++)
        c->steps[k] = (struct curve_step){c, k};
    uint64_t tiles = (uint64_t)c->tiles_x * c->tiles_y * VGX_CURVE_BINS * sizeof(uint32_t);
    c->tiles_count = rg_buffer(g, &(rg_buffer_desc){"warp.curve.tile_count", tiles});
    c->tiles_sum = rg_buffer(g, &(rg_buffer_desc){"warp.curve.tile_sum", tiles});
    c->tiles_offset = rg_buffer(g, &(rg_buffer_desc){"warp.curve.tile_offset", tiles});
    /* Both range steps bind the images (one descriptor layout); the first
     * reads them, the second the tiles' ranges. */
    rg_pass tiles_range = rg_pass_add(g, &(rg_pass_desc){.name = "warp.curve.range.tiles", .type = RG_PASS_COMPUTE,
                                                         .execute = step_execute, .user = &c->steps[K_RANGE_TILES]});
    rg_use(g, tiles_range, depth, RG_STORAGE_READ);
    rg_use(g, tiles_range, target, RG_STORAGE_READ);
    rg_use(g, tiles_range, c->tiles_count, RG_STORAGE_WRITE);
    rg_pass range = rg_pass_add(g, &(rg_pass_desc){.name = "warp.curve.range", .type = RG_PASS_COMPUTE,
                                                   .execute = step_execute, .user = &c->steps[K_RANGE]});
    rg_use(g, range, depth, RG_STORAGE_READ);
    rg_use(g, range, target, RG_STORAGE_READ);
    rg_use(g, range, c->tiles_count, RG_STORAGE_READ);
    rg_use(g, range, curve, RG_STORAGE_WRITE);
    rg_pass bins = rg_pass_add(g, &(rg_pass_desc){.name = "warp.curve.bins", .type = RG_PASS_COMPUTE,
                                                  .execute = step_execute, .user = &c->steps[K_BINS]});
    rg_use(g, bins, depth, RG_STORAGE_READ);
    rg_use(g, bins, target, RG_STORAGE_READ);
    rg_use(g, bins, curve, RG_STORAGE_READ);
    rg_use(g, bins, c->tiles_count, RG_STORAGE_WRITE);
    rg_use(g, bins, c->tiles_sum, RG_STORAGE_WRITE);
    rg_use(g, bins, c->tiles_offset, RG_STORAGE_WRITE);
    rg_pass resolve = rg_pass_add(g, &(rg_pass_desc){.name = "warp.curve.resolve", .type = RG_PASS_COMPUTE,
                                                     .execute = step_execute, .user = &c->steps[K_RESOLVE]});
    rg_use(g, resolve, c->tiles_count, RG_STORAGE_READ);
    rg_use(g, resolve, c->tiles_sum, RG_STORAGE_READ);
    rg_use(g, resolve, c->tiles_offset, RG_STORAGE_READ);
    rg_use(g, resolve, curve, RG_STORAGE_READ_WRITE);
}
