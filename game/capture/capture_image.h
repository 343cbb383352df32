/* vergence — the pictures of a capture that are more than a copy of an
 * image: the cascade view (paper Fig. 5), the left eye tinted by the stage
 * of the warp's cascade that gave each pixel's vertices their disparity. */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "pass/frame_types.h"

/* Stage colours (index VGX_STAGE_*), also the report's legend. */
extern const float capture_cascade_tint[5][3];
/* w x h RGB of the cascade view from fo->left and fo->left_aux; with
 * dim_rest, pixels without a stage (sky, holes) are washed out. */
void capture_image_cascade(const frame_outputs *fo, uint32_t w, uint32_t h, bool dim_rest, uint8_t *rgb);
