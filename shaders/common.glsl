// vergence — GLSL prelude of the scene passes.
#extension GL_EXT_scalar_block_layout : require
#include "shared.h"

layout(set = 0, binding = 0, scalar) uniform FrameBlock { vg_frame_ubo u; };
