/* vergence — mid.keyframes: coarse renders of the window's keyframes. */
#include "keyframe_gpu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CGLM_FORCE_DEPTH_ZERO_TO_ONE
#include <cglm/cglm.h>

#include "gpu/pipeline.h"
#include "render/gbuffer_gpu.h"
#include "render/scene_gpu.h"
#include "shared.h"


#define UBO_STRIDE ((sizeof(vg_frame_ubo) + 255) & ~(size_t)255)

struct keyframe_gpu {
    frame_ctx *fc;
    keyframe_gpu_desc d;
    VkPipeline sky, scene;
    scene_state now, prev, next;
    gpu_buffer vertices[VG_FRAMES_IN_FLIGHT]; /* per tile: current (6 floats) | prev (3) | next (3) */
    gpu_buffer ubo[VG_FRAMES_IN_FLIGHT];      /* per tile: vg_frame_ubo */
    VkDeviceSize tile_bytes;
    rg_graph *graph;
    rg_res r_vertices, r_ubo;
    int tiles;                                /* this frame */
};

vg_status keyframe_gpu_create(frame_ctx *fc, const keyframe_gpu_desc *desc, keyframe_gpu **out)
{
    *out = NULL;
    keyframe_gpu *k = calloc(1, sizeof *k);
    if (!k)
        return VG_ERR_NOMEM;
    k->fc = fc;
    k->d = *desc;
    const scene *s = fc->scene;
    k->tile_bytes = (VkDeviceSize)(s->vertex_count ? s->vertex_count : 1) * 12 * sizeof(float);
    vg_status st = scene_state_init(s, &k->now);
    if (st == VG_OK) st = scene_state_init(s, &k->prev);
    if (st == VG_OK) st = scene_state_init(s, &k->next);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT && st == VG_OK; i++) {
        char name[64];
        snprintf(name, sizeof name, "mid.keyframes vertices slot %d", i);
        st = gpu_buffer_create(fc->gpu, &(gpu_buffer_desc){.name = name, .size = k->tile_bytes * desc->max_tiles,
                                                            .usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, .host_visible = true},
                               &k->vertices[i]);
        snprintf(name, sizeof name, "mid.keyframes constants slot %d", i);
        if (st == VG_OK)
            st = gpu_buffer_create(fc->gpu, &(gpu_buffer_desc){.name = name, .size = UBO_STRIDE * desc->max_tiles,
                                                                .usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                                                .host_visible = true}, &k->ubo[i]);
    }
    if (st == VG_OK)
        st = gbuffer_gpu_pipelines_create(fc, "mid.keyframes", false, &k->sky, &k->scene);
    if (st != VG_OK) {
        keyframe_gpu_destroy(k);
        return st;
    }
    *out = k;
    return VG_OK;
}

void keyframe_gpu_destroy(keyframe_gpu *k)
{
    if (!k)
        return;
    gpu *g = k->fc->gpu;
    gpu_pipelines_destroy(g, (VkPipeline[]){k->sky, k->scene}, 2);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT; i++) {
        gpu_buffer_destroy(g, &k->vertices[i]);
        gpu_buffer_destroy(g, &k->ubo[i]);
    }
    scene_state_free(&k->now);
    scene_state_free(&k->prev);
    scene_state_free(&k->next);
    free(k);
}

/* ------------------------------------------------------------------------- */
/* Per frame                                                                 */
/* ------------------------------------------------------------------------- */

static void tile_ubo(keyframe_gpu *k, const float *atlas_from_clip, const vg_camera *cam, const vg_camera *prev,
                     const vg_camera *next, vg_frame_ubo *u)
{
    frame_ctx *fc = k->fc;
    memcpy(u, fc->ubo[fc->slot].mapped, sizeof *u); /* light, sky, rig, display of this frame */
    mat4 a, vp, out, inv;
    memcpy(a, atlas_from_clip, sizeof a);
    const vg_camera *cams[3] = {cam, prev, next};
    float *dst[3] = {u->view_proj.m, u->view_proj_prev.m, u->view_proj_next.m};
    for (int i = 0; i < 3; i++) {
        memcpy(vp, cams[i]->view_proj, sizeof vp);
        glm_mat4_mul(a, vp, out);
        memcpy(dst[i], out, sizeof out);
    }
    memcpy(vp, u->view_proj.m, sizeof vp);
    glm_mat4_inv(vp, inv);
    memcpy(u->inv_view_proj.m, inv, sizeof inv);
    memcpy(u->view.m, cam->view, 64);
    memcpy(u->camera_pos.v, (float[4]){cam->position[0], cam->position[1], cam->position[2], cam->zfar}, 16);
    float aw = (float)k->d.nx, ah = (float)(k->d.ny * k->d.max_tiles);
    memcpy(u->viewport.v, (float[4]){aw, ah, 1.0f / aw, 1.0f / ah}, 16);
}

void keyframe_gpu_prepare(keyframe_gpu *k, const keyframe_gpu_tile *tiles, int count)
{
    frame_ctx *fc = k->fc;
    const scene *s = fc->scene;
    int slot = fc->slot;
    k->tiles = count < (int)k->d.max_tiles ? count : (int)k->d.max_tiles;
    float aspect = (float)fc->width / (float)fc->height;
    for (int m = 0; m < k->tiles; m++) {
        const keyframe_gpu_tile *tile = &tiles[m];
        const scene_past *known = scene_gpu_known(fc->sg);
        scene_evaluate_known(s, known, (float)tile->t, &k->now);
        scene_evaluate_known(s, known, (float)tile->t_prev, &k->prev);
        scene_evaluate_known(s, known, (float)tile->t_next, &k->next);
        vg_camera cam, cp, cn;
        scene_camera_resolve(s, &k->now, fc->camera, aspect, &cam);
        scene_camera_resolve(s, &k->prev, fc->camera, aspect, &cp);
        scene_camera_resolve(s, &k->next, fc->camera, aspect, &cn);
        tile_ubo(k, tile->atlas_from_clip, &cam, &cp, &cn, (vg_frame_ubo *)((uint8_t *)k->ubo[slot].mapped + UBO_STRIDE * m));
        float *v = (float *)((uint8_t *)k->vertices[slot].mapped + k->tile_bytes * m);
        float *pv = v + 6 * (size_t)s->vertex_count, *nv = pv + 3 * (size_t)s->vertex_count;
        for (uint32_t i = 0; i < s->vertex_count; i++) {
            memcpy(v + 6 * i, k->now.positions + 3 * i, 3 * sizeof(float));
            memcpy(v + 6 * i + 3, k->now.normals + 3 * i, 3 * sizeof(float));
        }
        memcpy(pv, k->prev.positions, (size_t)s->vertex_count * 3 * sizeof(float));
        memcpy(nv, k->next.positions, (size_t)s->vertex_count * 3 * sizeof(float));
    }
    rg_bind_buffer(k->graph, k->r_vertices, k->vertices[slot].buffer);
    rg_bind_buffer(k->graph, k->r_ubo, k->ubo[slot].buffer);
}

int keyframe_gpu_tiles(const keyframe_gpu *k) { return k->tiles; }

/* ------------------------------------------------------------------------- */
/* Pass                                                                      */
/* ------------------------------------------------------------------------- */

static void keyframes_execute(const rg_context *ctx, void *user)
{
    keyframe_gpu *k = user;
    frame_ctx *fc = k->fc;
    const scene *s = fc->scene;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    VkBuffer ubo = rg_ctx_buffer(ctx, k->r_ubo), verts = rg_ctx_buffer(ctx, k->r_vertices);
    VkDeviceSize nv = s->vertex_count;
    /* The scene's textures: computed saliency reads the base colour. */
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, fc->scene_layout, 1, 1, &fc->sg->texture_set, 0,
                            NULL);
    for (int m = 0; m < k->tiles; m++) {
        vkCmdSetScissor(cmd, 0, 1, &(VkRect2D){{0, (int32_t)(m * k->d.ny)}, {k->d.nx, k->d.ny}});
        VkDescriptorBufferInfo info = {ubo, UBO_STRIDE * (VkDeviceSize)m, sizeof(vg_frame_ubo)};
        VkWriteDescriptorSet w = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = VG_BINDING_FRAME,
                                  .descriptorCount = 1, .descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                                  .pBufferInfo = &info};
        fc->gpu->cmd_push_descriptor_set(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, fc->scene_layout, 0, 1, &w);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, k->sky);
        vkCmdDraw(cmd, 3, 1, 0, 0);
        if (!s->index_count)
            continue;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, k->scene);
        VkDeviceSize base = k->tile_bytes * (VkDeviceSize)m;
        VkBuffer buffers[4] = {verts, verts, verts, fc->sg->statics.buffer};
        VkDeviceSize offsets[4] = {base, base + nv * 6 * sizeof(float), base + nv * 9 * sizeof(float), 0};
        vkCmdBindVertexBuffers(cmd, 0, 4, buffers, offsets);
        vkCmdBindIndexBuffer(cmd, fc->sg->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
        for (int i = 0; i < s->instance_count; i++) {
            const scene_instance *in = &s->instances[i];
            scene_gpu_push_instance(fc->sg, cmd, fc->scene_layout, i, 0);
            vkCmdDrawIndexed(cmd, s->primitives[in->primitive].index_count, 1, in->first_index,
                             (int32_t)in->first_vertex, 0);
        }
    }
}

void keyframe_gpu_add(keyframe_gpu *k, rg_graph *g, const frame_resources *res, disparity_gpu_atlas *a)
{
    uint32_t w = k->d.nx, h = k->d.ny * k->d.max_tiles;
    k->graph = g;
    k->r_vertices = rg_import_buffer(g, &(rg_buffer_desc){"mid.keyframes.vertices", k->vertices[0].size},
                                     &(rg_import_desc){.initial = RG_VERTEX});
    k->r_ubo = rg_import_buffer(g, &(rg_buffer_desc){"mid.keyframes.ubo", k->ubo[0].size},
                                &(rg_import_desc){.initial = RG_UNIFORM});
    gbuffer_targets t = gbuffer_gpu_targets(g, "mid.keyframes", w, h);
    a->color = t.color, a->depth = t.depth, a->ids = t.ids, a->motion = t.motion;
    rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = "mid.keyframes", .type = RG_PASS_GRAPHICS,
                                               .execute = keyframes_execute, .user = k});
    rg_use(g, p, k->r_ubo, RG_UNIFORM);
    rg_use(g, p, k->r_vertices, RG_VERTEX);
    rg_use(g, p, res->statics, RG_VERTEX);
    rg_use(g, p, res->indices, RG_INDEX);
    /* Each rendered tile is covered by its sky first, the others are never read. */
    gbuffer_gpu_targets_write(g, p, &t);
}
