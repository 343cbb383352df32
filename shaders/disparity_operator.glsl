// vergence — disparity.operator: h = M(g, saliency), exactly as
// disp_operator_apply() (engine/disparity/disp_operator.c, docs/method.md
// Sec. 3). One workgroup fits a mapping to the samples of one image: the
// domain (this image's range of g, or a fixed one), the linear operator's
// scale, and for lang the saliency-weighted histogram (integer weights:
// order-free), blurred, turned into knots, smoothed in time for
// lang-smoothed (disparity_fit.glsl). The includer declares `op` (the
// disp_op_push constants, DISP_OP_PUSH) and `state` (the mapping entries).
#extension GL_EXT_scalar_block_layout : require
#include "disparity/mid_shared.h"

#define DISP_OP_PUSH layout(push_constant, scalar) uniform OpPush { disp_op_push op; }
