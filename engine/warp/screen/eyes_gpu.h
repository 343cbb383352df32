/* vergence — a stereo pair without tessellation (the SDK's
 * VGX_CONTEXT_EYES): the host's shaded centre view moved per pixel by half
 * the disparity of the target map, for hosts whose materials cannot take
 * the tessellated warp (include/vergence/warp.glsl). Forward warping with
 * a depth test, each centre pixel filling the eye pixels up to its right
 * neighbour's landing place when both are one surface (no cracks where a
 * surface stretches); then each disocclusion takes the colour of the
 * nearest covered pixel along its row on the farther side (the background
 * the moved surface uncovered). Four steps, both eyes each
 * (shaders/eyes.glsl):
 *   vgx.eyes.clear   nothing has landed
 *   vgx.eyes.depth   each centre pixel's depth into its span, the nearest kept
 *   vgx.eyes.color   the nearest's colour (alpha 1)
 *   vgx.eyes.fill    disocclusions from the farther side (alpha 0.5; none within reach: 0) */
#pragma once
#include <stdint.h>

#include "gpu/pipeline.h"
#include "graph/graph.h"

typedef struct eyes_gpu eyes_gpu;

/* `sampler` reads the colour (nearest, clamped); the context owns it. */
vg_status eyes_gpu_create(gpu *g, uint32_t width, uint32_t height, VkSampler sampler, eyes_gpu **out);
void eyes_gpu_destroy(eyes_gpu *e);
/* The steps: ubo (vg_frame_ubo: the display and viewport), depth and target
 * (R32F, storage), colour (sampled) -> left and right (RGBA8, storage). */
void eyes_gpu_add(eyes_gpu *e, rg_graph *g, rg_res ubo, rg_res depth, rg_res target, rg_res color, rg_res left,
                  rg_res right);
