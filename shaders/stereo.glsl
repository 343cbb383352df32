// vergence — display and stereo-rig geometry on the GPU (engine/stereo is
// the double-precision reference; DESIGN.md "Units and conventions").
// Image pixels span the panel width: one image pixel is u.display.z metres.

#ifndef VGX_CONSTANTS
#define VGX_CONSTANTS u
#endif
#include "vergence/display.glsl"

// Image parallax x_right - x_left (pixels) of the original rig at depth z.
float rig_parallax_px(float z)
{
    return u.rig.x * (1.0 - u.rig.y / z);
}

float vergence_from_depth(float z)
{
    return vgx_vergence_from_px(rig_parallax_px(z));
}
