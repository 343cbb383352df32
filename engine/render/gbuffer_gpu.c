/* vergence — the sky and G-buffer passes. */
#include "gbuffer_gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/pipeline.h"
#include "scene_gpu.h"
#include "shared.h"

#include "gbuffer_frag.h"
#include "gbuffer_unlit_frag.h"
#include "gbuffer_vert.h"
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
    VkPipeline sky, gbuffer;
    rg_res shadow_map;       /* the sun's (shadow_gpu), sampled */
};

/* ------------------------------------------------------------------------- */
/* Passes                                                                    */
/* ------------------------------------------------------------------------- */

static void gbuffer_execute(const rg_context *ctx, void *user)
{
    gbuffer_gpu *p = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    frame_ctx_push_scene(p->fc, ctx, p->shadow_map);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->fc->scene_layout, 1, 1,
                            &p->fc->sg->texture_set, 0, NULL);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->gbuffer);
    scene_gpu_draw(p->fc->sg, cmd, p->fc->slot, p->fc->scene_layout, SCENE_INPUT_MOTION, 0);
    /* The sky last, behind the depth test: only what no surface covers. */
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->sky);
    vkCmdDraw(cmd, 3, 1, 0, 0);
}

void gbuffer_gpu_add(gbuffer_gpu *p, rg_graph *g, frame_resources *res)
{
    uint32_t w = p->fc->width, h = p->fc->height;
    gbuffer_targets t = gbuffer_gpu_targets(g, "gbuffer", w, h);
    res->color = t.color, res->depth = t.depth, res->ids = t.ids, res->motion = t.motion, res->zbuffer = t.zbuffer;
    p->shadow_map = res->shadow;
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

vg_status gbuffer_gpu_create(frame_ctx *fc, const gbuffer_gpu_desc *desc, gbuffer_gpu **out)
{
    gbuffer_gpu *p = calloc(1, sizeof *p);
    if (!p)
        return VG_ERR_NOMEM;
    p->fc = fc;
    vg_status st = gbuffer_gpu_pipelines_create(fc, "gbuffer", desc->lit, &p->sky, &p->gbuffer);
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
    gpu_pipelines_destroy(p->fc->gpu, (VkPipeline[]){p->sky, p->gbuffer}, 2);
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
    uint32_t computed = fc->sg->computed_saliency; /* gbuffer.glsl's SALIENCY_COMPUTED */
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
