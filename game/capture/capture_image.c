/* vergence — the cascade view. */
#include "capture_image.h"

#include "shared.h"

const float capture_cascade_tint[5][3] = {
    {1, 1, 1}, {0.25f, 0.85f, 0.3f}, {1.0f, 0.85f, 0.15f}, {1.0f, 0.45f, 0.1f}, {0.75f, 0.2f, 0.9f}};

void capture_image_cascade(const frame_outputs *fo, uint32_t w, uint32_t h, bool dim_rest, uint8_t *rgb)
{
    size_t px = (size_t)w * h;
    for (size_t i = 0; i < px; i++) {
        int stage = (int)fo->left_aux[4 * i + 3];
        const uint8_t *c = fo->left + 4 * i;
        stage = stage < 0 || stage > VGX_STAGE_CURVE || (dim_rest && c[3] < 192) ? 0 : stage;
        float lum = (0.3f * c[0] + 0.59f * c[1] + 0.11f * c[2]) / 255.0f;
        for (int k = 0; k < 3; k++)
            rgb[3 * i + (size_t)k] = stage  ? (uint8_t)(255.0f * (0.35f + 0.65f * lum) * capture_cascade_tint[stage][k])
                                     : dim_rest ? (uint8_t)(0.55f * c[k] + 0.45f * 255)
                                                : c[k];
    }
}
