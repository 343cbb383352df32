// vergence — the engine's binding of the public warp (include/vergence/
// warp.glsl, which hosts of the SDK include too): its constants are the
// frame UBO's members, its maps and curve the frame's push descriptors.
// Needs common.glsl and stereo.glsl first.
#define VGX_WARP_SET 0
#define VGX_WARP_BINDING_DEPTH VG_BINDING_DEPTH
#define VGX_WARP_BINDING_TARGET VG_BINDING_TARGET
#define VGX_WARP_BINDING_CURVE VG_BINDING_CURVE
#include "vergence/warp.glsl"
