/* vergence — the end of a windowed frame (DESIGN.md step 10): the composed
 * stereo image (the overlays already in each eye: overlay_gpu.h) is
 * blitted, scaled to fit, onto the swapchain image; the bars around it are
 * black.
 *
 *   present.blit  (transfer) clear the swapchain image, res->stereo -> its middle
 *
 * The swapchain image is imported: the frame finds it just acquired and
 * leaves it ready to present. */
#pragma once
#include "pass/frame_ctx.h"

typedef struct present_gpu present_gpu;

typedef struct present_gpu_desc {
    VkFormat format;             /* the swapchain's */
    VkExtent2D extent;           /* the swapchain image's */
    VkExtent2D source;           /* what the frame shows: the composed stereo image, or the centre colour */
} present_gpu_desc;

vg_status present_gpu_create(frame_ctx *fc, const present_gpu_desc *desc, present_gpu **out);
void present_gpu_destroy(present_gpu *p);
/* Declares the swapchain image and the pass; returns the imported image. */
rg_res present_gpu_add(present_gpu *p, rg_graph *g, frame_resources *res);
