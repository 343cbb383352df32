// vergence — the display model in GLSL (docs/sdk.md "The warp"): vergence
// (arcmin) and screen parallax (image pixels) of the viewer of vergence.h's
// vgx_display. Reads VGX_CONSTANTS.display (vec4: interocular distance e (m),
// viewing distance D (m), metres per image pixel, the screen's vergence
// (arcmin)) and .viewport (width, height, 1 / width, 1 / height); the
// includer defines VGX_CONSTANTS, or includes warp.glsl, which declares the
// SDK's constant block.
#ifndef VERGENCE_DISPLAY_GLSL
#define VERGENCE_DISPLAY_GLSL

const float VGX_ARCMIN_PER_RAD = 3437.74677;

// Vergence (arcmin) of a screen parallax in image pixels, x_right - x_left:
// 2 atan((e - P) / 2D).
float vgx_vergence_from_px(float px)
{
    return 2.0 * atan((VGX_CONSTANTS.display.x - px * VGX_CONSTANTS.display.z) / (2.0 * VGX_CONSTANTS.display.y)) *
           VGX_ARCMIN_PER_RAD;
}

// Image pixels of a vergence: P = e - 2 D tan(a / 2).
float vgx_px_from_vergence(float a)
{
    return (VGX_CONSTANTS.display.x - 2.0 * VGX_CONSTANTS.display.y * tan(0.5 * a / VGX_ARCMIN_PER_RAD)) /
           VGX_CONSTANTS.display.z;
}

// The image pixel (x right, y down) of a clip position, in a viewport of
// VGX_CONSTANTS.viewport.xy pixels.
vec2 vgx_centre_pixel(vec4 clip)
{
    return (clip.xy / clip.w * 0.5 + 0.5) * VGX_CONSTANTS.viewport.xy;
}

#endif
