/* vergence — the sRGB transfer function (IEC 61966-2-1) on the CPU: 8-bit
 * colours of textures and images to linear light. The shaders' is
 * lighting_srgb.glsl. */
#pragma once
#include <math.h>

static inline float vg_srgb_to_linear(float c)
{
    return c <= 0.04045f ? c / 12.92f : powf((c + 0.055f) / 1.055f, 2.4f);
}
