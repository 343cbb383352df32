/* vergence — shadow, sky and G-buffer passes. */
#include "gbuffer_gpu.h"

#include <stdlib.h>

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
    rg_res shadow_map;
};

/* ------------------------------------------------------------------------- */
/* Passes                                                                    */
/* ------------------------------------------------------------------------- */

static void shadow_execute(const rg_context *ctx, void *user)
{
    gbuffer_gpu *p = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->shadow);
    frame_ctx_push_scene(p->fc, ctx, (rg_res){0});
    /* Slope-scaled bias keeps grazing surfaces free of acne. */
    vkCmdSetDepthBias(cmd, 1.0f, 0.0f, 1.75f);
    scene_gpu_draw(&p->fc->sg, cmd, p->fc->slot, p->fc->scene_layout, SCENE_INPUT_POSITIONS, 0);
}

static void gbuffer_execute(const rg_context *ctx, void *user)
{
    gbuffer_gpu *p = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    frame_ctx_push_scene(p->fc, ctx, p->shadow_map);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->fc->scene_layout, 1, 1,
                            &p->fc->sg.texture_set, 0, NULL);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->sky);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->gbuffer);
    scene_gpu_draw(&p->fc->sg, cmd, p->fc->slot, p->fc->scene_layout, SCENE_INPUT_MOTION, 0);
}

void gbuffer_gpu_add(gbuffer_gpu *p, rg_graph *g, frame_resources *res)
{
    uint32_t w = p->fc->desc.width, h = p->fc->desc.height, sz = p->fc->desc.shadow_size;
    res->shadow = p->shadow_map = rg_image(g, &(rg_image_desc){"shadow.map", GBUFFER_DEPTH_FORMAT, sz, sz, 1});
    res->color = rg_image(g, &(rg_image_desc){"gbuffer.color", gbuffer_formats[VG_GBUFFER_COLOR], w, h, 1});
    res->depth = rg_image(g, &(rg_image_desc){"gbuffer.depth", gbuffer_formats[VG_GBUFFER_DEPTH], w, h, 1});
    res->ids = rg_image(g, &(rg_image_desc){"gbuffer.ids", gbuffer_formats[VG_GBUFFER_ID], w, h, 1});
    res->motion = rg_image(g, &(rg_image_desc){"gbuffer.motion", gbuffer_formats[VG_GBUFFER_MOTION], w, h, 1});
    res->zbuffer = rg_image(g, &(rg_image_desc){"gbuffer.zbuffer", GBUFFER_DEPTH_FORMAT, w, h, 1});

    rg_pass shadow = rg_pass_add(g, &(rg_pass_desc){.name = "shadow", .type = RG_PASS_GRAPHICS,
                                                    .execute = shadow_execute, .user = p});
    rg_use(g, shadow, res->ubo, RG_UNIFORM);
    rg_use(g, shadow, res->vertices, RG_VERTEX);
    rg_use(g, shadow, res->indices, RG_INDEX);
    rg_use_clear(g, shadow, res->shadow, RG_DEPTH_WRITE, (VkClearValue){.depthStencil = {1.0f, 0}});

    rg_pass gbuf = rg_pass_add(g, &(rg_pass_desc){.name = "gbuffer", .type = RG_PASS_GRAPHICS,
                                                  .execute = gbuffer_execute, .user = p});
    rg_use(g, gbuf, res->ubo, RG_UNIFORM);
    rg_use(g, gbuf, res->vertices, RG_VERTEX);
    rg_use(g, gbuf, res->statics, RG_VERTEX);
    rg_use(g, gbuf, res->indices, RG_INDEX);
    rg_use(g, gbuf, res->shadow, RG_SAMPLED);
    /* Attachment order = shader output locations (shared.h); the sky covers
     * every pixel first, so the colour targets need no clear. */
    rg_use(g, gbuf, res->color, RG_COLOR_WRITE);
    rg_use(g, gbuf, res->depth, RG_COLOR_WRITE);
    rg_use(g, gbuf, res->ids, RG_COLOR_WRITE);
    rg_use(g, gbuf, res->motion, RG_COLOR_WRITE);
    rg_use_clear(g, gbuf, res->zbuffer, RG_DEPTH_WRITE, (VkClearValue){.depthStencil = {1.0f, 0}});
}

/* ------------------------------------------------------------------------- */
/* Pipelines                                                                 */
/* ------------------------------------------------------------------------- */

vg_status gbuffer_gpu_create(frame_ctx *fc, gbuffer_gpu **out)
{
    gpu *g = fc->gpu;
    gbuffer_gpu *p = calloc(1, sizeof *p);
    if (!p)
        return VG_ERR_NOMEM;
    p->fc = fc;
    VkShaderModule gvert = 0, gfrag = 0, svert = 0, skyv = 0, skyf = 0;
    /* The lit centre colour is only looked at in captures, mono frames and
     * the image-warping baseline; a warped stereo frame shades its eyes. */
    const frame_desc *d = &fc->desc;
    bool lit = d->readback || d->stereo == FRAME_STEREO_OFF || d->stereo == FRAME_STEREO_IMAGEWARP;
    vg_status st = GPU_SHADER(g, spv_gbuffer_vert, &gvert);
    if (st == VG_OK)
        st = lit ? GPU_SHADER(g, spv_gbuffer_frag, &gfrag) : GPU_SHADER(g, spv_gbuffer_unlit_frag, &gfrag);
    if (st == VG_OK) st = GPU_SHADER(g, spv_shadow_vert, &svert);
    if (st == VG_OK) st = GPU_SHADER(g, spv_sky_vert, &skyv);
    if (st == VG_OK) st = GPU_SHADER(g, spv_sky_frag, &skyf);

    VkVertexInputBindingDescription vb[SCENE_BINDING_COUNT];
    VkVertexInputAttributeDescription va[8];
    uint32_t nb, na;
    if (st == VG_OK) {
        scene_gpu_vertex_input(SCENE_INPUT_POSITIONS, vb, &nb, va, &na);
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "shadow", .layout = fc->scene_layout, .vert = svert, .bindings = vb,
            .binding_count = nb, .attributes = va, .attribute_count = na, .depth_test = true,
            .depth_write = true, .depth_bias = true, .depth_format = GBUFFER_DEPTH_FORMAT}, &p->shadow);
    }
    if (st == VG_OK)
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "sky", .layout = fc->scene_layout, .vert = skyv, .frag = skyf,
            .color_formats = gbuffer_formats, .color_count = 4, .depth_format = GBUFFER_DEPTH_FORMAT}, &p->sky);
    if (st == VG_OK) {
        scene_gpu_vertex_input(SCENE_INPUT_MOTION, vb, &nb, va, &na);
        /* No culling: single-sided glTF surfaces seen from behind flip their
         * normal in the shader instead of leaving holes in depth and ids. */
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "gbuffer", .layout = fc->scene_layout, .vert = gvert, .frag = gfrag, .bindings = vb,
            .binding_count = nb, .attributes = va, .attribute_count = na, .depth_test = true,
            .depth_write = true, .color_formats = gbuffer_formats, .color_count = 4,
            .depth_format = GBUFFER_DEPTH_FORMAT}, &p->gbuffer);
    }
    VkShaderModule mods[] = {gvert, gfrag, svert, skyv, skyf};
    for (size_t i = 0; i < sizeof mods / sizeof mods[0]; i++)
        if (mods[i])
            vkDestroyShaderModule(g->device, mods[i], NULL);
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
    VkDevice dev = p->fc->gpu->device;
    VkPipeline pipes[] = {p->shadow, p->sky, p->gbuffer};
    for (size_t i = 0; i < sizeof pipes / sizeof pipes[0]; i++)
        if (pipes[i])
            vkDestroyPipeline(dev, pipes[i], NULL);
    free(p);
}
