/* vergence — disparity.operator on the GPU (DESIGN.md step 4): h = M(g,
 * saliency) with the CPU reference's operators (disp_operator.c): none,
 * linear, lang, lang-smoothed, for full-resolution frames and for the
 * keyframes rendered at coarse resolution (tiles of an atlas).
 *
 * A fit (one workgroup per image) computes the mapping, a map applies it.
 * The frame's statistics come from the samples of the solver's coarse grid
 * (stride), the same samples a keyframe has, so at a keyframe the frame's
 * mapping and the keyframe's are the same mapping (stride 1 is exactly the
 * CPU reference on every pixel). The mappings live in a small persistent
 * buffer (mid_shared.h disp_op_state entries). */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "disparity/disp_operator.h"
#include "gpu/gpu.h"

typedef struct operator_gpu_desc {
    disp_operator_desc op;      /* kind, preset, screen vergence, range, domain, ... (CPU meaning) */
    double keyframe_seconds;    /* lang-smoothed at the keyframe rate, 0 = MID_KEYFRAME_SECONDS */
    uint32_t stride;            /* statistics of a frame from every stride-th pixel, 0 = 1 */
    uint32_t max_tiles;         /* keyframes fitted at once, 0 = none */
    uint32_t ring;              /* keyframe mappings kept (the store's ring slots), 0 = none */
    bool no_saliency;           /* every pixel weighs 1 (the CPU's saliency = NULL) */
} operator_gpu_desc;

typedef struct operator_gpu operator_gpu;

vg_status operator_gpu_create(gpu *g, const operator_gpu_desc *desc, operator_gpu **out);
void operator_gpu_destroy(operator_gpu *o);
/* The next fit starts without temporal state (lang-smoothed). */
void operator_gpu_reset(operator_gpu *o);
/* lang-smoothed, keyframes fitted again: the next tiles fit chains from
 * the mapping of the keyframe in ring slot key_slot (the one before its
 * first tile), not from the last tile fitted. */
void operator_gpu_tiles_chain(operator_gpu *o, uint32_t key_slot);
/* lang-smoothed in the frame: the next frame fit blends with the mapping of
 * the keyframe in ring slot key_slot (that keyframe's running mapping),
 * decayed over the `frames` frames since it, instead of with the last
 * frame's. A frame's h then depends on its keyframe and itself only, not on
 * which frames between were rendered (issue 13); at a keyframe (frames 0)
 * it is that keyframe's mapping, so h is continuous across keyframes.
 * Needs desc.ring; without a call, fits blend with the last frame fit. */
void operator_gpu_frame_anchor(operator_gpu *o, uint32_t key_slot, long frames);
/* The target range (disp_operator_range without a fixed domain). */
void operator_gpu_range(const operator_gpu *o, double *lo, double *hi);

VkBuffer operator_gpu_state(const operator_gpu *o);
VkDeviceSize operator_gpu_state_size(const operator_gpu *o);

/* Frame: fit to g (and the saliency in colour's alpha), then map g to h.
 * Images as storage images in the given layouts. */
void operator_gpu_record_fit(operator_gpu *o, VkCommandBuffer cmd, const VkDescriptorImageInfo *g,
                       const VkDescriptorImageInfo *color, uint32_t width, uint32_t height);
void operator_gpu_record_map(operator_gpu *o, VkCommandBuffer cmd, const VkDescriptorImageInfo *g,
                       const VkDescriptorImageInfo *h, uint32_t width, uint32_t height);

/* Keyframes: `tiles` coarse renders stacked in an atlas of tile_w x tile_h
 * tiles (depth, colour with saliency, motion in coarse pixels), in time
 * order; the store gets them in ring slots store_first, store_first + 1, ... */
typedef struct operator_gpu_tiles {
    VkBuffer ubo;                               /* vg_frame_ubo: rig and display for g */
    const VkDescriptorImageInfo *depth, *color, *motion, *ids;
    uint32_t tiles, tile_w, tile_h;
    VkBuffer store;
    uint32_t store_first, store_cap;
} operator_gpu_tiles;
void operator_gpu_record_tiles_fit(operator_gpu *o, VkCommandBuffer cmd, const operator_gpu_tiles *t);
void operator_gpu_record_tiles_store(operator_gpu *o, VkCommandBuffer cmd, const operator_gpu_tiles *t);
