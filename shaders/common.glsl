// vergence — GLSL prelude of the scene passes.
#extension GL_EXT_scalar_block_layout : require
#include "shared.h"

// Compute passes that branch on values derived from the frame constants
// read them as a storage buffer (define VG_FRAME_STORAGE first): lavapipe
// (Mesa 22.3, lvp_inline_uniforms.c) folds uniform-buffer and push-constant
// values that decide a branch into the shader and compiles it again with LLVM
// for every new set of values, which for warp.classify was once per frame of a
// moving camera (about 2 s each with an empty shader cache). Storage-buffer
// loads are not folded. `gpu.capture.variants` counts the compiles.
#ifdef VG_FRAME_STORAGE
layout(set = 0, binding = 0, scalar) readonly buffer FrameBlock { vg_frame_ubo u; };
#else
layout(set = 0, binding = 0, scalar) uniform FrameBlock { vg_frame_ubo u; };
#endif
