// vergence — mid.upsample (DESIGN.md step 7, paper 4.4, Fig. 4): only the
// correction f / h is upsampled, exactly as disp_upsample.c (docs/method.md
// Sec. 8). The coarse grid: sample (qx, qy) is the full-resolution pixel
// (min(qx s + s/2, W - 1), min(qy s + s/2, H - 1)).
#extension GL_EXT_scalar_block_layout : require
#include "disparity/mid_shared.h"

layout(push_constant, scalar) uniform UpsPush { disp_upsample_push up; };

int grid_px(int q) { return min(q * int(up.stride) + int(up.stride) / 2, int(up.full_w) - 1); }
int grid_py(int q) { return min(q * int(up.stride) + int(up.stride) / 2, int(up.full_h) - 1); }
