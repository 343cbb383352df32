/* vergence — stereo pair passes: the tessellated warp, two cameras, image
 * warping (the curve they follow: warp/screen). */
#include "warp_gpu.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

#include "gpu/pipeline.h"
#include "render/gbuffer_gpu.h"
#include "render/scene_gpu.h"
#include "shared.h"
#include "warp/screen/curve_gpu.h"

#include "cameras_vert.h"
#include "eye_frag.h"
#include "eye_measure_frag.h"
#include "eye_sky_frag.h"
#include "imagewarp_frag.h"
#include "imagewarp_vert.h"
#include "sky_vert.h"
#include "warp_tesc.h"
#include "warp_tese.h"
#include "warp_classify_comp.h"
#include "warp_compact_comp.h"
#include "warp_cull_comp.h"
#include "warp_edge_levels_comp.h"
#include "warp_edges_comp.h"
#include "warp_fill_apply_comp.h"
#include "warp_fill_find_comp.h"
#include "warp_fill_test_comp.h"
#include "warp_vertex_search_comp.h"
#include "warp_vertices_comp.h"
#include "warp_flat_vert.h"
#include "warp_vert.h"

/* What one eye pass draws. */
typedef enum eye_kind { EYE_WARP, EYE_CAMERAS, EYE_IMAGEWARP } eye_kind;

typedef struct eye_pass {
    warp_gpu *w;
    eye_kind kind;
    bool right;
} eye_pass;

struct warp_gpu {
    frame_ctx *fc;
    warp_gpu_desc desc;          /* its curve copied into `baked` and cleared */
    VkPipeline warp, warp_flat, cameras, imagewarp, sky;
    gpu_compute_kit classify;    /* K_CULL, K_VERTICES, K_VERTEX_SEARCH, K_EDGES, K_EDGE_LEVELS, K_CLASSIFY,
                                    K_COMPACT */
    gpu_compute_kit fill;        /* K_FILL_RESET, K_FILL_FIND, K_FILL_TEST, K_FILL_APPLY */
    gpu_buffer fill_header;      /* per eye: candidates, dispatch size over them (warp_fill.glsl) */
    gpu_buffer instances;        /* vg_warp_instance per scene instance */
    gpu_buffer chunks;           /* vg_warp_chunk: 256-triangle pieces of instances */
    gpu_buffer tri_edges, edges; /* each triangle's 3 edge ids; vg_warp_edge: every edge once */
    uint32_t edge_count;
    gpu_buffer vertex_seen;      /* per scene vertex: the stamp of the last frame that used it */
    gpu_buffer classify_work;    /* the edges to sample, by bucket, and the vertices to search
                                    (VG_BINDING_CLASSIFY_WORK) */
    uint32_t stamp;              /* this frame's (warp.cull) */
    gpu_buffer baked;            /* a baked vgx_curve_data (desc.curve), else none */
    uint32_t chunk_count;
    uint32_t tess_slots;         /* indirect commands of all tessellated chunks */
    curve_gpu *curve;            /* warp.curve */
    uint32_t patches_per_draw;
    eye_pass eyes[6];
    struct fill_pass {
        warp_gpu *w;
        rg_res color, aux, list;
        uint32_t eye;
        struct fill_step {
            const struct fill_pass *fill;
            uint32_t kernel;
        } steps[4];
    } fills[2];
    rg_res fill_header_res;
    /* this frame's graph resources */
    frame_resources *res;
    rg_res target;
    rg_res flat_indices, tess_indices, tess_levels, args, kinds, counts, edge_levels, vertex_warp, vertex_seen_res;
    rg_res classify_work_res;
};

static const VkFormat k_eye_formats[2] = {WARP_COLOR_FORMAT, WARP_AUX_FORMAT};

enum { K_CULL, K_VERTICES, K_VERTEX_SEARCH, K_EDGES, K_EDGE_LEVELS, K_CLASSIFY, K_COMPACT }; /* of the classify kit */
enum { K_FILL_RESET, K_FILL_FIND, K_FILL_TEST, K_FILL_APPLY }; /* of the fill kit */

/* ------------------------------------------------------------------------- */
/* Classify                                                                  */
/* ------------------------------------------------------------------------- */

static void bind_classify(warp_gpu *w, const rg_context *ctx, uint32_t kernel, uint32_t bucket)
{
    const frame_ctx *fc = w->fc;
    const frame_resources *r = w->res;
    VkDescriptorBufferInfo ubo = {fc->ubo[fc->slot].buffer, 0, sizeof(vg_frame_ubo)};
    VkDescriptorImageInfo depth = rg_ctx_sampled_info(ctx, r->depth, fc->nearest_clamp);
    VkDescriptorImageInfo target = rg_ctx_sampled_info(ctx, w->target, fc->nearest_clamp);
    enum { NB = 17 };
    VkDescriptorBufferInfo bufs[NB] = {
        {rg_ctx_buffer(ctx, r->curve), 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, r->vertices), 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, r->indices), 0, VK_WHOLE_SIZE},
        {w->instances.buffer, 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->flat_indices), 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->tess_indices), 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->args), 0, VK_WHOLE_SIZE},
        {w->chunks.buffer, 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->kinds), 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->counts), 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->tess_levels), 0, VK_WHOLE_SIZE},
        {w->tri_edges.buffer, 0, VK_WHOLE_SIZE},
        {w->edges.buffer, 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->edge_levels), 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->vertex_warp), 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->vertex_seen_res), 0, VK_WHOLE_SIZE},
        {rg_ctx_buffer(ctx, w->classify_work_res), 0, VK_WHOLE_SIZE},
    };
    static const uint32_t buffer_bindings[NB] = {
        VG_BINDING_CURVE, VG_BINDING_VERTICES, VG_BINDING_INDICES, VG_BINDING_INSTANCES, VG_BINDING_FLAT,
        VG_BINDING_TESS, VG_BINDING_ARGS, VG_BINDING_CHUNKS, VG_BINDING_KINDS, VG_BINDING_COUNTS,
        VG_BINDING_TESS_LEVELS, VG_BINDING_TRI_EDGES, VG_BINDING_EDGES, VG_BINDING_EDGE_LEVELS,
        VG_BINDING_VERTEX_WARP, VG_BINDING_VERTEX_SEEN, VG_BINDING_CLASSIFY_WORK};
    VkWriteDescriptorSet wr[3 + NB] = {
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = VG_BINDING_FRAME, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &ubo},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = VG_BINDING_DEPTH, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, .pImageInfo = &depth},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = VG_BINDING_TARGET, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, .pImageInfo = &target},
    };
    for (int i = 0; i < NB; i++)
        wr[3 + i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                                           .dstBinding = buffer_bindings[i], .descriptorCount = 1,
                                           .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                           .pBufferInfo = &bufs[i]};
    vg_classify_push push = {.instance_count = (uint32_t)fc->scene->instance_count,
                             .chunk_triangles = w->patches_per_draw, .chunk_count = w->chunk_count,
                             .tess_slots = w->tess_slots, .edge_count = w->edge_count,
                             .vertex_count = fc->scene->vertex_count, .stamp = w->stamp, .bucket = bucket};
    gpu_compute_kit_bind(fc->gpu, rg_ctx_cmd(ctx), &w->classify, kernel, wr, 3 + NB, &push);
}

/* warp.classify, four steps (the graph orders them): cull the triangles,
 * warp each vertex a visible one uses and level each edge (both once,
 * however many triangles share them), sample the edges and search the
 * vertices the work lists hold, then gather each triangle's kind and count
 * the chunks' (the barrier reduction only there: lavapipe runs a kernel with
 * a barrier as coroutines, and the edge levels are the pass's main cost). */
static void cull_execute(const rg_context *ctx, void *user)
{
    warp_gpu *w = user;
    if (++w->stamp == 0) /* 0 is what vertex_seen starts as */
        w->stamp = 1;
    bind_classify(w, ctx, K_CULL, 0);
    vkCmdDispatch(rg_ctx_cmd(ctx), w->chunk_count ? w->chunk_count : 1, 1, 1); /* one group resets the work lists */
}

static void vertices_execute(const rg_context *ctx, void *user)
{
    warp_gpu *w = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    bind_classify(w, ctx, K_VERTICES, 0);
    vkCmdDispatch(cmd, (w->fc->scene->vertex_count + 63) / 64, 1, 1);
    if (w->edge_count) {
        bind_classify(w, ctx, K_EDGES, 0);
        vkCmdDispatch(cmd, (w->edge_count + 63) / 64, 1, 1);
    }
}

/* The edges to sample, bucket by bucket, then the vertices the 3x3
 * neighbourhood left to the Halton search (warp_edges.comp,
 * warp_vertices.glsl), as the work lists' indirect dispatches. */
static void levels_execute(const rg_context *ctx, void *user)
{
    warp_gpu *w = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    for (uint32_t k = 0; k < VG_EDGE_BUCKETS && w->edge_count; k++) {
        bind_classify(w, ctx, K_EDGE_LEVELS, k);
        vkCmdDispatchIndirect(cmd, w->classify_work.buffer, VG_WORKLIST_ARGS(k));
    }
    bind_classify(w, ctx, K_VERTEX_SEARCH, 0);
    vkCmdDispatchIndirect(cmd, w->classify_work.buffer, VG_WORKLIST_ARGS(VG_HALTON_LIST));
}

static void gather_execute(const rg_context *ctx, void *user)
{
    warp_gpu *w = user;
    bind_classify(w, ctx, K_CLASSIFY, 0);
    vkCmdDispatch(rg_ctx_cmd(ctx), w->chunk_count, 1, 1);
}

static void compact_execute(const rg_context *ctx, void *user)
{
    warp_gpu *w = user;
    bind_classify(w, ctx, K_COMPACT, 0);
    vkCmdDispatch(rg_ctx_cmd(ctx), w->chunk_count, 1, 1);
}

/* Flat triangles through the vertex shader, the rest through the
 * tessellator, both as indirect draws that warp.classify filled in. */
static void draw_warped(warp_gpu *w, const rg_context *ctx, uint32_t flags)
{
    frame_ctx *fc = w->fc;
    const scene *s = fc->scene;
    const vg_warp_instance *table = w->instances.mapped;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    VkBuffer args = rg_ctx_buffer(ctx, w->args);
    const VkDeviceSize stride = sizeof(VkDrawIndexedIndirectCommand);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, w->warp_flat);
    scene_gpu_bind(fc->sg, cmd, fc->slot, SCENE_INPUT_SHADE, rg_ctx_buffer(ctx, w->flat_indices));
    for (int i = 0; i < s->instance_count; i++) {
        /* An instance without a whole triangle has no chunk, so warp.classify
         * never writes its draw: drawing it would read arguments nobody wrote
         * (lavapipe then spins on garbage counts). */
        if (table[i].index_count < 3)
            continue;
        scene_gpu_push_instance(fc->sg, cmd, fc->scene_layout, i, flags);
        vkCmdDrawIndexedIndirect(cmd, args, (VkDeviceSize)i * stride, 1, (uint32_t)stride);
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, w->warp);
    scene_gpu_bind(fc->sg, cmd, fc->slot, SCENE_INPUT_SHADE, rg_ctx_buffer(ctx, w->tess_indices));
    for (int i = 0; i < s->instance_count; i++) {
        if (!table[i].tess_chunks)
            continue;
        scene_gpu_push_instance(fc->sg, cmd, fc->scene_layout, i, flags);
        VkDeviceSize first = (VkDeviceSize)(s->instance_count + (int)table[i].tess_args) * stride;
        VkDeviceSize count = (VkDeviceSize)(s->instance_count + (int)w->tess_slots) * stride + 4 * (VkDeviceSize)i;
        /* lavapipe (Mesa 22.3) loses the draws of vkCmdDrawIndexedIndirectCount
         * when later passes bind other buffers (docs/architecture.md). */
        if (fc->gpu->features.draw_indirect_count && !fc->gpu->is_cpu)
            vkCmdDrawIndexedIndirectCount(cmd, args, first, args, count, table[i].tess_chunks, (uint32_t)stride);
        else if (fc->gpu->features.multi_draw_indirect)
            vkCmdDrawIndexedIndirect(cmd, args, first, table[i].tess_chunks, (uint32_t)stride);
        else
            for (uint32_t c = 0; c < table[i].tess_chunks; c++)
                vkCmdDrawIndexedIndirect(cmd, args, first + c * stride, 1, (uint32_t)stride);
    }
}

/* ------------------------------------------------------------------------- */
/* Eyes                                                                      */
/* ------------------------------------------------------------------------- */

/* Two real cameras need the disparity maps (and the curve) only to measure
 * themselves; without them the frame makes no maps (frame.c) and the graph
 * culls the G-buffer. */
static bool eye_reads_maps(const warp_gpu *w, eye_kind kind)
{
    return w->target.id && (kind != EYE_CAMERAS || w->desc.measure);
}

static void push_eye(const warp_gpu *w, const rg_context *ctx, eye_kind kind)
{
    const frame_ctx *fc = w->fc;
    const frame_resources *r = w->res;
    VkDescriptorBufferInfo ubo = {fc->ubo[fc->slot].buffer, 0, sizeof(vg_frame_ubo)};
    VkDescriptorImageInfo shadow = rg_ctx_sampled_info(ctx, r->shadow, fc->shadow_sampler);
    VkDescriptorImageInfo depth = rg_ctx_sampled_info(ctx, r->depth, fc->nearest_clamp);
    VkDescriptorImageInfo target = rg_ctx_sampled_info(ctx, w->target, fc->nearest_clamp);
    VkDescriptorImageInfo color = rg_ctx_sampled_info(ctx, r->color, fc->nearest_clamp);
    VkDescriptorImageInfo ids = rg_ctx_sampled_info(ctx, r->ids, fc->nearest_clamp);
    VkDescriptorBufferInfo curve = {rg_ctx_buffer(ctx, r->curve), 0, VK_WHOLE_SIZE};
    VkDescriptorBufferInfo levels = {kind == EYE_WARP ? rg_ctx_buffer(ctx, w->tess_levels) : VK_NULL_HANDLE, 0,
                                     VK_WHOLE_SIZE};
    VkDescriptorBufferInfo vertex_warp = {kind == EYE_WARP ? rg_ctx_buffer(ctx, w->vertex_warp) : VK_NULL_HANDLE,
                                          0, VK_WHOLE_SIZE};
#define W(b, t, field) {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = (b), \
                        .descriptorCount = 1, .descriptorType = (t), field}
    VkWriteDescriptorSet wr[9] = {
        W(VG_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, .pBufferInfo = &ubo),
        W(VG_BINDING_SHADOW, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, .pImageInfo = &shadow),
        W(VG_BINDING_DEPTH, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, .pImageInfo = &depth),
        W(VG_BINDING_TARGET, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, .pImageInfo = &target),
        W(VG_BINDING_CURVE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &curve),
        W(5, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, .pImageInfo = &color),
        W(6, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, .pImageInfo = &ids),
        W(VG_BINDING_TESS_LEVELS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &levels),
        W(VG_BINDING_VERTEX_WARP, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &vertex_warp),
    };
#undef W
    /* The image-warping baseline reads the G-buffer colour and ids, the
     * others the shadow map and the curve, the warp its edge levels and
     * vertices. */
    VkWriteDescriptorSet used[9];
    uint32_t n = 0;
    bool maps = eye_reads_maps(w, kind);
    used[n++] = wr[0];
    if (maps) {
        used[n++] = wr[2];
        used[n++] = wr[3];
    }
    if (kind != EYE_IMAGEWARP) {
        used[n++] = wr[1];
        if (maps)
            used[n++] = wr[4];
        if (kind == EYE_WARP) {
            used[n++] = wr[7];
            used[n++] = wr[8];
        }
    } else {
        used[n++] = wr[5];
        used[n++] = wr[6];
    }
    fc->gpu->cmd_push_descriptor_set(rg_ctx_cmd(ctx), VK_PIPELINE_BIND_POINT_GRAPHICS, fc->scene_layout, 0, n, used);
}

static void eye_execute(const rg_context *ctx, void *user)
{
    const eye_pass *e = user;
    warp_gpu *w = e->w;
    frame_ctx *fc = w->fc;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    uint32_t flags = e->right ? VG_DRAW_RIGHT_EYE : 0;
    push_eye(w, ctx, e->kind);
    if (e->kind == EYE_IMAGEWARP) {
        vg_draw_push push = {.flags = flags};
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, w->imagewarp);
        vkCmdPushConstants(cmd, fc->scene_layout, VK_SHADER_STAGE_ALL_GRAPHICS, 0, sizeof push, &push);
        vkCmdDraw(cmd, fc->width * fc->height, 1, 0, 0);
        return;
    }
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, fc->scene_layout, 1, 1, &fc->sg->texture_set, 0,
                            NULL);
    if (e->kind == EYE_WARP) {
        draw_warped(w, ctx, flags);
    } else {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, w->cameras);
        scene_gpu_draw(fc->sg, cmd, fc->slot, fc->scene_layout, SCENE_INPUT_SHADE, flags);
    }
    /* The sky last, at the far plane behind the depth test: only the pixels
     * no surface covers pay for it. */
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, w->sky);
    vkCmdDraw(cmd, 3, 1, 0, 0);
}

/* warp.fill (shaders/warp_fill.glsl), four steps in the eye's own images:
 * reset the eye's counts, candidates over every pixel, then the test and the
 * mean over the candidates only (indirect, as many as the find step listed). */
static void fill_bind(const rg_context *ctx, const struct fill_step *step)
{
    const struct fill_pass *f = step->fill;
    warp_gpu *w = f->w;
    const rg_res images[3] = {f->color, f->aux, w->res->ids};
    VkDescriptorImageInfo info[3];
    gpu_binding b[5];
    for (uint32_t i = 0; i < 3; i++) {
        info[i] = rg_ctx_image_info(ctx, images[i]);
        b[i] = GPU_STORAGE_IMAGE(&info[i]);
    }
    b[3] = GPU_STORAGE_BUFFER(w->fill_header.buffer);
    b[4] = GPU_STORAGE_BUFFER(rg_ctx_buffer(ctx, f->list));
    uint32_t slot = f->eye;
    gpu_compute_kit_bind_list(w->fc->gpu, rg_ctx_cmd(ctx), &w->fill, step->kernel, b, 5, &slot);
}

static void fill_execute(const rg_context *ctx, void *user)
{
    const struct fill_step *step = user;
    const struct fill_pass *f = step->fill;
    const warp_gpu *w = f->w;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    fill_bind(ctx, step);
    if (step->kernel == K_FILL_RESET)
        vkCmdDispatch(cmd, 1, 1, 1);
    else if (step->kernel == K_FILL_FIND)
        vkCmdDispatch(cmd, (w->fc->width + 7) / 8, (w->fc->height + 7) / 8, 1);
    else
        vkCmdDispatchIndirect(cmd, w->fill_header.buffer, VG_WORKLIST_ARGS(f->eye));
}

static void add_eye(warp_gpu *w, rg_graph *g, frame_resources *res, eye_pass *e, const char *name,
                    rg_res color, rg_res aux)
{
    uint32_t width = w->fc->width, height = w->fc->height;
    char zname[48];
    snprintf(zname, sizeof zname, "%s.zbuffer", name);
    rg_res z = rg_image(g, &(rg_image_desc){zname, GBUFFER_DEPTH_FORMAT, width, height, 1});
    rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = name, .type = RG_PASS_GRAPHICS, .execute = eye_execute,
                                               .user = e});
    rg_use(g, p, res->ubo, RG_UNIFORM);
    bool maps = eye_reads_maps(w, e->kind);
    if (maps) {
        rg_use(g, p, res->depth, RG_SAMPLED);
        rg_use(g, p, w->target, RG_SAMPLED);
    }
    if (e->kind == EYE_IMAGEWARP) {
        rg_use(g, p, res->color, RG_SAMPLED);
        rg_use(g, p, res->ids, RG_SAMPLED);
        /* Pixels no splat reaches stay (0, 0, 0, 0): the holes. */
        rg_use_clear(g, p, color, RG_COLOR_WRITE, (VkClearValue){0});
    } else {
        rg_use(g, p, res->vertices, RG_VERTEX);
        rg_use(g, p, res->statics, RG_VERTEX);
        if (e->kind == EYE_WARP) {
            rg_use(g, p, w->flat_indices, RG_INDEX);
            rg_use(g, p, w->tess_indices, RG_INDEX);
            rg_use(g, p, w->tess_levels, RG_STORAGE_READ);
            rg_use(g, p, w->vertex_warp, RG_STORAGE_READ);
            rg_use(g, p, w->args, RG_INDIRECT);
        } else {
            rg_use(g, p, res->indices, RG_INDEX);
        }
        rg_use(g, p, res->shadow, RG_SAMPLED);
        if (maps)
            rg_use(g, p, res->curve, RG_STORAGE_READ);
        rg_use(g, p, color, RG_COLOR_WRITE); /* surfaces, then the sky covers every pixel left */
    }
    rg_use(g, p, aux, RG_COLOR_WRITE);
    rg_use_clear(g, p, z, RG_DEPTH_WRITE, (VkClearValue){.depthStencil = {1.0f, 0}});
}

void warp_gpu_add(warp_gpu *w, rg_graph *g, frame_resources *res, rg_res target)
{
    const warp_gpu_desc *d = &w->desc;
    uint32_t width = w->fc->width, height = w->fc->height;
    w->res = res;
    w->target = target;
    if (d->stereo == FRAME_STEREO_OFF)
        return;

    /* warp.curve: the last stage of the cascade (and of the error measurement),
     * built from this frame's target map unless a baked one was given. */
    if (!target.id) {
        /* Two cameras with nothing to measure: no curve. */
    } else if (w->baked.buffer) {
        res->curve = rg_import_buffer(g, &(rg_buffer_desc){"warp.curve.baked", sizeof(vgx_curve_data)},
                                      &(rg_import_desc){.initial = RG_STORAGE_READ});
    } else {
        res->curve = rg_buffer(g, &(rg_buffer_desc){"warp.curve", sizeof(vgx_curve_data)});
        curve_gpu_add(w->curve, g, res->depth, target, res->curve);
    }

    if (d->stereo == FRAME_STEREO_WARP) {
        const scene *sc = w->fc->scene;
        uint64_t index_bytes = (uint64_t)(sc->index_count ? sc->index_count : 1) * sizeof(uint32_t);
        uint64_t arg_bytes = (uint64_t)(sc->instance_count + w->tess_slots + 1) * sizeof(VkDrawIndexedIndirectCommand) +
                             (uint64_t)sc->instance_count * sizeof(uint32_t);
        w->flat_indices = rg_buffer(g, &(rg_buffer_desc){"warp.flat_indices", index_bytes});
        w->tess_indices = rg_buffer(g, &(rg_buffer_desc){"warp.tess_indices", index_bytes});
        w->args = rg_buffer(g, &(rg_buffer_desc){"warp.draw_args", arg_bytes});
        w->kinds = rg_buffer(g, &(rg_buffer_desc){"warp.kinds", index_bytes / 3 + 4});
        w->tess_levels = rg_buffer(g, &(rg_buffer_desc){"warp.tess_levels", index_bytes / 3 + 4});
        w->counts = rg_buffer(g, &(rg_buffer_desc){"warp.counts", (uint64_t)(w->chunk_count + 1) * 8});
        w->edge_levels = rg_buffer(g, &(rg_buffer_desc){"warp.edge_levels", (uint64_t)(w->edge_count + 1) * 4});
        w->vertex_warp = rg_buffer(g, &(rg_buffer_desc){"warp.vertex_warp", (uint64_t)(sc->vertex_count + 1) * 8});
        w->vertex_seen_res = rg_import_buffer(g, &(rg_buffer_desc){"warp.vertex_seen", w->vertex_seen.size},
                                              &(rg_import_desc){.initial = RG_STORAGE_READ_WRITE,
                                                                .final = RG_STORAGE_READ_WRITE});
        w->classify_work_res = rg_import_buffer(g, &(rg_buffer_desc){"warp.classify_work", w->classify_work.size},
                                            &(rg_import_desc){.initial = RG_STORAGE_READ_WRITE,
                                                              .final = RG_STORAGE_READ_WRITE});
        /* The steps push the same descriptors; each declares every buffer
         * the kit's kernels write, as written from the first step on (a
         * superset: cull writes only the kinds, but each step's barrier then
         * covers them all), and the work lists as indirect arguments where
         * dispatched from. */
        static const struct {
            const char *name;
            rg_execute_fn execute;
            bool indirect;
        } steps[] = {{"warp.classify.cull", cull_execute, false},
                     {"warp.classify.vertices", vertices_execute, false},
                     {"warp.classify.levels", levels_execute, true},
                     {"warp.classify.gather", gather_execute, false}};
        for (size_t i = 0; i < sizeof steps / sizeof steps[0]; i++) {
            rg_pass cls = rg_pass_add(g, &(rg_pass_desc){.name = steps[i].name, .type = RG_PASS_COMPUTE,
                                                         .execute = steps[i].execute, .user = w});
            rg_usage out = i == 0 ? RG_STORAGE_WRITE : RG_STORAGE_READ_WRITE;
            rg_use(g, cls, res->ubo, RG_STORAGE_READ);
            rg_use(g, cls, res->depth, RG_SAMPLED);
            rg_use(g, cls, target, RG_SAMPLED);
            rg_use(g, cls, res->curve, RG_STORAGE_READ);
            rg_use(g, cls, res->vertices, RG_STORAGE_READ);
            rg_use(g, cls, res->indices, RG_STORAGE_READ);
            rg_use(g, cls, w->kinds, out);
            rg_use(g, cls, w->counts, out);
            rg_use(g, cls, w->edge_levels, out);
            rg_use(g, cls, w->vertex_warp, out);
            rg_use(g, cls, w->vertex_seen_res, RG_STORAGE_READ_WRITE);
            rg_use(g, cls, w->classify_work_res, steps[i].indirect ? RG_INDIRECT_STORAGE : RG_STORAGE_READ_WRITE);
        }
        rg_pass cpt = rg_pass_add(g, &(rg_pass_desc){.name = "warp.compact", .type = RG_PASS_COMPUTE,
                                                     .execute = compact_execute, .user = w});
        rg_use(g, cpt, res->depth, RG_SAMPLED);
        rg_use(g, cpt, target, RG_SAMPLED);
        rg_use(g, cpt, res->curve, RG_STORAGE_READ);
        rg_use(g, cpt, res->vertices, RG_STORAGE_READ);
        rg_use(g, cpt, res->indices, RG_STORAGE_READ);
        rg_use(g, cpt, w->kinds, RG_STORAGE_READ);
        rg_use(g, cpt, w->counts, RG_STORAGE_READ);
        rg_use(g, cpt, w->flat_indices, RG_STORAGE_WRITE);
        rg_use(g, cpt, w->tess_indices, RG_STORAGE_WRITE);
        rg_use(g, cpt, w->tess_levels, RG_STORAGE_WRITE);
        rg_use(g, cpt, w->args, RG_STORAGE_WRITE);
    }

    static const char *const names[3][2] = {
        {"warp.left", "warp.right"}, {"cameras.left", "cameras.right"}, {"imagewarp.left", "imagewarp.right"}};
    eye_kind kind = d->stereo == FRAME_STEREO_WARP ? EYE_WARP : d->stereo == FRAME_STEREO_CAMERAS ? EYE_CAMERAS
                                                                                                 : EYE_IMAGEWARP;
    if (kind == EYE_WARP)
        w->fill_header_res = rg_import_buffer(g, &(rg_buffer_desc){"warp.fill.header", w->fill_header.size},
                                              &(rg_import_desc){.initial = RG_STORAGE_READ_WRITE,
                                                                .final = RG_STORAGE_READ_WRITE});
    res->left = rg_image(g, &(rg_image_desc){"eye.left", WARP_COLOR_FORMAT, width, height, 1});
    res->right = rg_image(g, &(rg_image_desc){"eye.right", WARP_COLOR_FORMAT, width, height, 1});
    res->left_aux = rg_image(g, &(rg_image_desc){"eye.left.aux", WARP_AUX_FORMAT, width, height, 1});
    res->right_aux = rg_image(g, &(rg_image_desc){"eye.right.aux", WARP_AUX_FORMAT, width, height, 1});
    for (int i = 0; i < 2; i++) {
        w->eyes[i] = (eye_pass){w, kind, i == 1};
        rg_res color = i ? res->right : res->left, aux = i ? res->right_aux : res->left_aux;
        if (kind != EYE_WARP) {
            add_eye(w, g, res, &w->eyes[i], names[kind][i], color, aux);
            continue;
        }
        /* warp.fill closes the warp's cracks in the eye's images. */
        struct fill_pass *f = &w->fills[i];
        f->w = w;
        f->color = color;
        f->aux = aux;
        f->eye = (uint32_t)i;
        f->list = rg_buffer(g, &(rg_buffer_desc){i ? "warp.fill.right.list" : "warp.fill.left.list",
                                                  (uint64_t)width * height * sizeof(uint32_t)});
        add_eye(w, g, res, &w->eyes[i], names[kind][i], color, aux);
        static const char *const step_names[2][4] = {
            {"warp.fill.left.reset", "warp.fill.left.find", "warp.fill.left.test", "warp.fill.left.apply"},
            {"warp.fill.right.reset", "warp.fill.right.find", "warp.fill.right.test", "warp.fill.right.apply"}};
        for (uint32_t k = K_FILL_RESET; k <= K_FILL_APPLY; k++) {
            f->steps[k] = (struct fill_step){f, k};
            rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = step_names[i][k], .type = RG_PASS_COMPUTE,
                                                       .execute = fill_execute, .user = &f->steps[k]});
            rg_use(g, p, color, RG_STORAGE_READ_WRITE);
            rg_use(g, p, aux, RG_STORAGE_READ_WRITE);
            rg_use(g, p, res->ids, RG_STORAGE_READ);
            bool indirect = k == K_FILL_TEST || k == K_FILL_APPLY;
            rg_use(g, p, w->fill_header_res, indirect ? RG_INDIRECT_STORAGE : RG_STORAGE_READ_WRITE);
            rg_use(g, p, f->list, k == K_FILL_RESET ? RG_STORAGE_WRITE : RG_STORAGE_READ_WRITE);
        }
    }
    if (d->reference && kind != EYE_CAMERAS) {
        res->ref_left = rg_image(g, &(rg_image_desc){"reference.left", WARP_COLOR_FORMAT, width, height, 1});
        res->ref_right = rg_image(g, &(rg_image_desc){"reference.right", WARP_COLOR_FORMAT, width, height, 1});
        rg_res aux_l = rg_image(g, &(rg_image_desc){"reference.left.aux", WARP_AUX_FORMAT, width, height, 1});
        rg_res aux_r = rg_image(g, &(rg_image_desc){"reference.right.aux", WARP_AUX_FORMAT, width, height, 1});
        for (int i = 0; i < 2; i++) {
            w->eyes[2 + i] = (eye_pass){w, EYE_CAMERAS, i == 1};
            add_eye(w, g, res, &w->eyes[2 + i], i ? "reference.right" : "reference.left",
                    i ? res->ref_right : res->ref_left, i ? aux_r : aux_l);
        }
    }
}

/* ------------------------------------------------------------------------- */
/* Pipelines                                                                 */
/* ------------------------------------------------------------------------- */

typedef struct shader_set {
    VkShaderModule warp_vert, warp_flat_vert, warp_tesc, warp_tese, eye_frag, eye_measure_frag, cameras_vert, sky_vert,
        eye_sky_frag, imagewarp_vert, imagewarp_frag;
} shader_set;

static vg_status load_shaders(gpu *g, shader_set *s)
{
    vg_status st = GPU_SHADER(g, spv_warp_vert, &s->warp_vert);
    if (st == VG_OK) st = GPU_SHADER(g, spv_warp_flat_vert, &s->warp_flat_vert);
    if (st == VG_OK) st = GPU_SHADER(g, spv_warp_tesc, &s->warp_tesc);
    if (st == VG_OK) st = GPU_SHADER(g, spv_warp_tese, &s->warp_tese);
    if (st == VG_OK) st = GPU_SHADER(g, spv_eye_frag, &s->eye_frag);
    if (st == VG_OK) st = GPU_SHADER(g, spv_eye_measure_frag, &s->eye_measure_frag);
    if (st == VG_OK) st = GPU_SHADER(g, spv_cameras_vert, &s->cameras_vert);
    if (st == VG_OK) st = GPU_SHADER(g, spv_sky_vert, &s->sky_vert);
    if (st == VG_OK) st = GPU_SHADER(g, spv_eye_sky_frag, &s->eye_sky_frag);
    if (st == VG_OK) st = GPU_SHADER(g, spv_imagewarp_vert, &s->imagewarp_vert);
    if (st == VG_OK) st = GPU_SHADER(g, spv_imagewarp_frag, &s->imagewarp_frag);
    return st;
}

static void free_shaders(gpu *g, shader_set *s)
{
    gpu_shaders_destroy(g, (VkShaderModule *)s, sizeof *s / sizeof(VkShaderModule));
}

static vg_status create_pipelines(warp_gpu *w, const shader_set *s)
{
    frame_ctx *fc = w->fc;
    gpu *g = fc->gpu;
    VkVertexInputBindingDescription vb[SCENE_BINDING_COUNT];
    VkVertexInputAttributeDescription va[8];
    uint32_t nb, na;
    scene_gpu_vertex_input(SCENE_INPUT_SHADE, vb, &nb, va, &na);
    gpu_graphics_desc eye = {
        .layout = fc->scene_layout, .bindings = vb, .binding_count = nb, .attributes = va,
        .attribute_count = na, .depth_test = true, .depth_write = true, .color_formats = k_eye_formats,
        .color_count = 2, .depth_format = GBUFFER_DEPTH_FORMAT,
    };
    gpu_graphics_desc d = eye;
    d.name = "warp.stereo";
    d.vert = s->warp_vert;
    d.tesc = s->warp_tesc;
    d.tese = s->warp_tese;
    /* Measuring costs the fragment shader a second cascade: only captures do it. */
    VkShaderModule warp_frag = w->desc.measure ? s->eye_measure_frag : s->eye_frag;
    d.frag = warp_frag;
    /* Only the warp tessellates: the baselines run on devices without it. */
    vg_status st = w->desc.stereo == FRAME_STEREO_WARP ? gpu_graphics_pipeline_create(g, &d, &w->warp) : VG_OK;
    if (st == VG_OK) {
        d = eye;
        d.name = "warp.stereo flat";
        d.vert = s->warp_flat_vert;
        d.frag = warp_frag;
        st = gpu_graphics_pipeline_create(g, &d, &w->warp_flat);
    }
    if (st == VG_OK) {
        d = eye;
        d.name = "cameras";
        d.vert = s->cameras_vert;
        d.frag = w->desc.measure ? s->eye_measure_frag : s->eye_frag;
        st = gpu_graphics_pipeline_create(g, &d, &w->cameras);
    }
    if (st == VG_OK)
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "eye sky", .layout = fc->scene_layout, .vert = s->sky_vert, .frag = s->eye_sky_frag,
            .depth_test = true, .depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL, /* where the clear's 1 is left */
            .color_formats = k_eye_formats, .color_count = 2, .depth_format = GBUFFER_DEPTH_FORMAT}, &w->sky);
    if (st == VG_OK)
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "imagewarp", .layout = fc->scene_layout, .vert = s->imagewarp_vert, .frag = s->imagewarp_frag,
            .points = true, .depth_test = true, .depth_write = true,
            .depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL, /* the sky splats at depth 1 */
            .color_formats = k_eye_formats, .color_count = 2, .depth_format = GBUFFER_DEPTH_FORMAT}, &w->imagewarp);

    if (st == VG_OK)
        st = curve_gpu_create(g, fc->width, fc->height, &w->curve);
    /* warp.classify: the scene bindings of set 0 plus its own buffers; the
     * frame constants as a storage buffer (shaders/common.glsl,
     * VG_FRAME_STORAGE: lavapipe would compile a variant per camera pose). */
    VkDescriptorType ctypes[VG_BINDING_CLASSIFY_WORK + 1];
    for (int i = 0; i <= VG_BINDING_CLASSIFY_WORK; i++)
        ctypes[i] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    ctypes[VG_BINDING_SHADOW] = ctypes[VG_BINDING_DEPTH] = ctypes[VG_BINDING_TARGET] = ctypes[5] = ctypes[6] =
        VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    if (st == VG_OK)
        st = gpu_compute_kit_create(g, &(gpu_compute_kit_desc){
            .name = "warp.classify", .types = ctypes, .count = VG_BINDING_CLASSIFY_WORK + 1,
            .push_size = sizeof(vg_classify_push),
            .kernels = {[K_CULL] = GPU_KERNEL(spv_warp_cull_comp, "warp.cull"),
                        [K_VERTICES] = GPU_KERNEL(spv_warp_vertices_comp, "warp.vertices"),
                        [K_VERTEX_SEARCH] = GPU_KERNEL(spv_warp_vertex_search_comp, "warp.vertex_search"),
                        [K_EDGES] = GPU_KERNEL(spv_warp_edges_comp, "warp.edges"),
                        [K_EDGE_LEVELS] = GPU_KERNEL(spv_warp_edge_levels_comp, "warp.edge_levels"),
                        [K_CLASSIFY] = GPU_KERNEL(spv_warp_classify_comp, "warp.classify"),
                        [K_COMPACT] = GPU_KERNEL(spv_warp_compact_comp, "warp.compact")}}, &w->classify);
    static const uint32_t k_reset[1] = {1};
    static const VkDescriptorType ftypes[5] = {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                                               VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                               VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    if (st == VG_OK)
        st = gpu_compute_kit_create(g, &(gpu_compute_kit_desc){
            .name = "warp.fill", .types = ftypes, .count = 5, .push_size = sizeof(uint32_t),
            .kernels = {[K_FILL_RESET] = GPU_KERNEL_SPEC(spv_warp_fill_find_comp, "warp.fill.reset", k_reset),
                        [K_FILL_FIND] = GPU_KERNEL(spv_warp_fill_find_comp, "warp.fill.find"),
                        [K_FILL_TEST] = GPU_KERNEL(spv_warp_fill_test_comp, "warp.fill.test"),
                        [K_FILL_APPLY] = GPU_KERNEL(spv_warp_fill_apply_comp, "warp.fill.apply")}}, &w->fill);
    return st;
}

/* Every edge of the scene's triangles once (vg_warp_edge), and each
 * triangle's three edge ids (opposite vertex 0, 1, 2: edges 1-2, 2-0, 0-1),
 * so warp.edges levels an edge once for the two triangles that share it.
 * Edges are keyed by their two global vertex numbers (open addressing). */
static vg_status create_edge_table(warp_gpu *w)
{
    const scene *s = w->fc->scene;
    const vg_warp_instance *table = w->instances.mapped;
    uint64_t triangles = s->index_count / 3; /* triangle g of instance i is first_index / 3 + t (as warp.kinds) */
    size_t cap = 16;
    while (cap < 4 * triangles)
        cap *= 2;
    uint64_t *keys = malloc(cap * sizeof(uint64_t));
    uint32_t *slot_edge = malloc(cap * sizeof(uint32_t));
    vg_warp_edge *list = malloc((3 * triangles + 1) * sizeof(vg_warp_edge));
    vg_status st = keys && slot_edge && list ? VG_OK : VG_ERR_NOMEM;
    if (st == VG_OK)
        st = gpu_buffer_create(w->fc->gpu, &(gpu_buffer_desc){
            .name = "warp triangle edges", .size = (3 * triangles + 1) * sizeof(uint32_t),
            .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true}, &w->tri_edges);
    uint32_t n = 0;
    if (st == VG_OK) {
        memset(keys, 0xff, cap * sizeof(uint64_t)); /* UINT64_MAX: empty (no edge joins vertex 2^32 - 1 twice) */
        uint32_t *tri_edges = w->tri_edges.mapped;
        for (int i = 0; i < s->instance_count; i++) {
            uint32_t base = table[i].first_index / 3, fv = table[i].first_vertex;
            for (uint32_t t = 0; t < table[i].index_count / 3; t++) {
                const uint32_t *ix = s->indices + table[i].first_index + 3 * t;
                for (int e = 0; e < 3; e++) {
                    uint32_t a = fv + ix[(e + 1) % 3], b = fv + ix[(e + 2) % 3];
                    uint64_t key = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
                    size_t h = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & (cap - 1);
                    while (keys[h] != UINT64_MAX && keys[h] != key)
                        h = (h + 1) & (cap - 1);
                    uint32_t g = base + t;
                    if (keys[h] == UINT64_MAX) {
                        keys[h] = key;
                        slot_edge[h] = n;
                        list[n++] = (vg_warp_edge){a, b, g, VG_EDGE_NONE};
                    } else {
                        vg_warp_edge *ed = &list[slot_edge[h]];
                        if (ed->t1 == VG_EDGE_NONE && ed->t0 != g)
                            ed->t1 = g;
                        else if (ed->t0 != g && ed->t1 != g)
                            ed->t0 = VG_EDGE_ALWAYS; /* a third triangle: level it whatever is culled */
                    }
                    tri_edges[3 * g + (uint32_t)e] = slot_edge[h];
                }
            }
        }
        w->edge_count = n;
        if ((n + 63) / 64 > w->fc->gpu->props.limits.maxComputeWorkGroupCount[0]) {
            vg_error("%s: %u triangle edges, more than the warp's one dispatch over edges takes on %s", s->path, n,
                     w->fc->gpu->props.deviceName);
            st = VG_ERR_UNSUPPORTED;
        }
    }
    if (st == VG_OK) {
        st = gpu_buffer_create(w->fc->gpu, &(gpu_buffer_desc){
            .name = "warp edges", .size = (n ? n : 1) * sizeof(vg_warp_edge),
            .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true}, &w->edges);
    }
    if (st == VG_OK)
        memcpy(w->edges.mapped, list, (size_t)n * sizeof(vg_warp_edge));
    /* warp.cull resets the lists' counts every frame. */
    if (st == VG_OK)
        st = gpu_buffer_create(w->fc->gpu, &(gpu_buffer_desc){
            .name = "warp classify work lists",
            .size = (VG_CLASSIFY_LISTS * 4 + VG_EDGE_BUCKETS * (n ? n : 1) + (uint64_t)s->vertex_count) * sizeof(uint32_t),
            .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT}, &w->classify_work);
    free(keys);
    free(slot_edge);
    free(list);
    return st;
}

/* Where each instance's lists and draw commands go (vg_warp_instance). */
static vg_status create_instance_table(warp_gpu *w)
{
    const scene *s = w->fc->scene;
    size_t n = s->instance_count ? (size_t)s->instance_count : 1;
    vg_status st = gpu_buffer_create(w->fc->gpu, &(gpu_buffer_desc){
        .name = "warp instances", .size = n * sizeof(vg_warp_instance),
        .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true}, &w->instances);
    if (st != VG_OK)
        return st;
    vg_warp_instance *table = w->instances.mapped;
    w->tess_slots = 0;
    for (int i = 0; i < s->instance_count; i++) {
        const scene_instance *in = &s->instances[i];
        uint32_t count = s->primitives[in->primitive].index_count, triangles = count / 3;
        uint32_t chunk = w->patches_per_draw ? w->patches_per_draw : (triangles ? triangles : 1);
        table[i] = (vg_warp_instance){
            .first_index = in->first_index, .index_count = count, .first_vertex = in->first_vertex,
            .tess_args = w->tess_slots, .tess_chunks = (triangles + chunk - 1) / chunk,
        };
        w->tess_slots += table[i].tess_chunks;
    }
    if (!w->patches_per_draw)
        w->patches_per_draw = UINT32_MAX; /* one draw per instance */

    /* Chunks of at most 256 triangles, instance by instance. */
    w->chunk_count = 0;
    for (int i = 0; i < s->instance_count; i++)
        w->chunk_count += (table[i].index_count / 3 + 255) / 256;
    st = gpu_buffer_create(w->fc->gpu, &(gpu_buffer_desc){
        .name = "warp chunks", .size = (w->chunk_count ? w->chunk_count : 1) * sizeof(vg_warp_chunk),
        .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, .host_visible = true}, &w->chunks);
    if (st != VG_OK)
        return st;
    vg_warp_chunk *chunks = w->chunks.mapped;
    uint32_t k = 0;
    for (int i = 0; i < s->instance_count; i++) {
        uint32_t triangles = table[i].index_count / 3, first_chunk = k;
        for (uint32_t t = 0; t < triangles; t += 256)
            chunks[k++] = (vg_warp_chunk){(uint32_t)i, t, triangles - t < 256 ? triangles - t : 256, first_chunk};
    }
    return create_edge_table(w);
}

void warp_gpu_bind(warp_gpu *w, rg_graph *g)
{
    /* The background the curve leaves out: this frame's far plane. */
    curve_gpu_set_background(w->curve, w->fc->cam.zfar);
    if (w->baked.buffer)
        rg_bind_buffer(g, w->res->curve, w->baked.buffer);
    if (w->vertex_seen.buffer)
        rg_bind_buffer(g, w->vertex_seen_res, w->vertex_seen.buffer);
    if (w->classify_work_res.id)
        rg_bind_buffer(g, w->classify_work_res, w->classify_work.buffer);
    if (w->fill_header_res.id)
        rg_bind_buffer(g, w->fill_header_res, w->fill_header.buffer);
}

vg_status warp_gpu_create(frame_ctx *fc, const warp_gpu_desc *desc, warp_gpu **out)
{
    *out = NULL;
    if (desc->stereo == FRAME_STEREO_WARP && !fc->gpu->features.tessellation) {
        vg_error("%s has no tessellation shaders, which the 3D warp needs (try --stereo-render cameras)",
                 fc->gpu->props.deviceName);
        return VG_ERR_DEVICE;
    }
    warp_gpu *w = calloc(1, sizeof *w);
    if (!w)
        return VG_ERR_NOMEM;
    w->fc = fc;
    w->desc = *desc;
    w->desc.curve = NULL;
    /* lavapipe corrupts draws tessellated into more than 65,535 vertices; a
     * level-L triangle patch makes about 0.8 (L + 1)^2 of them there. */
    uint32_t level = desc->max_tess_level;
    w->patches_per_draw = fc->gpu->is_cpu ? (uint32_t)(60000.0 / (0.8 * (level + 1) * (level + 1))) : 0;
    if (fc->gpu->is_cpu && w->patches_per_draw < 1)
        w->patches_per_draw = 1;
    shader_set s = {0};
    vg_status st = create_instance_table(w);
    /* Zero: no frame has stamped a vertex yet (warp.cull). */
    if (st == VG_OK && desc->stereo == FRAME_STEREO_WARP) {
        st = gpu_buffer_create(fc->gpu, &(gpu_buffer_desc){.name = "warp vertex stamps",
                                                           .size = 4 * (VkDeviceSize)(fc->scene->vertex_count + 1),
                                                           .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                           .host_visible = true}, &w->vertex_seen);
        if (st == VG_OK)
            memset(w->vertex_seen.mapped, 0, w->vertex_seen.size);
        /* warp.fill's counts, one per eye (zeroed by the pass itself). */
        if (st == VG_OK)
            st = gpu_buffer_create(fc->gpu, &(gpu_buffer_desc){.name = "warp fill header", .size = 2 * 4 * sizeof(uint32_t),
                                                               .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                                                        VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT}, &w->fill_header);
    }
    if (st == VG_OK && desc->curve) {
        st = gpu_buffer_create(fc->gpu, &(gpu_buffer_desc){.name = "baked curve", .size = sizeof(vgx_curve_data),
                                                           .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                                                    VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                                           .host_visible = true}, &w->baked);
        if (st == VG_OK)
            memcpy(w->baked.mapped, desc->curve, sizeof(vgx_curve_data));
    }
    if (st == VG_OK)
        st = load_shaders(fc->gpu, &s);
    if (st == VG_OK)
        st = create_pipelines(w, &s);
    free_shaders(fc->gpu, &s);
    if (st != VG_OK) {
        warp_gpu_destroy(w);
        return st;
    }
    *out = w;
    return VG_OK;
}

void warp_gpu_destroy(warp_gpu *w)
{
    if (!w)
        return;
    gpu_pipelines_destroy(w->fc->gpu, (VkPipeline[]){w->warp, w->warp_flat, w->cameras, w->imagewarp, w->sky}, 5);
    curve_gpu_destroy(w->curve);
    gpu_compute_kit_destroy(w->fc->gpu, &w->classify);
    gpu_compute_kit_destroy(w->fc->gpu, &w->fill);
    gpu_buffer_destroy(w->fc->gpu, &w->instances);
    gpu_buffer_destroy(w->fc->gpu, &w->chunks);
    gpu_buffer_destroy(w->fc->gpu, &w->tri_edges);
    gpu_buffer_destroy(w->fc->gpu, &w->edges);
    gpu_buffer_destroy(w->fc->gpu, &w->baked);
    gpu_buffer_destroy(w->fc->gpu, &w->vertex_seen);
    gpu_buffer_destroy(w->fc->gpu, &w->fill_header);
    gpu_buffer_destroy(w->fc->gpu, &w->classify_work);
    free(w);
}
