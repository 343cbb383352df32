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
#include "render/frame_ctx.h"

typedef struct present_gpu present_gpu;

vg_status present_gpu_create(frame_ctx *fc, VkFormat format, VkExtent2D extent, present_gpu **out);
void present_gpu_destroy(present_gpu *p);
/* Declares the swapchain image and the pass; returns the imported image. */
rg_res present_gpu_add(present_gpu *p, rg_graph *g, frame_resources *res);
