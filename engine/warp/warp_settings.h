/* vergence — the tessellated warp's settings and their defaults, resolved
 * once for the engine's frame (frame_desc) and the SDK (vgx_warp_settings).
 * Header-only: the SDK's library takes nothing else of the warp with it. */
#pragma once
#include <stdint.h>

typedef struct warp_settings {
    double tess_px;          /* edge length target in pixels (paper: 1); 0 = error-driven */
    double tess_error_px;    /* error-driven: the disparity error an edge may leave; 0 = 0.025 px */
    uint32_t max_level;      /* 0 = 32, 64 with tess_px (the caller clamps it to the device) */
    double depth_epsilon;    /* the cascade: relative depth difference of one surface; 0 = 0.01 */
    double halton_radius_px; /* the cascade's Halton search radius; 0 = 24 px */
} warp_settings;

/* Zero means default, field by field. 1-pixel tessellation needs the
 * hardware's full range. Error-driven levels seldom pass 4, but long edges
 * across the near ground need more (cubes at 240x135: p99 0.093 px at cap
 * 16, 0.057 at 32, 0.031 at 64, against 0.025 at 1 px); a lower cap packs
 * more patches into each of lavapipe's bounded draws. */
static inline warp_settings warp_settings_defaults(warp_settings s)
{
    if (s.tess_px <= 0 && s.tess_error_px <= 0)
        s.tess_error_px = 0.025;
    if (!s.max_level)
        s.max_level = s.tess_px > 0 ? 64 : 32;
    if (s.depth_epsilon <= 0)
        s.depth_epsilon = 0.01;
    if (s.halton_radius_px <= 0)
        s.halton_radius_px = 24;
    return s;
}
