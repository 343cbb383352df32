/* vergence — mid.upsample on the GPU (DESIGN.md step 7, paper 4.4): the
 * solver's coarse keyframe correction f / h to this frame's full-resolution
 * f, as disp_upsample.c: in time along the G-buffer's motion to the two
 * nearest keyframes with the links' occlusion test, in space by joint
 * bilateral upsampling guided by the full-resolution h. Processing is linear
 * in the output pixels (paper 4.5). */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "gpu/gpu.h"

typedef struct upsample_gpu upsample_gpu;

/* Where this frame is between its keyframes, and where they are stored. */
typedef struct upsample_gpu_frame {
    uint32_t width, height, stride;  /* full resolution; the coarse grid's stride */
    float tau;                       /* (t - t0) / (t1 - t0) */
    bool at_key;                     /* t is keyframe k0 itself */
    bool has1;                       /* keyframe k1 is available */
    uint32_t slot0, slot1;           /* ring slots of k0, k1 (store and published ratios) */
    uint32_t slots;                  /* ring slots of the published ratios (their slopes follow) */
    float span;                      /* seconds from k0 to k1 */
    float occlusion_tolerance;       /* relative depth, 0 = MID_OCCLUSION_TOLERANCE */
    float sigma_spatial, sigma_range;/* 0 = MID_SIGMA_SPATIAL, MID_SIGMA_RANGE */
    bool depth_only;                 /* occlusion in time by depth alone (disp_upsample_desc) */
} upsample_gpu_frame;

vg_status upsample_gpu_create(gpu *g, upsample_gpu **out);
void upsample_gpu_destroy(upsample_gpu *u);

/* Coarse ratio of the frame (an R32F image of nx x ny) from depth, motion
 * (RGBA32F: px to the previous keyframe xy, to the next zw), instance ids
 * (R32_UINT), the keyframe store and the published ratios and slopes
 * (mid_published, then slots x nx x ny ratios, then as many slopes per
 * second; the gate's plane after them is not read here). */
void upsample_gpu_record_time(upsample_gpu *u, VkCommandBuffer cmd, const upsample_gpu_frame *f, const VkDescriptorImageInfo *depth,
                         const VkDescriptorImageInfo *motion, const VkDescriptorImageInfo *ids, VkBuffer store,
                         VkBuffer published, const VkDescriptorImageInfo *g, const VkDescriptorImageInfo *h,
                         const VkDescriptorImageInfo *ratio);
/* Full-resolution f from h and the coarse ratio, clamped to the published range. */
void upsample_gpu_record_space(upsample_gpu *u, VkCommandBuffer cmd, const upsample_gpu_frame *f, const VkDescriptorImageInfo *h,
                          VkBuffer published, const VkDescriptorImageInfo *ratio, const VkDescriptorImageInfo *out);
