/* vergence — the frame: per-frame state, the graph, submission, readback. */
#include "frame.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CGLM_FORCE_DEPTH_ZERO_TO_ONE
#include <cglm/cglm.h>

#include "core/clock.h"
#include "core/log.h"
#include "disparity/gpu/disparity_gpu.h"
#include "keyframe_gpu.h"
#include "disparity/mid_window.h"
#include "pass/frame_ctx.h"
#include "render/gbuffer_gpu.h"
#include "render/scene_gpu.h"
#include "render/shadow_gpu.h"
#include "sdk/vgx_engine.h"
#include "shared.h"
#include "output/compose_gpu.h"
#include "output/overlay_gpu.h"
#include "output/present_gpu.h"
#include "probe_gpu.h"
#include "warp/gpu/warp_gpu.h"
#include "warp/warp_settings.h"

/* One image (or buffer: height 0, width = bytes) copied to the host after
 * the frame, and the frame_outputs field that points at its copy. */
typedef struct readback_item {
    rg_res res;
    uint32_t width, height, texel;
    VkDeviceSize offset;
    void *dest;                  /* a pointer field of frame_outputs */
} readback_item;

#define FRAME_MAX_READBACK 16

_Static_assert(VG_FRAMES_IN_FLIGHT <= RG_MAX_SLOTS, "the graph keeps timestamps for every frame in flight");
_Static_assert(FRAME_PROBES_KEPT > VG_FRAMES_IN_FLIGHT, "frame_wait_idle completes every frame in flight at once");

/* One of the SDK dispatch's passes, as a pass of the frame's graph. */
#define FRAME_MAX_SDK_PASSES 24
typedef struct sdk_pass {
    struct frame *f;
    uint32_t index;
} sdk_pass;

const char *const frame_look_ahead_names[] = {"foresight", "causal", NULL};
const char *const frame_saliency_names[] = {"auto", "authored", "computed", NULL};

struct frame {
    frame_desc desc;             /* as asked, defaults resolved (frame_get_desc) */
    frame_ctx fc;                /* what the pass modules share */
    scene_gpu sg;                /* the scene on the GPU (fc.sg) */
    shadow_gpu *shadow;
    gbuffer_gpu *gbuffer;
    vgx_context *vgx;            /* the disparity passes, through the public API (include/vergence) */
    sdk_pass sdk_passes[FRAME_MAX_SDK_PASSES];
    vgx_image maps[3];           /* g, h, f: the context's */
    disparity_gpu_atlas atlas;
    disparity_gpu *disparity;    /* behind it: the frame's metrics read the solve's keyframes */
    keyframe_gpu *keyframes;     /* the frame renders the window's keyframes vgx_begin_frame asks for */
    warp_gpu *warp;
    compose_gpu *compose;
    overlay_gpu *overlay;        /* stereo frames that draw a HUD (windowed, or desc.overlay) */
    frame_hud *hud;              /* headless: what frame_set_hud gave */
    present_gpu *present;
    rg_res r_swapchain;
    probe_gpu *probe;            /* desc.probe_ids */
    long slot_index[VG_FRAMES_IN_FLIGHT];    /* the frame in flight in each slot */
    frame_probe probes[FRAME_PROBES_KEPT]; /* completed, not yet taken (frame_take_probes) */
    int probe_count;

    gpu_buffer readback;
    readback_item items[FRAME_MAX_READBACK];
    int item_count;
    VkCommandBuffer cmd[VG_FRAMES_IN_FLIGHT];
    VkFence fence[VG_FRAMES_IN_FLIGHT];
    bool submitted[VG_FRAMES_IN_FLIGHT];

    rg_graph *graph;
    frame_resources res;
    rg_res r_readback;
    frame_outputs outputs;
    double pass_ms[RG_MAX_PASSES];   /* the last completed frame */
    uint32_t pass_count;
    double host_t0;                      /* the CPU clock when this frame's host part began */
    double host_ms[VG_FRAMES_IN_FLIGHT]; /* per slot: the host part of the frame in flight there */
    double host_done_ms;                 /* that of the last completed frame (beside pass_ms) */
    bool timed;                      /* the pass clock is on (frame_time_passes) */
};


/* ------------------------------------------------------------------------- */
/* Readback                                                                  */
/* ------------------------------------------------------------------------- */

static void readback_execute(const rg_context *ctx, void *user)
{
    frame *f = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    for (int i = 0; i < f->item_count; i++) {
        const readback_item *it = &f->items[i];
        if (!it->height) {
            VkBufferCopy copy = {.dstOffset = it->offset, .size = it->width};
            vkCmdCopyBuffer(cmd, rg_ctx_buffer(ctx, it->res), rg_ctx_buffer(ctx, f->r_readback), 1, &copy);
            continue;
        }
        VkBufferImageCopy region = {
            .bufferOffset = it->offset,
            .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
            .imageExtent = {it->width, it->height, 1},
        };
        vkCmdCopyImageToBuffer(cmd, rg_ctx_image(ctx, it->res), rg_ctx_layout(ctx, it->res),
                               rg_ctx_buffer(ctx, f->r_readback), 1, &region);
    }
}

static void readback_add_item(frame *f, rg_res res, uint32_t w, uint32_t h, uint32_t texel, void *dest)
{
    VkDeviceSize offset = 0;
    if (f->item_count > 0) {
        const readback_item *last = &f->items[f->item_count - 1];
        offset = last->offset + (VkDeviceSize)last->width * (last->height ? last->height * last->texel : 1);
        offset = (offset + 15) & ~(VkDeviceSize)15;
    }
    f->items[f->item_count++] = (readback_item){res, w, h, texel, offset, dest};
}

/* ------------------------------------------------------------------------- */
/* Graph                                                                     */
/* ------------------------------------------------------------------------- */

/* Two real cameras showing g need no disparity map: only their measures
 * and the readback of the maps do. Every other stereo frame draws one. */
static bool frame_needs_maps(const frame_desc *d)
{
    return d->stereo != FRAME_STEREO_OFF &&
           (d->stereo != FRAME_STEREO_CAMERAS || d->mode != FRAME_MODE_ORIGINAL || d->measure || d->readback);
}

/* The disparity passes as graph passes of the frame, one per pass of the
 * SDK's dispatch (vgx_pass_name), each recording only its own
 * (first_pass): the pass clock, the HUD and the benches time them one by
 * one. Each reads the G-buffer and the atlas (so they live until the last),
 * and leaves g, h and f, the context's images, in SHADER_READ_ONLY_OPTIMAL
 * (RG_SAMPLED) as it found them. */
static vgx_image vgx_image_of(const rg_context *ctx, rg_res r)
{
    return (vgx_image){rg_ctx_image(ctx, r), rg_ctx_view(ctx, r), rg_ctx_layout(ctx, r)};
}

static void sdk_pass_execute(const rg_context *ctx, void *user)
{
    const sdk_pass *p = user;
    frame *f = p->f;
    const frame_ctx *fc = &f->fc;
    const frame_resources *res = &f->res;
    const disparity_gpu_atlas *a = &f->atlas;
    vgx_dispatch_desc d = {
        .command_buffer = rg_ctx_cmd(ctx),
        .frame = {vgx_image_of(ctx, res->depth), vgx_image_of(ctx, res->color), vgx_image_of(ctx, res->motion),
                  vgx_image_of(ctx, res->ids)},
        .keyframes = {vgx_image_of(ctx, a->depth), vgx_image_of(ctx, a->color), vgx_image_of(ctx, a->motion),
                      vgx_image_of(ctx, a->ids)},
        /* The original rig as stereo_setup makes it: the render camera's field of view. */
        .rig = {.hfov_deg = 2.0 * atan(tan(0.5 * fc->cam.yfov) * fc->cam.aspect) * 180.0 / M_PI,
                .interaxial_m = f->desc.rig.interaxial_m, .convergence_m = f->desc.rig.convergence_m},
        .first_pass = p->index, .pass_count = 1,
    };
    if (vgx_dispatch(f->vgx, &d) != VGX_SUCCESS)
        vg_error("the frame's disparity pass %s was not recorded", vgx_pass_name(f->vgx, p->index));
}

static vg_status sdk_passes_add(frame *f, rg_graph *g, frame_resources *res, const disparity_gpu_atlas *atlas)
{
    uint32_t n = vgx_pass_count(f->vgx);
    if (n > FRAME_MAX_SDK_PASSES) {
        vg_error("frame: the SDK's dispatch has %u passes; the frame holds %d", n, FRAME_MAX_SDK_PASSES);
        return VG_ERR_GRAPH;
    }
    f->atlas = *atlas;
    rg_import_desc sampled = {RG_SAMPLED, RG_SAMPLED};
    static const char *const names[3] = {"disparity.g", "disparity.h", "disparity.f"};
    rg_res *maps[3] = {&res->g, &res->h, &res->f};
    for (int i = 0; i < 3; i++) {
        vgx_image img;
        if (vgx_get_output(f->vgx, (vgx_output)i, &img) != VGX_SUCCESS)
            continue;
        *maps[i] = rg_import_image(g, &(rg_image_desc){names[i], VK_FORMAT_R32_SFLOAT, f->fc.width,
                                                       f->fc.height, 1}, &sampled);
        f->maps[i] = img;
    }
    rg_res reads[8] = {res->depth, res->color, res->motion, res->ids, atlas->depth, atlas->color, atlas->motion,
                       atlas->ids};
    for (uint32_t i = 0; i < n; i++) {
        f->sdk_passes[i] = (sdk_pass){f, i};
        rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = vgx_pass_name(f->vgx, i), .type = RG_PASS_COMPUTE,
                                                   .execute = sdk_pass_execute, .user = &f->sdk_passes[i],
                                                   .side_effects = true});
        for (int k = 0; k < 8; k++)
            rg_use(g, p, reads[k], RG_STORAGE_READ);
        for (int k = 0; k < 3; k++)
            if (maps[k]->id)
                rg_use(g, p, *maps[k], RG_SAMPLED);
    }
    return VG_OK;
}

static vg_status build_graph(frame *f)
{
    frame_ctx *fc = &f->fc;
    rg_graph *g = f->graph = rg_create();
    if (!g)
        return VG_ERR_NOMEM;
    frame_resources *res = &f->res;
    rg_import_desc ready_vertex = {.initial = RG_VERTEX}, ready_index = {.initial = RG_INDEX},
                   ready_uniform = {.initial = RG_UNIFORM};
    res->ubo = rg_import_buffer(g, &(rg_buffer_desc){"frame.ubo", sizeof(vg_frame_ubo)}, &ready_uniform);
    res->vertices = rg_import_buffer(g, &(rg_buffer_desc){"scene.vertices", fc->sg->dynamic[0].size}, &ready_vertex);
    res->statics = rg_import_buffer(g, &(rg_buffer_desc){"scene.statics", fc->sg->statics.size}, &ready_vertex);
    res->indices = rg_import_buffer(g, &(rg_buffer_desc){"scene.indices", fc->sg->indices.size}, &ready_index);

    shadow_gpu_add(f->shadow, g, res);
    gbuffer_gpu_add(f->gbuffer, g, res);
    bool stereo = f->desc.stereo != FRAME_STEREO_OFF;
    uint32_t w = fc->width, h = fc->height, sw = 0, sh = 0;
    bool eyes = stereo && !f->desc.maps_only;
    if (stereo) {
        rg_res target = {0};
        if (f->vgx) {
            disparity_gpu_atlas atlas;
            keyframe_gpu_add(f->keyframes, g, res, &atlas);
            vg_status st = sdk_passes_add(f, g, res, &atlas);
            if (st != VG_OK)
                return st;
            target = f->desc.mode == FRAME_MODE_MANIPULATED ? res->h
                     : f->desc.mode == FRAME_MODE_OPTIMIZED ? res->f
                                                             : res->g;
        }
        if (!target.id && frame_needs_maps(&f->desc)) {
            vg_error("mode '%s' is not available: the disparity passes did not produce its map",
                     frame_mode_names[f->desc.mode]);
            return VG_ERR_UNSUPPORTED;
        }
        if (f->probe && target.id)
            probe_gpu_add(f->probe, g, res, target);
        if (eyes) {
            warp_gpu_add(f->warp, g, res, target);
            if (f->overlay)
                overlay_gpu_add(f->overlay, g, res);
            compose_gpu_add(f->compose, g, res);
            frame_compose_size(f->desc.compose, w, h, &sw, &sh);
        }
    }

    if (f->desc.readback) {
        frame_outputs *o = &f->outputs;
        *o = (frame_outputs){0};
        readback_add_item(f, res->color, w, h, 4, &o->color);
        readback_add_item(f, res->depth, w, h, 4, &o->depth);
        readback_add_item(f, res->ids, w, h, 4, &o->ids);
        readback_add_item(f, res->motion, w, h, 16, &o->motion);
        if (stereo)
            readback_add_item(f, res->g, w, h, 4, &o->g);
        if (stereo && res->h.id)
            readback_add_item(f, res->h, w, h, 4, &o->h);
        if (stereo && res->f.id)
            readback_add_item(f, res->f, w, h, 4, &o->f);
        if (eyes) {
            readback_add_item(f, res->left, w, h, 4, &o->left);
            readback_add_item(f, res->right, w, h, 4, &o->right);
            readback_add_item(f, res->left_aux, w, h, 16, &o->left_aux);
            readback_add_item(f, res->right_aux, w, h, 16, &o->right_aux);
            readback_add_item(f, res->stereo, sw, sh, 4, &o->stereo);
            o->stereo_width = sw;
            o->stereo_height = sh;
            if (res->ref_left.id) {
                readback_add_item(f, res->ref_left, w, h, 4, &o->ref_left);
                readback_add_item(f, res->ref_right, w, h, 4, &o->ref_right);
            }
            readback_add_item(f, res->curve, sizeof(vgx_curve_data), 0, 0, &o->curve);
        }
        const readback_item *last = &f->items[f->item_count - 1];
        VkDeviceSize size = last->offset + (VkDeviceSize)last->width * (last->height ? last->height * last->texel : 1);
        vg_status st = gpu_buffer_create(fc->gpu, &(gpu_buffer_desc){
            .name = "frame readback", .size = size, .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
            .host_visible = true}, &f->readback);
        if (st != VG_OK)
            return st;
        f->r_readback = rg_import_buffer(g, &(rg_buffer_desc){"readback", size},
                                         &(rg_import_desc){.final = RG_HOST_READ});
        rg_pass rb = rg_pass_add(g, &(rg_pass_desc){.name = "readback", .type = RG_PASS_TRANSFER,
                                                    .execute = readback_execute, .user = f});
        for (int i = 0; i < f->item_count; i++)
            rg_use(g, rb, f->items[i].res, RG_TRANSFER_SRC);
        rg_use(g, rb, f->r_readback, RG_TRANSFER_DST);
        /* Each field gets the address of its copy (memcpy: the fields are
         * pointers of several types). */
        for (int i = 0; i < f->item_count; i++) {
            const void *copy = (const uint8_t *)f->readback.mapped + f->items[i].offset;
            memcpy(f->items[i].dest, &copy, sizeof copy);
        }
    }
    if (f->present)
        f->r_swapchain = present_gpu_add(f->present, g, res);
    if (!f->desc.readback && !f->present)
        rg_export(g, eyes ? res->stereo : res->color);
    vg_status st = rg_compile(g);
    if (st == VG_OK)
        st = rg_realize(g, fc->gpu);
    if (st == VG_OK)
        shadow_gpu_bind(f->shadow, g);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Lifetime                                                                  */
/* ------------------------------------------------------------------------- */

static vg_status create_layouts(frame_ctx *fc)
{
    gpu *g = fc->gpu;
    /* Set 0 of every scene pipeline (shared.h VG_BINDING_*): frame UBO,
     * shadow map, centre depth, target vergence, curve, centre colour, ids,
     * the warp's edge levels and vertices. */
    const VkShaderStageFlags all = VK_SHADER_STAGE_ALL_GRAPHICS;
    VkDescriptorSetLayoutBinding bindings[9] = {
        {VG_BINDING_FRAME, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, all, NULL},
        {VG_BINDING_SHADOW, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, all, NULL},
        {VG_BINDING_DEPTH, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, all, NULL},
        {VG_BINDING_TARGET, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, all, NULL},
        {VG_BINDING_CURVE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, all, NULL},
        {5, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, all, NULL},
        {6, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, all, NULL},
        {VG_BINDING_TESS_LEVELS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, all, NULL},
        {VG_BINDING_VERTEX_WARP, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, all, NULL},
    };
    VkDescriptorSetLayoutCreateInfo set0 = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR,
        .bindingCount = 9,
        .pBindings = bindings,
    };
    VK_TRY(vkCreateDescriptorSetLayout(g->device, &set0, g->alloc, &fc->push_layout));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, fc->push_layout, "scene push layout");
    VkDescriptorSetLayout sets[2] = {fc->push_layout, fc->sg->texture_layout};
    VkPushConstantRange push = {VK_SHADER_STAGE_ALL_GRAPHICS, 0, sizeof(vg_draw_push)};
    VkPipelineLayoutCreateInfo layout = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = 2,
        .pSetLayouts = sets,
        .pushConstantRangeCount = 1,
        .pPushConstantRanges = &push,
    };
    VK_TRY(vkCreatePipelineLayout(g->device, &layout, g->alloc, &fc->scene_layout));
    GPU_NAME(g, VK_OBJECT_TYPE_PIPELINE_LAYOUT, fc->scene_layout, "scene pipeline layout");

    VkSamplerCreateInfo shadow = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = VK_FILTER_LINEAR,
        .minFilter = VK_FILTER_LINEAR,
        .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
        .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
        .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
        .compareEnable = VK_TRUE,
        .compareOp = VK_COMPARE_OP_LESS_OR_EQUAL,
        .borderColor = VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE,
    };
    VK_TRY(vkCreateSampler(g->device, &shadow, g->alloc, &fc->shadow_sampler));
    GPU_NAME(g, VK_OBJECT_TYPE_SAMPLER, fc->shadow_sampler, "shadow compare sampler");
    VkSamplerCreateInfo clamp = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = VK_FILTER_LINEAR,
        .minFilter = VK_FILTER_LINEAR,
        .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
        .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
        .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
    };
    VK_TRY(vkCreateSampler(g->device, &clamp, g->alloc, &fc->linear_clamp));
    GPU_NAME(g, VK_OBJECT_TYPE_SAMPLER, fc->linear_clamp, "linear clamp sampler");
    clamp.magFilter = clamp.minFilter = VK_FILTER_NEAREST;
    VK_TRY(vkCreateSampler(g->device, &clamp, g->alloc, &fc->nearest_clamp));
    GPU_NAME(g, VK_OBJECT_TYPE_SAMPLER, fc->nearest_clamp, "nearest clamp sampler");
    return VG_OK;
}

static vg_status create_submission(frame *f)
{
    gpu *g = f->fc.gpu;
    VkCommandBufferAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = g->pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = VG_FRAMES_IN_FLIGHT,
    };
    VK_TRY(vkAllocateCommandBuffers(g->device, &alloc, f->cmd));
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT; i++) {
        GPU_NAME(g, VK_OBJECT_TYPE_COMMAND_BUFFER, f->cmd[i], "frame commands slot %d", i);
        VK_TRY(vkCreateFence(g->device, &(VkFenceCreateInfo){.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO},
                             g->alloc, &f->fence[i]));
        GPU_NAME(g, VK_OBJECT_TYPE_FENCE, f->fence[i], "frame fence slot %d", i);
        char name[32];
        snprintf(name, sizeof name, "frame ubo slot %d", i);
        /* Storage too: warp.classify reads it as a storage buffer (common.glsl). */
        vg_status st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = name, .size = sizeof(vg_frame_ubo),
                                                               .usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                                                                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                                               .host_visible = true}, &f->fc.ubo[i]);
        if (st != VG_OK)
            return st;
    }
    return VG_OK;
}

/* Every default of a frame_desc, resolved once (frame_get_desc gives them
 * back); each pass module gets the part it renders in its own desc
 * (frame_create) and changes nothing. */
static frame_desc resolve_defaults(const frame_desc *desc)
{
    frame_desc d = *desc;
    if (!d.width || !d.height) {
        d.width = 960;
        d.height = 540;
    }
    /* The disparity pipeline's defaults (DESIGN.md steps 4-7) are its own
     * (disparity_gpu_desc_defaults, as the SDK resolves them). */
    disparity_gpu_desc dd = disparity_gpu_desc_defaults(&(disparity_gpu_desc){
        .fps = d.fps, .keyframe_stride = d.keyframe_stride, .coarse_stride = d.coarse_stride,
        .window_seconds = d.window_seconds, .window_future = d.window_future, .op = d.op, .solver = d.solver});
    d.fps = dd.fps;
    d.keyframe_stride = dd.keyframe_stride;
    d.coarse_stride = dd.coarse_stride;
    d.window_seconds = dd.window_seconds;
    d.window_future = dd.window_future;
    d.op = dd.op;
    d.solver = dd.solver;
    /* A cascade's texels follow the frame's rows, so a shadow looks the same
     * at every size (shadow_gpu_setup's split depth then depends on the scene
     * alone) and costs in proportion to the pixels, as the other passes. */
    if (!d.shadow_size)
        d.shadow_size = d.height * FRAME_SHADOW_TEXELS_PER_ROW < 256 ? 256 : d.height * FRAME_SHADOW_TEXELS_PER_ROW;
    if (d.mode == FRAME_MODE_DEFAULT)
        d.mode = FRAME_MODE_OPTIMIZED; /* f: motion in depth restored (issue 4) */
    if (d.compose == FRAME_COMPOSE_DEFAULT)
        d.compose = FRAME_COMPOSE_SBS;
    warp_settings w = warp_settings_defaults((warp_settings){d.tess_px, d.tess_error, d.max_tess_level,
                                                             d.depth_epsilon, d.halton_radius});
    d.tess_error = w.tess_error_px, d.max_tess_level = w.max_level;
    d.depth_epsilon = w.depth_epsilon, d.halton_radius = w.halton_radius_px;
    if (d.rig.interaxial_m <= 0)
        d.rig.interaxial_m = FRAME_DEFAULT_INTERAXIAL;
    if (d.rig.convergence_m <= 0)
        d.rig.convergence_m = FRAME_DEFAULT_CONVERGENCE;
    return d;
}

bool frame_size_ok(uint32_t width, uint32_t height, char *why, size_t cap)
{
    uint32_t st = disparity_gpu_grid_stride(width, height, 0);
    if ((width + st - 1) / st >= 2 && (height + st - 1) / st >= 2)
        return true;
    /* The cell is at least 5 px and grows with the size (192 x 108 cells at most). */
    uint32_t by_w = disparity_gpu_grid_stride(width, 1, 0), by_h = disparity_gpu_grid_stride(1, height, 0);
    snprintf(why, cap, "%ux%u gives the disparity solver %ux%u cells of %u px, and it needs at least 2x2: at this "
             "width the height must be at least %u px, at this height the width at least %u px", width, height,
             (width + st - 1) / st, (height + st - 1) / st, st, by_w + 1, by_h + 1);
    return false;
}

/* The disparity passes for the frame's settings, through the SDK as any
 * host would make them (its context over the frame's own device), and the
 * renderer of their keyframe atlas. */
static vg_status disparity_create(frame *f)
{
    frame_ctx *fc = &f->fc;
    const frame_desc *fd = &f->desc;
    gpu *g = fc->gpu;
    bool optimize = fd->mode == FRAME_MODE_OPTIMIZED || fd->measure || (fd->readback && !fd->maps_only);
    const stereo_display_desc *dd = &fd->display;
    vgx_context_desc d = {
        .header_version = VGX_HEADER_VERSION, .instance = g->instance, .physical_device = g->phys,
        .device = g->device, .queue_family = g->queue_family, .allocator = g->alloc,
        .width = fd->width, .height = fd->height,
        .display = {.diagonal_in = dd->diagonal_in, .aspect_w = dd->aspect_w, .aspect_h = dd->aspect_h,
                    .res_x = dd->res_x, .res_y = dd->res_y, .distance_m = dd->distance_m, .ipd_m = dd->ipd_m},
        .op = (vgx_operator)fd->op, .preset = (vgx_preset)fd->op_preset, .target_range_arcmin = fd->target_range,
        .fps = fd->fps, .keyframe_stride = fd->keyframe_stride, .window_seconds = fd->window_seconds,
        .look_ahead = fd->look_ahead == FRAME_LOOK_AHEAD_CAUSAL ? VGX_LOOK_AHEAD_CAUSAL : VGX_LOOK_AHEAD_PREDICTED,
        /* Keyframes in every mode: lang-smoothed's h depends on its keyframe
         * and the frame only (issue 13). */
        .flags = VGX_CONTEXT_SALIENCY | VGX_CONTEXT_KEYFRAMES | (optimize ? VGX_CONTEXT_OPTIMIZE : 0u) |
                 (g->debug_utils ? VGX_CONTEXT_DEBUG_UTILS : 0u),
    };
    vgx_result r = vgx_engine_context_create(&d, &(disparity_gpu_desc){
        .coarse_stride = fd->coarse_stride, .window_future = fd->window_future, .solver = fd->solver,
        .solver_iterations = fd->solver_iterations, .temporal_depth_only = fd->temporal_depth_only,
        .readback = fd->readback, .budgeted = fd->budgeted_solve}, &f->vgx);
    if (r != VGX_SUCCESS)
        return vgx_engine_status(r);
    f->disparity = vgx_engine_disparity(f->vgx);
    disparity_gpu_info i;
    disparity_gpu_get_info(f->disparity, &i);
    return keyframe_gpu_create(fc, &(keyframe_gpu_desc){.nx = i.nx, .ny = i.ny, .stride = i.stride,
                                                          .max_tiles = i.max_tiles}, &f->keyframes);
}

vg_status frame_create(gpu *g, const scene *s, const frame_desc *desc, frame **out)
{
    *out = NULL;
    /* An orthographic view has no stereo rig to derive g from (docs/scene.md):
     * refused for every command, not rendered as zeros. */
    if (desc->stereo != FRAME_STEREO_OFF && scene_camera_orthographic(s, desc->camera)) {
        vg_error("%s: camera %d is orthographic: a stereo frame needs a perspective camera (docs/scene.md)",
                 s->file_count ? s->files[0] : "the scene", desc->camera);
        return VG_ERR_FORMAT;
    }
    frame *f = calloc(1, sizeof *f);
    if (!f)
        return VG_ERR_NOMEM;
    frame_ctx *fc = &f->fc;
    fc->gpu = g;
    fc->sg = &f->sg;
    fc->scene = s;
    f->desc = resolve_defaults(desc);
    if (f->desc.max_tess_level > g->props.limits.maxTessellationGenerationLevel)
        f->desc.max_tess_level = g->props.limits.maxTessellationGenerationLevel;
    if (f->desc.shadow_size * VG_SHADOW_CASCADES > g->props.limits.maxImageDimension2D)
        f->desc.shadow_size = g->props.limits.maxImageDimension2D / VG_SHADOW_CASCADES;
    fc->width = f->desc.width;
    fc->height = f->desc.height;
    fc->camera = f->desc.camera;
    fc->slot = -1;
    stereo_display_init(&fc->display, &f->desc.display);

    vg_status st = scene_gpu_create(g, s, fc->sg);
    if (f->desc.look_ahead == FRAME_LOOK_AHEAD_CAUSAL)
        fc->sg->causal_step = (float)(1.0 / f->desc.fps); /* the last frame and one time step before it */
    fc->sg->computed_saliency = f->desc.saliency == FRAME_SALIENCY_COMPUTED ||
                                (f->desc.saliency == FRAME_SALIENCY_AUTO && !scene_has_saliency(s));
    if (st == VG_OK)
        st = create_layouts(fc);
    if (st == VG_OK)
        st = create_submission(f);
    /* Each pass module gets the settings it renders. The lit centre colour
     * is only looked at in captures, mono frames and the image-warping
     * baseline; a warped stereo frame shades its eyes. */
    const frame_desc *d = &f->desc;
    if (st == VG_OK)
        st = shadow_gpu_create(fc, &(shadow_gpu_desc){.size = d->shadow_size}, &f->shadow);
    if (st == VG_OK)
        st = gbuffer_gpu_create(fc, &(gbuffer_gpu_desc){.lit = d->readback || d->stereo == FRAME_STEREO_OFF ||
                                                               d->stereo == FRAME_STEREO_IMAGEWARP}, &f->gbuffer);
    bool eyes = d->stereo != FRAME_STEREO_OFF && !d->maps_only;
    if (st == VG_OK && d->stereo != FRAME_STEREO_OFF && frame_needs_maps(d))
        st = disparity_create(f);
    if (st == VG_OK && eyes)
        st = warp_gpu_create(fc, &(warp_gpu_desc){.stereo = d->stereo, .measure = d->measure,
                                                   .reference = d->reference, .max_tess_level = d->max_tess_level,
                                                   .curve = d->curve}, &f->warp);
    if (st == VG_OK && eyes)
        st = compose_gpu_create(fc, &(compose_gpu_desc){.compose = d->compose, .swap_eyes = d->swap_eyes},
                                &f->compose);
    if (st == VG_OK && d->probe_ids[0] && frame_needs_maps(d))
        st = probe_gpu_create(fc, d->probe_ids, &f->probe);
    if (st == VG_OK && eyes && (d->overlay || d->present_format != VK_FORMAT_UNDEFINED))
        st = overlay_gpu_create(fc, &f->overlay);
    if (st == VG_OK && d->present_format != VK_FORMAT_UNDEFINED) {
        VkExtent2D source = {d->width, d->height};
        if (d->stereo != FRAME_STEREO_OFF)
            frame_compose_size(d->compose, d->width, d->height, &source.width, &source.height);
        st = present_gpu_create(fc, &(present_gpu_desc){.format = d->present_format,
                                                         .extent = {d->present_width, d->present_height},
                                                         .source = source}, &f->present);
    }
    if (st == VG_OK)
        st = build_graph(f);
    if (st != VG_OK) {
        frame_destroy(f);
        return st;
    }
    *out = f;
    return VG_OK;
}

void frame_destroy(frame *f)
{
    if (!f)
        return;
    frame_ctx *fc = &f->fc;
    gpu *g = fc->gpu;
    vkDeviceWaitIdle(g->device);
    rg_destroy(f->graph);
    present_gpu_destroy(f->present);
    probe_gpu_destroy(f->probe);
    overlay_gpu_destroy(f->overlay);
    free(f->hud);
    compose_gpu_destroy(f->compose);
    warp_gpu_destroy(f->warp);
    vgx_context_destroy(f->vgx);
    keyframe_gpu_destroy(f->keyframes);
    gbuffer_gpu_destroy(f->gbuffer);
    shadow_gpu_destroy(f->shadow);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT; i++) {
        gpu_buffer_destroy(g, &fc->ubo[i]);
        if (f->fence[i])
            vkDestroyFence(g->device, f->fence[i], g->alloc);
    }
    if (f->cmd[0])
        vkFreeCommandBuffers(g->device, g->pool, VG_FRAMES_IN_FLIGHT, f->cmd);
    gpu_buffer_destroy(g, &f->readback);
    VkSampler samplers[] = {fc->shadow_sampler, fc->linear_clamp, fc->nearest_clamp};
    for (size_t i = 0; i < sizeof samplers / sizeof samplers[0]; i++)
        if (samplers[i])
            vkDestroySampler(g->device, samplers[i], g->alloc);
    if (fc->scene_layout)
        vkDestroyPipelineLayout(g->device, fc->scene_layout, g->alloc);
    if (fc->push_layout)
        vkDestroyDescriptorSetLayout(g->device, fc->push_layout, g->alloc);
    scene_gpu_destroy(g, fc->sg);
    free(f);
}

/* ------------------------------------------------------------------------- */
/* Rendering                                                                 */
/* ------------------------------------------------------------------------- */

/* The original rig follows the render camera: its field of view and the
 * image width; the off-axis eye cameras are the centre camera moved by half
 * the interaxial along its right axis with the frustum shifted so depth c
 * lands on the screen (asymmetric frusta, no toe-in). */
static void stereo_setup(frame *f, vg_frame_ubo *u)
{
    frame_ctx *fc = &f->fc;
    const frame_desc *d = &f->desc;
    stereo_camera_desc rig = d->rig;
    rig.hfov_deg = 2.0 * atan(tan(0.5 * fc->cam.yfov) * fc->cam.aspect) * 180.0 / M_PI;
    rig.image_width = (int)d->width;
    stereo_camera_init(&fc->rig, &rig, &fc->display);
    double b = fc->rig.interaxial_m, c = fc->rig.convergence_m;
    for (int eye = 0; eye < 2; eye++) {
        double side = eye ? 1.0 : -1.0; /* left eye at -b/2 along the camera's right */
        mat4 view, proj, vp;
        memcpy(view, fc->cam.view, sizeof view);
        memcpy(proj, fc->cam.proj, sizeof proj);
        view[3][0] -= (float)(side * 0.5 * b);      /* view-space x of every point moves by -side b/2 */
        proj[2][0] -= (float)(side * proj[0][0] * 0.5 * b / c); /* x_ndc -= -side P00 (b/2) / c */
        glm_mat4_mul(proj, view, vp);
        memcpy(u->eye_view_proj[eye].m, vp, sizeof vp);
    }
    frame_ctx_ubo_stereo(u, &fc->rig, &fc->display, d->width);
    memcpy(u->warp.v, (float[4]){(float)d->tess_px, (float)d->tess_error, (float)d->depth_epsilon,
                                 (float)d->halton_radius}, 16);
    memcpy(u->warp2.v, (float[4]){(float)d->max_tess_level, d->diffuse ? 0.0f : 1.0f, d->measure ? 1.0f : 0.0f, 0}, 16);
}

/* The frame's constants. */
static void fill_ubo(frame *f, vg_frame_ubo *u)
{
    frame_ctx *fc = &f->fc;
    memset(u, 0, sizeof *u);
    memcpy(u->view_proj.m, fc->cam.view_proj, 64);
    memcpy(u->view_proj_prev.m, fc->cam_prev.view_proj, 64);
    memcpy(u->view_proj_next.m, fc->cam_next.view_proj, 64);
    memcpy(u->view.m, fc->cam.view, 64);
    mat4 vp, inv; /* cglm's SIMD paths need its own aligned matrices */
    memcpy(vp, fc->cam.view_proj, sizeof vp);
    glm_mat4_inv(vp, inv);
    memcpy(u->inv_view_proj.m, inv, 64);
    memcpy(u->camera_pos.v, (float[4]){fc->cam.position[0], fc->cam.position[1], fc->cam.position[2], fc->cam.zfar}, 16);
    memcpy(u->viewport.v, (float[4]){(float)fc->width, (float)fc->height, 1.0f / (float)fc->width,
                                     1.0f / (float)fc->height}, 16);
    shadow_gpu_setup(f->shadow, u);
    stereo_setup(f, u);
    /* Computed saliency: the contrast's reference colour and the depth
     * scale, the camera's distance to the scene's centre. */
    const float *lo = fc->sg->now.bounds_min, *hi = fc->sg->now.bounds_max;
    float dc[3] = {0.5f * (lo[0] + hi[0]) - fc->cam.position[0], 0.5f * (lo[1] + hi[1]) - fc->cam.position[1],
                   0.5f * (lo[2] + hi[2]) - fc->cam.position[2]};
    memcpy(u->saliency.v, (float[4]){fc->sg->mean_base[0], fc->sg->mean_base[1], fc->sg->mean_base[2],
                                     sqrtf(dc[0] * dc[0] + dc[1] * dc[1] + dc[2] * dc[2]) + 1e-3f}, 16);
}

/* What a completed slot measured: its timestamps (a CPU device writes none:
 * the pass clock times its passes, `timed`) and its probe. */
static void slot_done(frame *f, int slot, bool timed)
{
    if (!timed) {
        f->pass_count = f->fc.gpu->is_cpu ? 0 : rg_timings(f->graph, (uint32_t)slot, f->pass_ms, RG_MAX_PASSES);
        f->host_done_ms = f->host_ms[slot];
    }
    if (f->probe) {
        if (f->probe_count == FRAME_PROBES_KEPT) /* not taken: the oldest goes */
            memmove(f->probes, f->probes + 1, --f->probe_count * sizeof f->probes[0]);
        f->probes[f->probe_count++] = probe_gpu_read(f->probe, slot, f->slot_index[slot]);
    }
}

/* Takes the next slot once the GPU is done with it, evaluates the scene
 * and fills the slot's constants. */
static vg_status frame_begin(frame *f, long index)
{
    frame_ctx *fc = &f->fc;
    gpu *g = fc->gpu;
    fc->slot = (fc->slot + 1) % VG_FRAMES_IN_FLIGHT;
    int slot = fc->slot;
    if (f->submitted[slot]) {
        VK_TRY(vkWaitForFences(g->device, 1, &f->fence[slot], VK_TRUE, UINT64_MAX));
        VK_TRY(vkResetFences(g->device, 1, &f->fence[slot]));
        f->submitted[slot] = false;
        slot_done(f, slot, false);
    }
    f->host_t0 = vg_now_ms(); /* the host part starts once the slot is free */
    fc->times = frame_times_at(index, f->desc.fps, f->desc.keyframe_stride);
    f->slot_index[slot] = index;
    scene_gpu_update(fc->sg, slot, (float)fc->times.t, (float)fc->times.t_prev, (float)fc->times.t_next);
    float aspect = (float)fc->width / (float)fc->height;
    scene_camera_resolve(fc->scene, &fc->sg->now, fc->camera, aspect, &fc->cam);
    scene_camera_resolve(fc->scene, &fc->sg->prev, fc->camera, aspect, &fc->cam_prev);
    scene_camera_resolve(fc->scene, &fc->sg->next, fc->camera, aspect, &fc->cam_next);
    vg_frame_ubo *u = fc->ubo[slot].mapped;
    fill_ubo(f, u);
    f->outputs.shadow_texel_m[0] = u->shadow.v[1];
    f->outputs.shadow_texel_m[1] = u->shadow.v[2];
    f->outputs.shadow_split_m = u->shadow.v[0];
    if (!f->vgx)
        return VG_OK;
    vgx_frame_plan plan;
    vgx_result r = vgx_engine_begin_frame(f->vgx, fc->times.index, slot, &plan);
    if (r != VGX_SUCCESS)
        return vgx_engine_status(r);
    /* The frame is the SDK's host: it renders what the plan asks for. */
    keyframe_gpu_tile tiles[MID_MAX_KEYFRAMES];
    uint32_t n = plan.keyframe_count < MID_MAX_KEYFRAMES ? plan.keyframe_count : MID_MAX_KEYFRAMES;
    for (uint32_t i = 0; i < n; i++) {
        vgx_keyframe kf;
        vgx_get_keyframe(f->vgx, i, &kf);
        tiles[i] = (keyframe_gpu_tile){kf.time_s, kf.prev_time_s, kf.next_time_s, {0}};
        memcpy(tiles[i].atlas_from_clip, kf.atlas_from_clip, sizeof kf.atlas_from_clip);
    }
    keyframe_gpu_prepare(f->keyframes, tiles, (int)n);
    return VG_OK;
}

/* Binds this slot's imported buffers to the graph. */
static void frame_bind(frame *f)
{
    frame_ctx *fc = &f->fc;
    int slot = fc->slot;
    rg_bind_buffer(f->graph, f->res.ubo, fc->ubo[slot].buffer);
    rg_bind_buffer(f->graph, f->res.vertices, fc->sg->dynamic[slot].buffer);
    rg_bind_buffer(f->graph, f->res.statics, fc->sg->statics.buffer);
    rg_bind_buffer(f->graph, f->res.indices, fc->sg->indices.buffer);
    const rg_res maps[3] = {f->res.g, f->res.h, f->res.f};
    for (int i = 0; i < 3; i++)
        if (f->vgx && f->maps[i].image)
            rg_bind_image(f->graph, maps[i], f->maps[i].image, f->maps[i].view);
    if (f->desc.readback)
        rg_bind_buffer(f->graph, f->r_readback, f->readback.buffer);
    if (f->probe)
        probe_gpu_bind(f->probe, f->graph);
    if (f->warp)
        warp_gpu_bind(f->warp, f->graph);
}

/* Records the compiled graph for the current slot. */
static vg_status frame_record(frame *f, VkCommandBuffer *out)
{
    int slot = f->fc.slot;
    VkCommandBuffer cmd = f->cmd[slot];
    VK_TRY(vkResetCommandBuffer(cmd, 0));
    VK_TRY(vkBeginCommandBuffer(cmd, &(VkCommandBufferBeginInfo){
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT}));
    rg_execute(f->graph, cmd, (uint32_t)slot);
    VK_TRY(vkEndCommandBuffer(cmd));
    *out = cmd;
    return VG_OK;
}

/* One command buffer; the window's semaphores where `first` / `last` (none
 * headless). The acquire semaphore is waited on where the graph expects the
 * image (import_track in graph.c: colour attachment output). */
static VkResult submit_one(gpu *g, VkCommandBuffer cmd, const frame_target *t, bool first, bool last, VkFence fence)
{
    return gpu_queue_submit(g, cmd, t && first ? t->wait : VK_NULL_HANDLE,
                            VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, t && last ? t->signal : VK_NULL_HANDLE,
                            fence);
}

/* The pass clock on a CPU device: each ordered pass recorded, submitted and
 * waited for on its own and timed by the wall clock, so the passes' ms add
 * up to the frame's. lavapipe's timestamps cannot do this: llvmpipe bins
 * draws and rasterises them later, on other threads, so a draw's work lands
 * in a later pass's timestamps or in none (docs/PERFORMANCE.md). */
static vg_status submit_timed(frame *f, const frame_target *target)
{
    gpu *g = f->fc.gpu;
    int slot = f->fc.slot;
    VkCommandBuffer cmd = f->cmd[slot];
    uint32_t n = rg_order_count(f->graph);
    f->host_done_ms = vg_now_ms() - f->host_t0; /* each pass's recording is in that pass's ms */
    for (uint32_t o = 0; o < n && o < RG_MAX_PASSES; o++) {
        double t0 = vg_now_ms();
        VK_TRY(vkResetCommandBuffer(cmd, 0));
        VK_TRY(vkBeginCommandBuffer(cmd, &(VkCommandBufferBeginInfo){
            .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
            .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT}));
        rg_execute_pass(f->graph, cmd, o);
        VK_TRY(vkEndCommandBuffer(cmd));
        VK_TRY(submit_one(g, cmd, target, o == 0, o + 1 == n, f->fence[slot]));
        VK_TRY(vkWaitForFences(g->device, 1, &f->fence[slot], VK_TRUE, UINT64_MAX));
        VK_TRY(vkResetFences(g->device, 1, &f->fence[slot]));
        f->pass_ms[o] = vg_now_ms() - t0;
    }
    f->pass_count = n;
    slot_done(f, slot, true);
    return VG_OK;
}

/* Records the whole graph and submits it once (timestamps around each pass
 * when the device has them); `wait_done`: headless, wait for it. */
static vg_status submit_frame(frame *f, const frame_target *target, bool wait_done)
{
    if (f->timed && f->fc.gpu->is_cpu)
        return submit_timed(f, target);
    VkCommandBuffer cmd;
    vg_status st = frame_record(f, &cmd);
    if (st != VG_OK)
        return st;
    gpu *g = f->fc.gpu;
    int slot = f->fc.slot;
    VK_TRY(submit_one(g, cmd, target, true, true, f->fence[slot]));
    f->host_ms[slot] = vg_now_ms() - f->host_t0;
    f->submitted[slot] = true;
    if (!wait_done)
        return VG_OK;
    VK_TRY(vkWaitForFences(g->device, 1, &f->fence[slot], VK_TRUE, UINT64_MAX));
    VK_TRY(vkResetFences(g->device, 1, &f->fence[slot]));
    f->submitted[slot] = false;
    slot_done(f, slot, false);
    return VG_OK;
}

/* A frame: its slot and constants, the overlay, the bindings (the window's
 * image when there is one), the submission. Headless frames are waited for,
 * so outputs and timings belong to them. */
static vg_status run_frame(frame *f, long index, const frame_hud *hud, const frame_target *target)
{
    vg_status st = frame_begin(f, index);
    if (st != VG_OK)
        return st;
    if (f->overlay)
        overlay_gpu_update(f->overlay, hud);
    if (target)
        rg_bind_image(f->graph, f->r_swapchain, target->image, target->view);
    frame_bind(f);
    return submit_frame(f, target, !target);
}

vg_status frame_render(frame *f, long index)
{
    if (f->present) {
        vg_error("frame_render: this frame presents to a window; use frame_present");
        return VG_ERR_ARG;
    }
    return run_frame(f, index, f->hud, NULL);
}

vg_status frame_set_hud(frame *f, const frame_hud *hud)
{
    if (!f->overlay) {
        vg_error("frame_set_hud: the frame draws no overlay (frame_desc.overlay, stereo)");
        return VG_ERR_ARG;
    }
    if (!f->hud && !(f->hud = malloc(sizeof *f->hud)))
        return VG_ERR_NOMEM;
    *f->hud = *hud;
    return VG_OK;
}

vg_status frame_present(frame *f, long index, const frame_target *target, const struct frame_hud *hud)
{
    if (!f->present) {
        vg_error("frame_present: the frame was created without a swapchain format and extent");
        return VG_ERR_ARG;
    }
    return run_frame(f, index, hud, target);
}

void frame_time_passes(frame *f, bool on) { f->timed = on; }

/* Waits for every frame in flight (before resizing or reading timings). */
vg_status frame_wait_idle(frame *f)
{
    for (int k = 1; k <= VG_FRAMES_IN_FLIGHT; k++) { /* the oldest first */
        int i = (f->fc.slot + k) % VG_FRAMES_IN_FLIGHT;
        if (f->submitted[i]) {
            VK_TRY(vkWaitForFences(f->fc.gpu->device, 1, &f->fence[i], VK_TRUE, UINT64_MAX));
            VK_TRY(vkResetFences(f->fc.gpu->device, 1, &f->fence[i]));
            f->submitted[i] = false;
            slot_done(f, i, false);
        }
    }
    return VG_OK;
}

int frame_take_probes(frame *f, frame_probe *out, int cap)
{
    int n = f->probe_count < cap ? f->probe_count : cap;
    memcpy(out, f->probes, (size_t)n * sizeof *out);
    memmove(f->probes, f->probes + n, (size_t)(f->probe_count - n) * sizeof *out);
    f->probe_count -= n;
    return n;
}

const frame_outputs *frame_get_outputs(const frame *f) { return &f->outputs; }
const frame_times *frame_get_times(const frame *f) { return &f->fc.times; }
const vg_camera *frame_get_camera(const frame *f) { return &f->fc.cam; }
const frame_desc *frame_get_desc(const frame *f) { return &f->desc; }
rg_graph *frame_get_graph(frame *f) { return f->graph; }

void frame_restart(frame *f)
{
    if (f && f->vgx)
        vgx_restart(f->vgx);
}

double frame_original_vergence(const frame *f, double z_m)
{
    return stereo_camera_vergence(&f->fc.rig, &f->fc.display, z_m);
}

void frame_get_info(const frame *f, frame_info *out)
{
    *out = (frame_info){.disparity = f->disparity != NULL, .saliency_computed = f->fc.sg->computed_saliency};
    if (!f->disparity)
        return;
    disparity_gpu_info i;
    disparity_gpu_get_info(f->disparity, &i);
    out->grid_stride = i.stride;
    out->grid_nx = i.nx;
    out->grid_ny = i.ny;
    out->window_past = i.past;
    out->window_future = i.future;
    out->range_lo = i.range_lo;
    out->range_hi = i.range_hi;
}

vg_status frame_solved_keyframe(const frame *f, long keyframe, disparity_gpu_keyframe *out)
{
    if (!f->disparity) {
        vg_error("the frame has no disparity pipeline");
        return VG_ERR_ARG;
    }
    return disparity_gpu_keyframe_read(f->disparity, keyframe, out);
}

uint32_t frame_pass_timings(frame *f, const char **names, double *ms, uint32_t cap)
{
    uint32_t n = f->pass_count < cap ? f->pass_count : cap;
    for (uint32_t i = 0; i < n; i++) {
        names[i] = rg_pass_name(f->graph, rg_order_pass(f->graph, i));
        ms[i] = f->pass_ms[i];
    }
    if (n && n < cap) {
        names[n] = FRAME_PASS_HOST;
        ms[n++] = f->host_done_ms;
    }
    return n;
}
