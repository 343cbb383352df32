// vergence — display and stereo-rig geometry on the GPU (engine/stereo is
// the double-precision reference; DESIGN.md "Units and conventions").
// Image pixels span the panel width: one image pixel is u.display.z metres.

const float ARCMIN_PER_RAD = 3437.74677;

// Image parallax x_right - x_left (pixels) of the original rig at depth z.
float rig_parallax_px(float z)
{
    return u.rig.x * (1.0 - u.rig.y / z);
}

// Vergence (arcmin) of a screen parallax in image pixels: 2 atan((e - P) / 2D).
float vergence_from_px(float px)
{
    return 2.0 * atan((u.display.x - px * u.display.z) / (2.0 * u.display.y)) * ARCMIN_PER_RAD;
}

// Image pixels of a vergence: P = e - 2 D tan(a / 2).
float px_from_vergence(float a)
{
    return (u.display.x - 2.0 * u.display.y * tan(0.5 * a / ARCMIN_PER_RAD)) / u.display.z;
}

float vergence_from_depth(float z)
{
    return vergence_from_px(rig_parallax_px(z));
}
