/* vergence — shadow, sky and G-buffer passes. */
#include "gbuffer_gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/pipeline.h"
#include "shared.h"

#include "gbuffer_frag.h"
#include "gbuffer_unlit_frag.h"
#include "gbuffer_vert.h"
#include "shadow_vert.h"
#include "sky_frag.h"
#include "sky_vert.h"

const VkFormat gbuffer_formats[4] = {
    [VG_GBUFFER_COLOR] = VK_FORMAT_R8G8B8A8_UNORM, /* sRGB-encoded by the shader */
    [VG_GBUFFER_DEPTH] = VK_FORMAT_R32_SFLOAT,
    [VG_GBUFFER_ID] = VK_FORMAT_R32_UINT,
    [VG_GBUFFER_MOTION] = VK_FORMAT_R32G32B32A32_SFLOAT,
};

struct gbuffer_gpu {
    frame_ctx *fc;
    VkPipeline shadow, sky, gbuffer;
    rg_res shadow_map, shadow_cache;
    /* The shadow cascades of the casters that stand still, kept while none of
     * them moves and the cascade's box stays (shadow.static); each frame the
     * shadow pass draws the others on a copy of it (shadow.copy). */
    gpu_image cache;
    uint8_t *in_cache;       /* instances: drawn into the cache */
    float *cache_placed;     /* instances x 16: their placements when the cache's set was chosen */
    float *last_placed;      /* instances x 16: the placements of the frame before */
    float cache_vp[VG_SHADOW_CASCADES][16]; /* the box each cascade of the cache was drawn with */
    bool cache_set, cache_valid[VG_SHADOW_CASCADES], have_last;
};

/* ------------------------------------------------------------------------- */
/* Passes                                                                    */
/* ------------------------------------------------------------------------- */

/* Draws the instances with in_cache[i] == cached (0 or 1) into cascade c's square
 * of the atlas (frame.c light_setup), cleared first when `clear`. */
static void shadow_draw(const gbuffer_gpu *p, VkCommandBuffer cmd, int c, bool cached, bool clear)
{
    const frame_ctx *fc = p->fc;
    uint32_t side = fc->desc.shadow_size;
    VkRect2D rect = {{(int32_t)(c * side), 0}, {side, side}};
    vkCmdSetViewport(cmd, 0, 1, &(VkViewport){(float)(c * side), 0, (float)side, (float)side, 0, 1});
    vkCmdSetScissor(cmd, 0, 1, &rect);
    if (clear)
        vkCmdClearAttachments(cmd, 1, &(VkClearAttachment){.aspectMask = VK_IMAGE_ASPECT_DEPTH_BIT,
                                                            .clearValue = {.depthStencil = {1.0f, 0}}},
                              1, &(VkClearRect){rect, 0, 1});
    vkCmdPushConstants(cmd, fc->scene_layout, VK_SHADER_STAGE_ALL_GRAPHICS, 0, sizeof(vg_draw_push),
                       &(vg_draw_push){.flags = (uint32_t)c});
    scene_gpu_draw_where(&fc->sg, cmd, fc->slot, fc->scene_layout, SCENE_INPUT_POSITIONS, 0, p->in_cache, cached);
}

static void shadow_begin(const gbuffer_gpu *p, const rg_context *ctx, VkCommandBuffer cmd)
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->shadow);
    frame_ctx_push_scene(p->fc, ctx, (rg_res){0});
    /* Slope-scaled bias keeps grazing surfaces free of acne. */
    vkCmdSetDepthBias(cmd, 1.0f, 0.0f, 1.75f);
}

/* Instance i is rigid and placed as it was the frame before. */
static bool standing_still(const gbuffer_gpu *p, const scene_state *st, int i)
{
    return p->have_last && scene_instance_rigid(p->fc->scene, st, i) &&
           !memcmp(st->placed + (size_t)i * 16, p->last_placed + (size_t)i * 16, 16 * sizeof(float));
}

/* Chooses what the cache holds and draws the cascades whose cache is stale.
 * Its set is the rigid instances that did not move since the frame before;
 * it is chosen again when one of them moves or another has come to rest
 * (so a thrown ball leaves it while it flies); a cascade is drawn again when
 * the set changed or its box moved. Depth keeps the nearest of all draws,
 * so the cached and the drawn casters give the map a single pass would. */
static void shadow_static_execute(const rg_context *ctx, void *user)
{
    gbuffer_gpu *p = user;
    const frame_ctx *fc = p->fc;
    const scene *s = fc->scene;
    const scene_state *st = &fc->sg.now;
    const vg_frame_ubo *u = fc->ubo[fc->slot].mapped;
    size_t mat = 16 * sizeof(float);
    bool keep = p->cache_set;
    for (int i = 0; i < s->instance_count && keep; i++)
        keep = p->in_cache[i] ? !memcmp(st->placed + (size_t)i * 16, p->cache_placed + (size_t)i * 16, mat)
                              : !standing_still(p, st, i);
    if (!keep) {
        for (int i = 0; i < s->instance_count; i++)
            p->in_cache[i] = standing_still(p, st, i);
        memcpy(p->cache_placed, st->placed, (size_t)s->instance_count * mat);
        memset(p->cache_valid, 0, sizeof p->cache_valid);
        p->cache_set = true;
    }
    memcpy(p->last_placed, st->placed, (size_t)s->instance_count * mat);
    p->have_last = true;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    bool begun = false;
    for (int c = 0; c < fc->shadow_cascades; c++) {
        if (p->cache_valid[c] && !memcmp(p->cache_vp[c], u->light_view_proj[c].m, mat))
            continue;
        if (!begun)
            shadow_begin(p, ctx, cmd);
        begun = true;
        shadow_draw(p, cmd, c, true, true);
        memcpy(p->cache_vp[c], u->light_view_proj[c].m, mat);
        p->cache_valid[c] = true;
    }
}

static void shadow_copy_execute(const rg_context *ctx, void *user)
{
    const gbuffer_gpu *p = user;
    uint32_t side = p->fc->desc.shadow_size;
    vkCmdCopyImage(rg_ctx_cmd(ctx), rg_ctx_image(ctx, p->shadow_cache), rg_ctx_layout(ctx, p->shadow_cache),
                   rg_ctx_image(ctx, p->shadow_map), rg_ctx_layout(ctx, p->shadow_map), 1,
                   &(VkImageCopy){.srcSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1},
                                  .dstSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1},
                                  .extent = {side * (uint32_t)p->fc->shadow_cascades, side, 1}});
}

/* The casters that move, on the copy of the cache. */
static void shadow_execute(const rg_context *ctx, void *user)
{
    const gbuffer_gpu *p = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    shadow_begin(p, ctx, cmd);
    for (int c = 0; c < p->fc->shadow_cascades; c++)
        shadow_draw(p, cmd, c, false, false);
}

static void gbuffer_execute(const rg_context *ctx, void *user)
{
    gbuffer_gpu *p = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    frame_ctx_push_scene(p->fc, ctx, p->shadow_map);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->fc->scene_layout, 1, 1,
                            &p->fc->sg.texture_set, 0, NULL);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->gbuffer);
    scene_gpu_draw(&p->fc->sg, cmd, p->fc->slot, p->fc->scene_layout, SCENE_INPUT_MOTION, 0);
    /* The sky last, behind the depth test: only what no surface covers. */
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->sky);
    vkCmdDraw(cmd, 3, 1, 0, 0);
}

/* A depth pass of the sun's casters into target. */
static void shadow_pass(rg_graph *g, const frame_resources *res, const char *name, rg_execute_fn execute,
                        gbuffer_gpu *p, rg_res target)
{
    rg_pass pass = rg_pass_add(g, &(rg_pass_desc){.name = name, .type = RG_PASS_GRAPHICS, .execute = execute,
                                                  .user = p});
    rg_use(g, pass, res->ubo, RG_UNIFORM);
    rg_use(g, pass, res->vertices, RG_VERTEX);
    rg_use(g, pass, res->indices, RG_INDEX);
    rg_use(g, pass, target, RG_DEPTH_WRITE);
}

void gbuffer_gpu_add(gbuffer_gpu *p, rg_graph *g, frame_resources *res)
{
    uint32_t w = p->fc->desc.width, h = p->fc->desc.height, sz = p->fc->desc.shadow_size;
    res->shadow = p->shadow_map =
        rg_image(g, &(rg_image_desc){"shadow.map", GBUFFER_DEPTH_FORMAT, VG_SHADOW_CASCADES * sz, sz, 1});
    p->shadow_cache = rg_import_image(g, &(rg_image_desc){"shadow.cache", GBUFFER_DEPTH_FORMAT, VG_SHADOW_CASCADES * sz,
                                                          sz, 1},
                                      &(rg_import_desc){RG_TRANSFER_SRC, RG_TRANSFER_SRC});
    gbuffer_targets t = gbuffer_gpu_targets(g, "gbuffer", w, h);
    res->color = t.color, res->depth = t.depth, res->ids = t.ids, res->motion = t.motion, res->zbuffer = t.zbuffer;

    shadow_pass(g, res, "shadow.static", shadow_static_execute, p, p->shadow_cache);
    rg_pass copy = rg_pass_add(g, &(rg_pass_desc){.name = "shadow.copy", .type = RG_PASS_TRANSFER,
                                                  .execute = shadow_copy_execute, .user = p});
    rg_use(g, copy, p->shadow_cache, RG_TRANSFER_SRC);
    rg_use(g, copy, res->shadow, RG_TRANSFER_DST);
    shadow_pass(g, res, "shadow", shadow_execute, p, res->shadow);

    rg_pass gbuf = rg_pass_add(g, &(rg_pass_desc){.name = "gbuffer", .type = RG_PASS_GRAPHICS,
                                                  .execute = gbuffer_execute, .user = p});
    rg_use(g, gbuf, res->ubo, RG_UNIFORM);
    rg_use(g, gbuf, res->vertices, RG_VERTEX);
    rg_use(g, gbuf, res->statics, RG_VERTEX);
    rg_use(g, gbuf, res->indices, RG_INDEX);
    rg_use(g, gbuf, res->shadow, RG_SAMPLED);
    gbuffer_gpu_targets_write(g, gbuf, &t);
}

gbuffer_targets gbuffer_gpu_targets(rg_graph *g, const char *prefix, uint32_t w, uint32_t h)
{
    static const char *const what[5] = {"color", "depth", "ids", "motion", "zbuffer"};
    const VkFormat formats[5] = {gbuffer_formats[VG_GBUFFER_COLOR], gbuffer_formats[VG_GBUFFER_DEPTH],
                                 gbuffer_formats[VG_GBUFFER_ID], gbuffer_formats[VG_GBUFFER_MOTION],
                                 GBUFFER_DEPTH_FORMAT};
    rg_res r[5];
    for (int i = 0; i < 5; i++) {
        char name[64]; /* the graph copies names */
        snprintf(name, sizeof name, "%s.%s", prefix, what[i]);
        r[i] = rg_image(g, &(rg_image_desc){name, formats[i], w, h, 1});
    }
    return (gbuffer_targets){r[0], r[1], r[2], r[3], r[4]};
}

void gbuffer_gpu_targets_write(rg_graph *g, rg_pass p, const gbuffer_targets *t)
{
    /* Attachment order = shader output locations (shared.h); the sky covers
     * every pixel the surfaces leave, so the colour targets need no clear. */
    rg_use(g, p, t->color, RG_COLOR_WRITE);
    rg_use(g, p, t->depth, RG_COLOR_WRITE);
    rg_use(g, p, t->ids, RG_COLOR_WRITE);
    rg_use(g, p, t->motion, RG_COLOR_WRITE);
    rg_use_clear(g, p, t->zbuffer, RG_DEPTH_WRITE, (VkClearValue){.depthStencil = {1.0f, 0}});
}

/* ------------------------------------------------------------------------- */
/* Pipelines                                                                 */
/* ------------------------------------------------------------------------- */

/* The cache and its bookkeeping; the image starts as the frame leaves it
 * (a copy source), its contents unused until a cascade is drawn. */
static vg_status shadow_cache_create(gbuffer_gpu *p)
{
    gpu *g = p->fc->gpu;
    size_t n = (size_t)(p->fc->scene->instance_count > 0 ? p->fc->scene->instance_count : 1);
    p->in_cache = calloc(n, 1);
    p->cache_placed = calloc(16 * n, sizeof(float));
    p->last_placed = calloc(16 * n, sizeof(float));
    if (!p->in_cache || !p->cache_placed || !p->last_placed)
        return VG_ERR_NOMEM;
    uint32_t sz = p->fc->desc.shadow_size;
    vg_status st = gpu_image_create(g, &(gpu_image_desc){.name = "shadow.cache", .format = GBUFFER_DEPTH_FORMAT,
                                                         .width = VG_SHADOW_CASCADES * sz, .height = sz,
                                                         .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT |
                                                                  VK_IMAGE_USAGE_TRANSFER_SRC_BIT},
                                    &p->cache);
    VkCommandBuffer cmd;
    if (st == VG_OK)
        st = gpu_oneshot_begin(g, &cmd);
    if (st != VG_OK)
        return st;
    gpu_cmd_enter_layout(cmd, p->cache.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    return gpu_oneshot_submit(g, cmd);
}

void gbuffer_gpu_bind(gbuffer_gpu *p, rg_graph *g)
{
    rg_bind_image(g, p->shadow_cache, p->cache.image, p->cache.view);
}

vg_status gbuffer_gpu_create(frame_ctx *fc, gbuffer_gpu **out)
{
    gpu *g = fc->gpu;
    gbuffer_gpu *p = calloc(1, sizeof *p);
    if (!p)
        return VG_ERR_NOMEM;
    p->fc = fc;
    /* The lit centre colour is only looked at in captures, mono frames and
     * the image-warping baseline; a warped stereo frame shades its eyes. */
    const render_desc *d = &fc->desc;
    bool lit = d->readback || d->stereo == FRAME_STEREO_OFF || d->stereo == FRAME_STEREO_IMAGEWARP;
    VkShaderModule svert = 0;
    vg_status st = GPU_SHADER(g, spv_shadow_vert, &svert);
    if (st == VG_OK) {
        VkVertexInputBindingDescription vb[SCENE_BINDING_COUNT];
        VkVertexInputAttributeDescription va[8];
        uint32_t nb, na;
        scene_gpu_vertex_input(SCENE_INPUT_POSITIONS, vb, &nb, va, &na);
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "shadow", .layout = fc->scene_layout, .vert = svert, .bindings = vb,
            .binding_count = nb, .attributes = va, .attribute_count = na, .depth_test = true,
            .depth_write = true, .depth_bias = true, .depth_format = GBUFFER_DEPTH_FORMAT}, &p->shadow);
    }
    if (svert)
        vkDestroyShaderModule(g->device, svert, g->alloc);
    if (st == VG_OK)
        st = gbuffer_gpu_pipelines_create(fc, "gbuffer", lit, &p->sky, &p->gbuffer);
    if (st == VG_OK)
        st = shadow_cache_create(p);
    if (st != VG_OK) {
        gbuffer_gpu_destroy(p);
        return st;
    }
    *out = p;
    return VG_OK;
}

void gbuffer_gpu_destroy(gbuffer_gpu *p)
{
    if (!p)
        return;
    gpu_pipelines_destroy(p->fc->gpu, (VkPipeline[]){p->shadow, p->sky, p->gbuffer}, 3);
    gpu_image_destroy(p->fc->gpu, &p->cache);
    free(p->in_cache);
    free(p->cache_placed);
    free(p->last_placed);
    free(p);
}

vg_status gbuffer_gpu_pipelines_create(frame_ctx *fc, const char *name, bool lit, VkPipeline *sky, VkPipeline *scene)
{
    gpu *g = fc->gpu;
    VkShaderModule vert = 0, frag = 0, skyv = 0, skyf = 0;
    vg_status st = GPU_SHADER(g, spv_gbuffer_vert, &vert);
    if (st == VG_OK)
        st = lit ? GPU_SHADER(g, spv_gbuffer_frag, &frag) : GPU_SHADER(g, spv_gbuffer_unlit_frag, &frag);
    if (st == VG_OK)
        st = GPU_SHADER(g, spv_sky_vert, &skyv);
    if (st == VG_OK)
        st = GPU_SHADER(g, spv_sky_frag, &skyf);
    char label[64];
    snprintf(label, sizeof label, "%s sky", name);
    if (st == VG_OK)
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = label, .layout = fc->scene_layout, .vert = skyv, .frag = skyf,
            .depth_test = true, .depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL, /* where the clear's 1 is left */
            .color_formats = gbuffer_formats, .color_count = 4, .depth_format = GBUFFER_DEPTH_FORMAT}, sky);
    VkVertexInputBindingDescription vb[SCENE_BINDING_COUNT];
    VkVertexInputAttributeDescription va[8];
    uint32_t nb, na;
    scene_gpu_vertex_input(SCENE_INPUT_MOTION, vb, &nb, va, &na);
    /* No culling: single-sided glTF surfaces seen from behind flip their
     * normal in the shader instead of leaving holes in depth and ids. */
    uint32_t computed = fc->sg.computed_saliency; /* gbuffer.glsl's SALIENCY_COMPUTED */
    VkSpecializationMapEntry entry = {0, 0, sizeof computed};
    if (st == VG_OK)
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = name, .layout = fc->scene_layout, .vert = vert, .frag = frag, .bindings = vb,
            .binding_count = nb, .attributes = va, .attribute_count = na, .depth_test = true,
            .depth_write = true, .color_formats = gbuffer_formats, .color_count = 4,
            .depth_format = GBUFFER_DEPTH_FORMAT, .spec = &(VkSpecializationInfo){1, &entry, sizeof computed, &computed}},
            scene);
    gpu_shaders_destroy(g, (VkShaderModule[]){vert, frag, skyv, skyf}, 4);
    return st;
}
