/* vergence — disparity.original on the GPU (DESIGN.md step 3): g, the
 * vergence a viewer of the display gets from the original stereo rig, per
 * pixel of linear depth (stereo_camera_vergence, engine/stereo, is the
 * reference). The frame (disparity_gpu) and the SDK record it alike. */
#pragma once
#include <stdint.h>

#include "gpu/pipeline.h"

typedef struct original_gpu {
    gpu_compute_kit kit;
} original_gpu;

vg_status original_gpu_create(gpu *g, original_gpu *out);
void original_gpu_destroy(gpu *g, original_gpu *o);
/* ubo: a vg_frame_ubo whose rig and display are set; depth (R32F, metres)
 * and g (R32F, arcmin) as storage images in the given layouts. */
void original_gpu_record(gpu *g, const original_gpu *o, VkCommandBuffer cmd, VkBuffer ubo,
                         const VkDescriptorImageInfo *depth, const VkDescriptorImageInfo *out_g, uint32_t width,
                         uint32_t height);
