// vergence — the fit of an operator's mapping (see disparity_operator.glsl).
// The includer defines sample_count() and sample_at(s) = (g, integer weight).
shared float s_lo[256], s_hi[256];
shared uint s_hist[DISP_OP_MAX_BINS];

// Fits entry `e` to the samples; lang-smoothed blends with entry `prev`
// (the same entry for the frame's own history) with weight alpha.
void op_fit(uint e, uint prev, float alpha)
{
    uint t = gl_LocalInvocationID.x, count = sample_count();
    float dom_lo = op.dom_lo, dom_hi = op.dom_hi;
    if (op.fixed_domain == 0u) {
        float lo = 3.0e38, hi = -3.0e38;
        for (uint s = t; s < count; s += 256u) {
            float g = sample_at(s).x;
            lo = min(lo, g);
            hi = max(hi, g);
        }
        s_lo[t] = lo;
        s_hi[t] = hi;
        barrier();
        for (uint s = 128u; s > 0u; s >>= 1u) {
            if (t < s) {
                s_lo[t] = min(s_lo[t], s_lo[t + s]);
                s_hi[t] = max(s_hi[t], s_hi[t + s]);
            }
            barrier();
        }
        dom_lo = s_lo[0];
        dom_hi = s_hi[0];
        barrier();
    }
    // linear: the largest scale about a_s <= 1 that fits the domain in range.
    float as = op.screen_vergence, scale = 1.0;
    if (dom_hi > op.range_hi)
        scale = min(scale, (op.range_hi - as) / (dom_hi - as));
    if (dom_lo < op.range_lo)
        scale = min(scale, (as - op.range_lo) / (as - dom_lo));
    bool lang = (op.kind == DISP_OP_LANG || op.kind == DISP_OP_LANG_SMOOTHED) && dom_hi - dom_lo > 1e-6;
    if (lang) {
        for (uint b = t; b < op.bins; b += 256u)
            s_hist[b] = 0u;
        barrier();
        float inv = float(op.bins) / (dom_hi - dom_lo);
        for (uint s = t; s < count; s += 256u) {
            vec2 v = sample_at(s);
            int b = clamp(int((v.x - dom_lo) * inv), 0, int(op.bins) - 1);
            // Lang et al.: pixels count by their visual importance.
            atomicAdd(s_hist[b], uint(v.y));
        }
        barrier();
    }
    if (t != 0u)
        return;
    ST_DOM_LO(e) = dom_lo;
    ST_DOM_HI(e) = dom_hi;
    ST_SCALE(e) = scale;
    ST_OUT_LO(e) = as + scale * (dom_lo - as);
    ST_OUT_HI(e) = as + scale * (dom_hi - as);
    ST_LO(e) = op.range_lo;
    ST_HI(e) = op.range_hi;
    if (!lang) {
        if (e != prev) {
            ST_HAS_PREV(e) = ST_HAS_PREV(prev);
            for (uint b = 0u; b <= op.bins; b++)
                ST_KNOT(e, b) = ST_KNOT(prev, b);
        }
        return;
    }
    // The mapping's slope per bin follows importance with a floor (Lang et
    // al. 2010): blur, integrate, normalise (lang_knots()).
    int bins = int(op.bins), radius = int(ceil(3.0 * op.blur_bins));
    float total = 0.0;
    float blurred[DISP_OP_MAX_BINS];
    for (int b = 0; b < bins; b++) {
        float s = 0.0, wsum = 0.0;
        for (int i = -radius; i <= radius; i++) {
            int j = b + i;
            if (j < 0 || j >= bins)
                continue;
            float k = exp(-0.5 * float(i * i) / (op.blur_bins * op.blur_bins));
            s += k * float(s_hist[j]);
            wsum += k;
        }
        blurred[b] = s / wsum;
        total += blurred[b];
    }
    bool smoothing = op.kind == DISP_OP_LANG_SMOOTHED && ST_HAS_PREV(prev) != 0.0 && (op.flags & DISP_OP_FLAG_RESET) == 0u;
    float a = smoothing ? alpha : 0.0;
    float sum = 0.0;
    for (int b = 0; b < bins; b++)
        sum += op.floor_slope + (total > 0.0 ? blurred[b] / total : 1.0 / float(bins)) * float(bins);
    float k = 0.0;
    for (int b = 0; b <= bins; b++) {
        // First-order temporal smoothing of the mapping (lang-smoothed only).
        ST_KNOT(e, uint(b)) = a * ST_KNOT(prev, uint(b)) + (1.0 - a) * (k / sum);
        if (b < bins)
            k += op.floor_slope + (total > 0.0 ? blurred[b] / total : 1.0 / float(bins)) * float(bins);
    }
    ST_KNOT(e, 0u) = 0.0;
    ST_KNOT(e, op.bins) = 1.0;
    ST_HAS_PREV(e) = 1.0;
}

