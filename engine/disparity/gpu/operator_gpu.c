/* vergence — disparity.operator on the GPU. */
#include "operator_gpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "gpu/pipeline.h"
#include "disparity/mid_shared.h"
#include "shared.h"

#include "disparity_fit_comp.h"
#include "disparity_map_comp.h"
#include "mid_keyframe_fit_comp.h"
#include "mid_keyframe_store_comp.h"

enum { P_FIT, P_MAP, P_TILES_FIT, P_TILES_STORE, P_COUNT };

struct operator_gpu {
    gpu *gpu;
    operator_gpu_desc d;
    disp_op_push push;
    double lo, hi;
    double frame_s, tau;   /* lang-smoothed: a frame's seconds, the time constant */
    bool reset_frame, reset_tiles;
    int chain_from;                /* state entry the next tiles fit chains from, -1: its own chain */
    gpu_buffer state;
    VkBufferView state_view;       /* the state as R32F texels: what disparity.operator reads */
    gpu_compute_kit kit[P_COUNT];
};

vg_status operator_gpu_create(gpu *g, const operator_gpu_desc *desc, operator_gpu **out)
{
    *out = NULL;
    /* The CPU reference resolves the defaults and checks the range. */
    disp_operator *ref;
    vg_status st = disp_operator_create(&desc->op, &ref);
    if (st != VG_OK)
        return st;
    operator_gpu *o = calloc(1, sizeof *o);
    if (!o) {
        disp_operator_destroy(ref);
        return VG_ERR_NOMEM;
    }
    o->gpu = g;
    o->d = *desc;
    disp_operator_range(ref, &o->lo, &o->hi);
    disp_operator_destroy(ref);
    const disp_operator_desc op = disp_operator_desc_defaults(&desc->op), *d = &op;
    double range = d->range, frame_s = d->frame_seconds, tau = d->smooth_seconds;
    double key_s = desc->keyframe_seconds > 0 ? desc->keyframe_seconds : MID_KEYFRAME_SECONDS;
    int bins = d->bins;
    if (bins > DISP_OP_MAX_BINS) {
        vg_error("GPU operator: %d bins (at most %d)", bins, DISP_OP_MAX_BINS);
        free(o);
        return VG_ERR_ARG;
    }
    o->push = (disp_op_push){
        .kind = (uint32_t)d->kind,
        .bins = (uint32_t)bins,
        .stride = desc->stride ? desc->stride : 1,
        .fixed_domain = d->in_max > d->in_min,
        .screen_vergence = (float)d->screen_vergence,
        .range_lo = (float)(d->screen_vergence - range),
        .range_hi = (float)(d->screen_vergence + range),
        .floor_slope = (float)d->floor,
        .blur_bins = (float)d->blur_bins,
        .saliency_floor = (float)d->saliency_floor,
        .smooth_alpha = (float)exp(-frame_s / tau),
        .key_alpha = (float)exp(-key_s / tau),
        .dom_lo = (float)d->in_min,
        .dom_hi = (float)d->in_max,
        .flags = desc->no_saliency ? DISP_OP_FLAG_NO_SALIENCY : 0,
        .prev = DISP_OP_ENTRY_FRAME,
        .keys = DISP_OP_ENTRY_TILE0 + desc->max_tiles,
    };
    /* The integer histogram weights assume the default saliency floor. */
    if (fabs(o->push.saliency_floor - DISP_OP_SALIENCY_FLOOR) > 1e-6 && !desc->no_saliency)
        vg_warn("GPU operator: saliency floor %g is not the default; the GPU uses %g", o->push.saliency_floor,
                DISP_OP_SALIENCY_FLOOR);
    o->frame_s = frame_s;
    o->tau = tau;
    o->reset_frame = o->reset_tiles = true;
    o->chain_from = -1;
    size_t entries = DISP_OP_ENTRY_TILE0 + desc->max_tiles + desc->ring;
    st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "disparity.operator state",
                                                 .size = entries * DISP_OP_STATE_FLOATS * sizeof(float),
                                                 .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                                          VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT,
                                                 .host_visible = true},
                           &o->state);
    if (st == VG_OK)
        memset(o->state.mapped, 0, entries * DISP_OP_STATE_FLOATS * sizeof(float));
    if (st == VG_OK)
        st = gpu_buffer_view_create(g, o->state.buffer, VK_FORMAT_R32_SFLOAT, o->state.size,
                                    "disparity.operator state (texels)", &o->state_view);

    static const VkDescriptorType IMG = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, BUF = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                  UBO = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                                  TEXELS = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    static const VkDescriptorType types[P_COUNT][6] = {
        [P_FIT] = {IMG, IMG, BUF}, [P_MAP] = {IMG, TEXELS, IMG},
        [P_TILES_FIT] = {UBO, IMG, IMG, BUF}, [P_TILES_STORE] = {UBO, IMG, IMG, BUF, BUF, IMG}};
    static const uint32_t counts[P_COUNT] = {3, 3, 4, 6};
    const gpu_kernel_code kernels[P_COUNT] = {
        GPU_KERNEL(spv_disparity_fit_comp, "disparity.operator.fit"),
        GPU_KERNEL(spv_disparity_map_comp, "disparity.operator"),
        GPU_KERNEL(spv_mid_keyframe_fit_comp, "mid.keyframes.fit"),
        GPU_KERNEL(spv_mid_keyframe_store_comp, "mid.keyframes.store"),
    };
    for (int p = 0; p < P_COUNT && st == VG_OK; p++)
        st = gpu_compute_kit_create(g, &(gpu_compute_kit_desc){.name = kernels[p].name, .types = types[p],
                                                               .count = counts[p], .push_size = sizeof(disp_op_push),
                                                               .kernels = {kernels[p]}}, &o->kit[p]);
    if (st != VG_OK) {
        operator_gpu_destroy(o);
        return st;
    }
    *out = o;
    return VG_OK;
}

void operator_gpu_destroy(operator_gpu *o)
{
    if (!o)
        return;
    for (int p = 0; p < P_COUNT; p++)
        gpu_compute_kit_destroy(o->gpu, &o->kit[p]);
    if (o->state_view)
        vkDestroyBufferView(o->gpu->device, o->state_view, o->gpu->alloc);
    gpu_buffer_destroy(o->gpu, &o->state);
    free(o);
}

void operator_gpu_reset(operator_gpu *o) { o->reset_frame = o->reset_tiles = true; }

void operator_gpu_tiles_chain(operator_gpu *o, uint32_t key_slot)
{
    o->chain_from = o->d.ring ? (int)(o->push.keys + key_slot % o->d.ring) : -1;
}

void operator_gpu_frame_anchor(operator_gpu *o, uint32_t key_slot, long frames)
{
    if (!o->d.ring)
        return;
    /* The first-order filter from the keyframe's state over `frames`
     * frames: exp(-dt / tau) with dt the whole time since the keyframe. */
    o->push.prev = o->push.keys + key_slot % o->d.ring;
    o->push.smooth_alpha = (float)exp(-(double)(frames > 0 ? frames : 0) * o->frame_s / o->tau);
    /* The keyframe's mapping starts afresh after a reset itself. */
    o->reset_frame = false;
}

void operator_gpu_range(const operator_gpu *o, double *lo, double *hi)
{
    *lo = o->lo;
    *hi = o->hi;
}

VkBuffer operator_gpu_state(const operator_gpu *o) { return o->state.buffer; }
VkDeviceSize operator_gpu_state_size(const operator_gpu *o) { return o->state.size; }

/* ------------------------------------------------------------------------- */
/* Recording                                                                 */
/* ------------------------------------------------------------------------- */

#define IMG GPU_STORAGE_IMAGE
#define BUF GPU_STORAGE_BUFFER
#define UBO GPU_UNIFORM_BUFFER

void operator_gpu_record_fit(operator_gpu *o, VkCommandBuffer cmd, const VkDescriptorImageInfo *g,
                       const VkDescriptorImageInfo *color, uint32_t width, uint32_t height)
{
    disp_op_push pc = o->push;
    pc.width = width;
    pc.height = height;
    pc.entry = DISP_OP_ENTRY_FRAME;
    if (o->reset_frame)
        pc.flags |= DISP_OP_FLAG_RESET;
    o->reset_frame = false;
    gpu_binding b[3] = {IMG(g), IMG(color), BUF(o->state.buffer)};
    gpu_compute_kit_bind_list(o->gpu, cmd, &o->kit[P_FIT], 0, b, 3, &pc);
    vkCmdDispatch(cmd, 1, 1, 1);
}

void operator_gpu_record_map(operator_gpu *o, VkCommandBuffer cmd, const VkDescriptorImageInfo *g,
                       const VkDescriptorImageInfo *h, uint32_t width, uint32_t height)
{
    disp_op_push pc = o->push;
    pc.width = width;
    pc.height = height;
    pc.entry = DISP_OP_ENTRY_FRAME;
    gpu_binding b[3] = {IMG(g), GPU_UNIFORM_TEXEL(&o->state_view), IMG(h)};
    gpu_compute_kit_bind_list(o->gpu, cmd, &o->kit[P_MAP], 0, b, 3, &pc);
    vkCmdDispatch(cmd, (width + 7) / 8, (height + 7) / 8, 1);
}

static disp_op_push tiles_push(const operator_gpu *o, const operator_gpu_tiles *t)
{
    disp_op_push pc = o->push;
    pc.width = t->tile_w;
    pc.tile_height = t->tile_h;
    pc.height = t->tile_h * t->tiles;
    pc.tiles = t->tiles;
    pc.store_first = t->store_first;
    pc.store_cap = t->store_cap ? t->store_cap : 1;
    if (o->d.ring && pc.store_cap <= o->d.ring)
        pc.flags |= DISP_OP_FLAG_KEY_RING;
    return pc;
}

void operator_gpu_record_tiles_fit(operator_gpu *o, VkCommandBuffer cmd, const operator_gpu_tiles *t)
{
    disp_op_push pc = tiles_push(o, t);
    if (o->reset_tiles)
        pc.flags |= DISP_OP_FLAG_RESET;
    else if (o->chain_from >= 0) {
        pc.prev = (uint32_t)o->chain_from;
        pc.flags |= DISP_OP_FLAG_CHAIN_FROM;
    }
    o->reset_tiles = false;
    o->chain_from = -1;
    gpu_binding b[4] = {UBO(t->ubo), IMG(t->depth), IMG(t->color), BUF(o->state.buffer)};
    gpu_compute_kit_bind_list(o->gpu, cmd, &o->kit[P_TILES_FIT], 0, b, 4, &pc);
    vkCmdDispatch(cmd, 1, 1, 1);
}

void operator_gpu_record_tiles_store(operator_gpu *o, VkCommandBuffer cmd, const operator_gpu_tiles *t)
{
    disp_op_push pc = tiles_push(o, t);
    gpu_binding b[6] = {UBO(t->ubo), IMG(t->depth), IMG(t->motion), BUF(o->state.buffer), BUF(t->store), IMG(t->ids)};
    gpu_compute_kit_bind_list(o->gpu, cmd, &o->kit[P_TILES_STORE], 0, b, 6, &pc);
    vkCmdDispatch(cmd, (t->tile_w + 7) / 8, (t->tile_h * t->tiles + 7) / 8, 1);
}
