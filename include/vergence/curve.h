/* vergence — the global curve's evaluation (vergence/warp_shared.h's
 * vgx_curve_data), one source for the warp's shaders and the CPU curve
 * (vergence/lang.h's subset of C and GLSL). GLSL: include it after the
 * storage block whose instance is named vgx_curve (vergence/warp.glsl
 * declares it); the functions read that block. C: each function takes the
 * curve as its first argument. */
#ifndef VERGENCE_CURVE_H
#define VERGENCE_CURVE_H

#include "warp_shared.h"

#ifdef GL_core_profile
#define VGX_CURVE_PARAM
#define VGX_CURVE_ARG
#define VGX_CURVE_AT(member) vgx_curve.member
#define VGX_SEGMENT(a, b) vgx_segment(a, b)
#else
#define VGX_CURVE_PARAM const vgx_curve_data *vgx_curve,
#define VGX_CURVE_ARG vgx_curve,
#define VGX_CURVE_AT(member) vgx_curve->member
#define VGX_SEGMENT(a, b) ((vgx_segment){(a), (b)})
#endif

/* Two nodes of the curve: the segment that holds an inverse depth. */
VGX_STRUCT(vgx_segment) {
    int first;
    int second;
};

/* Linear in inverse depth q between nodes a and b. */
VGX_FN float vgx_curve_between(VGX_CURVE_PARAM int a, int b, float q)
{
    float dq = VGX_CURVE_AT(inv_depth[b]) - VGX_CURVE_AT(inv_depth[a]);
    float t = dq > 1e-12f || dq < -1e-12f ? (q - VGX_CURVE_AT(inv_depth[a])) / dq : 0.0f;
    return vgx_mix(VGX_CURVE_AT(vergence[a]), VGX_CURVE_AT(vergence[b]), t);
}

/* The segment that holds inverse depth q; past either end, the end's
 * VGX_CURVE_REACH bins, so the curve continues linearly there (vertices off
 * screen or nearer than any pixel: the original g is affine in 1/z, so the
 * continuation is exact for it). */
VGX_FN vgx_segment vgx_curve_segment(VGX_CURVE_PARAM float q)
{
    const int last = VGX_CURVE_BINS - 1;
    if (q <= VGX_CURVE_AT(inv_depth[0]))
        return VGX_SEGMENT(0, VGX_CURVE_REACH);
    if (q >= VGX_CURVE_AT(inv_depth[last]))
        return VGX_SEGMENT(last - VGX_CURVE_REACH, last);
    /* Start at q's bin (nodes increase in inverse depth and each lies in
     * its bin), then step to the segment: rounding may put q a bin off. */
    float span = VGX_CURVE_AT(inv_depth_near) - VGX_CURVE_AT(inv_depth_far);
    int i = VGX_INT((q - VGX_CURVE_AT(inv_depth_far)) / (span > 1e-12f ? span : 1e-12f) * VGX_FLOAT(VGX_CURVE_BINS));
    i = i < 0 ? 0 : i > last - 1 ? last - 1 : i;
    while (i > 0 && q < VGX_CURVE_AT(inv_depth[i]))
        i--;
    while (i < last - 1 && q > VGX_CURVE_AT(inv_depth[i + 1]))
        i++;
    return VGX_SEGMENT(i, i + 1);
}

/* The curve's vergence (arcmin) at depth z (m). */
VGX_FN float vgx_curve_vergence(VGX_CURVE_PARAM float z)
{
    float q = 1.0f / (z > 1e-6f ? z : 1e-6f);
    vgx_segment s = vgx_curve_segment(VGX_CURVE_ARG q);
    return vgx_curve_between(VGX_CURVE_ARG s.first, s.second, q);
}

/* The slope of the curve's segment s, d vergence / d (1/z). */
VGX_FN float vgx_curve_slope(VGX_CURVE_PARAM vgx_segment s)
{
    float dq = VGX_CURVE_AT(inv_depth[s.second]) - VGX_CURVE_AT(inv_depth[s.first]);
    return dq > 1e-12f || dq < -1e-12f ? (VGX_CURVE_AT(vergence[s.second]) - VGX_CURVE_AT(vergence[s.first])) / dq
                                       : 0.0f;
}

#endif /* VERGENCE_CURVE_H */
