/* vergence — the sun and its shadow: the cascades set up on the CPU and the
 * passes that draw them (render/shadow_gpu.h). */
#include "shadow_gpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CGLM_FORCE_DEPTH_ZERO_TO_ONE /* Vulkan's clip depth, as the cameras' (scene/camera.c) */
#include <cglm/cglm.h>

#include "gbuffer_gpu.h"
#include "gpu/pipeline.h"
#include "scene_gpu.h"
#include "shared.h"

#include "shadow_vert.h"

struct shadow_gpu {
    frame_ctx *fc;
    uint32_t size;           /* a cascade's side, texels */
    VkPipeline pipeline;
    rg_res map, cache_res;
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
/* The cascades                                                              */
/* ------------------------------------------------------------------------- */

/* The shadow map's texels kept free around a cascade's content, so the 4x4
 * block of the filter (shade.glsl) never reads the neighbouring cascade. */
#define SHADOW_MARGIN_TEXELS 4.0f
/* The near cascade takes over where a texel of the whole scene's would cover
 * more than this many screen pixels (its staircase shows along shadow edges). */
#define SHADOW_SPLIT_PX 2.0f

/* An orthographic box of half-width r around (x, y) of the light's view. */
static void cascade(mat4 light_view, float x, float y, float r, float z_lo, float z_hi, vgx_mat4 *out)
{
    mat4 proj, vp;
    glm_ortho(x - r, x + r, y - r, y + r, z_lo, z_hi, proj);
    glm_mat4_mul(proj, light_view, vp);
    memcpy(out->m, vp, sizeof vp);
}

/* Sun: low in the sky to the left and behind the viewer, so shadows fall
 * into the scene and give depth cues (a fixed light keeps captures stable).
 *
 * Two cascades share one atlas (VG_SHADOW_CASCADES). Cascade 0 covers the
 * scene's bounding sphere now. Cascade 1 covers the bounding sphere of the
 * view frustum from the near plane to the split depth: the depth at which a
 * texel of the scene at rest (its bounds at t = 0, so the split stays put
 * while a ball stretches the bounds) would cover SHADOW_SPLIT_PX pixels.
 * Its size depends on the camera's field of view only, and its centre moves
 * in whole texels of the light's view (whose axes are fixed: the sun's), so
 * its shadow edges do not crawl as the camera moves. Without a perspective
 * camera, or when it would be less than twice as fine as cascade 0, there is
 * one. */
void shadow_gpu_setup(shadow_gpu *p, vg_frame_ubo *u)
{
    frame_ctx *fc = p->fc;
    vec3 sun = {-0.42f, 0.74f, 0.52f};
    glm_vec3_normalize(sun);
    const scene_state *st = &fc->sg->now;
    const vg_camera *cam = &fc->cam;
    float size = (float)p->size, keep = size / (size - 2.0f * SHADOW_MARGIN_TEXELS);
    vec3 lo, hi, centre, up = {0, 1, 0}, origin = {0, 0, 0};
    glm_vec3_copy((float *)st->bounds_min, lo);
    glm_vec3_copy((float *)st->bounds_max, hi);
    glm_vec3_center(lo, hi, centre);
    float radius = 0.5f * glm_vec3_distance(lo, hi) + 0.01f;
    if (fabsf(sun[1]) > 0.99f)
        glm_vec3_copy((vec3){0, 0, 1}, up);
    /* The light's view: a rotation (and a shift along its axis) only. */
    mat4 view;
    glm_lookat(sun, origin, up, view);
    vec3 c;
    glm_mat4_mulv3(view, centre, 1.0f, c);
    /* Every caster lies in the scene's sphere: one depth range for both. */
    float z_lo = -c[2] - 2.0f * radius, z_hi = -c[2] + 2.0f * radius;
    float r0 = radius * keep;
    cascade(view, c[0], c[1], r0, z_lo, z_hi, &u->light_view_proj[0]);
    float texel[2] = {2.0f * r0 / size, 0.0f}, split = 0.0f;

    if (!cam->orthographic && cam->yfov > 0.0f) {
        const scene *sc = fc->scene;
        float rest = 0.5f * glm_vec3_distance((float *)sc->bounds_min, (float *)sc->bounds_max) + 0.01f;
        float px_at_1m = 2.0f * tanf(0.5f * cam->yfov) / (float)fc->height;
        float d = 2.0f * rest * keep / size / (SHADOW_SPLIT_PX * px_at_1m);
        /* The smallest sphere around the frustum's slice [near, d]: k^2 is
         * the squared tangent of the corner rays' angle to the axis. */
        float n = cam->znear, k2 = tanf(0.5f * cam->yfov) * tanf(0.5f * cam->yfov) * (1.0f + cam->aspect * cam->aspect);
        float along = fminf(0.5f * (d + n) * (1.0f + k2), d);
        float r1 = sqrtf((d - along) * (d - along) + d * d * k2) * keep;
        if (d > n && r1 < 0.5f * r0) {
            vec3 mid, m;
            glm_vec3_scale((float *)cam->forward, along, mid);
            glm_vec3_add((float *)cam->position, mid, mid);
            glm_mat4_mulv3(view, mid, 1.0f, m);
            float t = 2.0f * r1 / size;
            cascade(view, t * floorf(m[0] / t + 0.5f), t * floorf(m[1] / t + 0.5f), r1, z_lo, z_hi,
                           &u->light_view_proj[1]);
            texel[1] = t;
            split = d;
        }
    }
    fc->shadow_cascades = split > 0.0f ? 2 : 1;
    memcpy(u->sun_dir.v, (float[4]){sun[0], sun[1], sun[2], 0.0f}, 16);
    memcpy(u->shadow.v, (float[4]){split, texel[0], texel[1], 0.0f}, 16);
    memcpy(u->sun_color.v, (float[4]){3.1f, 2.9f, 2.6f, 0.55f}, 16);
    memcpy(u->sky_zenith.v, (float[4]){0.23f, 0.42f, 0.78f, 0.0035f}, 16);
    memcpy(u->sky_horizon.v, (float[4]){0.78f, 0.86f, 0.95f, 0.85f}, 16);
    memcpy(u->ground_color.v, (float[4]){0.30f, 0.27f, 0.22f, 0.0f}, 16);
}

/* ------------------------------------------------------------------------- */
/* Passes                                                                    */
/* ------------------------------------------------------------------------- */

/* Draws the instances with in_cache[i] == cached (0 or 1) into cascade c's square
 * of the atlas (shadow_gpu_setup), cleared first when `clear`. */
static void shadow_draw(const shadow_gpu *p, VkCommandBuffer cmd, int c, bool cached, bool clear)
{
    const frame_ctx *fc = p->fc;
    uint32_t side = p->size;
    VkRect2D rect = {{(int32_t)(c * side), 0}, {side, side}};
    vkCmdSetViewport(cmd, 0, 1, &(VkViewport){(float)(c * side), 0, (float)side, (float)side, 0, 1});
    vkCmdSetScissor(cmd, 0, 1, &rect);
    if (clear)
        vkCmdClearAttachments(cmd, 1, &(VkClearAttachment){.aspectMask = VK_IMAGE_ASPECT_DEPTH_BIT,
                                                            .clearValue = {.depthStencil = {1.0f, 0}}},
                              1, &(VkClearRect){rect, 0, 1});
    vkCmdPushConstants(cmd, fc->scene_layout, VK_SHADER_STAGE_ALL_GRAPHICS, 0, sizeof(vg_draw_push),
                       &(vg_draw_push){.flags = (uint32_t)c});
    scene_gpu_draw_where(fc->sg, cmd, fc->slot, fc->scene_layout, SCENE_INPUT_POSITIONS, 0, p->in_cache, cached);
}

static void shadow_begin(const shadow_gpu *p, const rg_context *ctx, VkCommandBuffer cmd)
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->pipeline);
    frame_ctx_push_scene(p->fc, ctx, (rg_res){0});
    /* Slope-scaled bias keeps grazing surfaces free of acne. */
    vkCmdSetDepthBias(cmd, 1.0f, 0.0f, 1.75f);
}

/* Instance i is rigid and placed as it was the frame before. */
static bool standing_still(const shadow_gpu *p, const scene_state *st, int i)
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
static void static_execute(const rg_context *ctx, void *user)
{
    shadow_gpu *p = user;
    const frame_ctx *fc = p->fc;
    const scene *s = fc->scene;
    const scene_state *st = &fc->sg->now;
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

static void copy_execute(const rg_context *ctx, void *user)
{
    const shadow_gpu *p = user;
    uint32_t side = p->size;
    vkCmdCopyImage(rg_ctx_cmd(ctx), rg_ctx_image(ctx, p->cache_res), rg_ctx_layout(ctx, p->cache_res),
                   rg_ctx_image(ctx, p->map), rg_ctx_layout(ctx, p->map), 1,
                   &(VkImageCopy){.srcSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1},
                                  .dstSubresource = {VK_IMAGE_ASPECT_DEPTH_BIT, 0, 0, 1},
                                  .extent = {side * (uint32_t)p->fc->shadow_cascades, side, 1}});
}

/* The casters that move, on the copy of the cache. */
static void shadow_execute(const rg_context *ctx, void *user)
{
    const shadow_gpu *p = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    shadow_begin(p, ctx, cmd);
    for (int c = 0; c < p->fc->shadow_cascades; c++)
        shadow_draw(p, cmd, c, false, false);
}

/* A depth pass of the sun's casters into target. */
static void shadow_pass(rg_graph *g, const frame_resources *res, const char *name, rg_execute_fn execute,
                        shadow_gpu *p, rg_res target)
{
    rg_pass pass = rg_pass_add(g, &(rg_pass_desc){.name = name, .type = RG_PASS_GRAPHICS, .execute = execute,
                                                  .user = p});
    rg_use(g, pass, res->ubo, RG_UNIFORM);
    rg_use(g, pass, res->vertices, RG_VERTEX);
    rg_use(g, pass, res->indices, RG_INDEX);
    rg_use(g, pass, target, RG_DEPTH_WRITE);
}

void shadow_gpu_add(shadow_gpu *p, rg_graph *g, frame_resources *res)
{
    uint32_t sz = p->size;
    res->shadow = p->map =
        rg_image(g, &(rg_image_desc){"shadow.map", GBUFFER_DEPTH_FORMAT, VG_SHADOW_CASCADES * sz, sz, 1});
    p->cache_res = rg_import_image(g, &(rg_image_desc){"shadow.cache", GBUFFER_DEPTH_FORMAT, VG_SHADOW_CASCADES * sz,
                                                       sz, 1},
                                   &(rg_import_desc){RG_TRANSFER_SRC, RG_TRANSFER_SRC});
    shadow_pass(g, res, "shadow.static", static_execute, p, p->cache_res);
    rg_pass copy = rg_pass_add(g, &(rg_pass_desc){.name = "shadow.copy", .type = RG_PASS_TRANSFER,
                                                  .execute = copy_execute, .user = p});
    rg_use(g, copy, p->cache_res, RG_TRANSFER_SRC);
    rg_use(g, copy, res->shadow, RG_TRANSFER_DST);
    shadow_pass(g, res, "shadow", shadow_execute, p, res->shadow);
}

void shadow_gpu_bind(shadow_gpu *p, rg_graph *g)
{
    rg_bind_image(g, p->cache_res, p->cache.image, p->cache.view);
}

/* ------------------------------------------------------------------------- */
/* Lifetime                                                                  */
/* ------------------------------------------------------------------------- */

/* The cache and its bookkeeping; the image starts as the frame leaves it
 * (a copy source), its contents unused until a cascade is drawn. */
static vg_status shadow_cache_create(shadow_gpu *p)
{
    gpu *g = p->fc->gpu;
    size_t n = (size_t)(p->fc->scene->instance_count > 0 ? p->fc->scene->instance_count : 1);
    p->in_cache = calloc(n, 1);
    p->cache_placed = calloc(16 * n, sizeof(float));
    p->last_placed = calloc(16 * n, sizeof(float));
    if (!p->in_cache || !p->cache_placed || !p->last_placed)
        return VG_ERR_NOMEM;
    uint32_t sz = p->size;
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

vg_status shadow_gpu_create(frame_ctx *fc, const shadow_gpu_desc *desc, shadow_gpu **out)
{
    *out = NULL;
    gpu *g = fc->gpu;
    shadow_gpu *p = calloc(1, sizeof *p);
    if (!p)
        return VG_ERR_NOMEM;
    p->fc = fc;
    p->size = desc->size;
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
            .depth_write = true, .depth_bias = true, .depth_format = GBUFFER_DEPTH_FORMAT}, &p->pipeline);
    }
    if (svert)
        vkDestroyShaderModule(g->device, svert, g->alloc);
    if (st == VG_OK)
        st = shadow_cache_create(p);
    if (st != VG_OK) {
        shadow_gpu_destroy(p);
        return st;
    }
    *out = p;
    return VG_OK;
}

void shadow_gpu_destroy(shadow_gpu *p)
{
    if (!p)
        return;
    gpu_pipelines_destroy(p->fc->gpu, (VkPipeline[]){p->pipeline}, 1);
    gpu_image_destroy(p->fc->gpu, &p->cache);
    free(p->in_cache);
    free(p->cache_placed);
    free(p->last_placed);
    free(p);
}
