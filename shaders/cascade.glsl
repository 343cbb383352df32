// vergence — the engine's binding of the public warp (include/vergence/
// warp.glsl, which hosts of the SDK include too): its constants are the
// frame UBO's members, its maps and curve the frame's push descriptors.
// Needs common.glsl and stereo.glsl first.
#define VGX_WARP_SET 0
#define VGX_WARP_BINDING_DEPTH VG_BINDING_DEPTH
#define VGX_WARP_BINDING_TARGET VG_BINDING_TARGET
#define VGX_WARP_BINDING_CURVE VG_BINDING_CURVE
#include "vergence/warp.glsl"
#if VGX_CURVE_BINS != VG_CURVE_BINS || VGX_STAGE_CURVE != VG_STAGE_CURVE || VGX_STAGE_DIRECT != VG_STAGE_DIRECT
#error "include/vergence/warp.glsl and shaders/shared.h disagree"
#endif
