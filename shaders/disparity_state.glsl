// vergence — the operator's mapping entries (see disparity_operator.glsl);
// needs `op` and `state` declared, or OP_STATE(i) defined (the state's float
// i: disparity_map.comp reads it through a texel view).
// Mapping entry e: header at e * DISP_OP_STATE_FLOATS, knots after it.
#ifndef OP_STATE
#define OP_STATE(i) state[i]
#endif
#define ST_DOM_LO(e) OP_STATE((e) * DISP_OP_STATE_FLOATS + 0u)
#define ST_DOM_HI(e) OP_STATE((e) * DISP_OP_STATE_FLOATS + 1u)
#define ST_OUT_LO(e) OP_STATE((e) * DISP_OP_STATE_FLOATS + 2u)
#define ST_OUT_HI(e) OP_STATE((e) * DISP_OP_STATE_FLOATS + 3u)
#define ST_SCALE(e) OP_STATE((e) * DISP_OP_STATE_FLOATS + 4u)
#define ST_HAS_PREV(e) OP_STATE((e) * DISP_OP_STATE_FLOATS + 5u)
#define ST_LO(e) OP_STATE((e) * DISP_OP_STATE_FLOATS + 6u)
#define ST_HI(e) OP_STATE((e) * DISP_OP_STATE_FLOATS + 7u)
#define ST_KNOT(e, b) OP_STATE((e) * DISP_OP_STATE_FLOATS + 8u + (b))

// The mapping of entry e at vergence x (disp_operator_map).
float op_map(uint e, float x)
{
    if (op.kind == DISP_OP_NONE)
        return x;
    float as = op.screen_vergence;
    if (op.kind == DISP_OP_LINEAR)
        return as + ST_SCALE(e) * (x - as);
    float lo = ST_DOM_LO(e), span = ST_DOM_HI(e) - lo;
    if (!(span > 1e-6))
        return as + ST_SCALE(e) * (x - as);
    float bins = float(op.bins);
    float u = clamp((x - lo) / span * bins, 0.0, bins);
    uint b = min(uint(u), op.bins - 1u);
    float k = ST_KNOT(e, b) + (u - float(b)) * (ST_KNOT(e, b + 1u) - ST_KNOT(e, b));
    return ST_OUT_LO(e) + (ST_OUT_HI(e) - ST_OUT_LO(e)) * k;
}

// The integer histogram weight of an 8-bit saliency (DISP_OP_WEIGHT_SCALE).
float op_weight(float saliency)
{
    if ((op.flags & DISP_OP_FLAG_NO_SALIENCY) != 0u)
        return float(DISP_OP_WEIGHT_SCALE);
    return 255.0 + 10.0 * round(saliency * 255.0);
}
