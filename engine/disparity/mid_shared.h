/* vergence — constants, buffer layouts and per-element formulas of the
 * motion-in-depth (MID) optimiser, shared by the C reference and the GLSL
 * compute passes (paper Sec. 4.1-4.5; units in DESIGN.md; equations in
 * docs/method.md).
 *
 * Written in vergence/lang.h's subset of C17 and GLSL 4.50, with structs
 * of scalar float/uint members only and sizes a multiple of 16 bytes, so
 * std430 and C agree on every offset (static asserts at the end). The C side
 * includes it from mid_*.c; GLSL includes it with
 * GL_GOOGLE_include_directive. Every field is float32; only reductions
 * (cost, dot products) are accumulated in double on the CPU. */
#ifndef VG_MID_SHARED_H
#define VG_MID_SHARED_H

#include "vergence/lang.h"

/* ------------------------------------------------------------------------- */
/* Constants                                                                 */
/* ------------------------------------------------------------------------- */

/* The Weber fraction STEREO_WEBER_K and its inverse (paper Sec. 4.2). */
#include "stereo/stereo_shared.h"
/* a = exp(-10 |dh|) on h normalised to [0,1] over the target range (Sec. 4.1, DESIGN.md). */
#define MID_EDGE_SHARPNESS 10.0f
/* The paper's weights (Sec. 4.3). */
#define MID_W_DATA 0.05f
#define MID_W_SPATIAL 1.0f
#define MID_W_TEMPORAL 0.1f
#define MID_W_ACCEL 0.1f
/* The paper's descent step (Sec. 4.5), applied to the Jacobi-preconditioned gradient. */
#define MID_DESCENT_STEP 0.5f
#define MID_DESCENT_ITERATIONS 8
/* Default Gauss-Newton budget: outer iterations x preconditioned CG steps
 * (within 2 % of the converged cost on the tests' scenes, docs/method.md). */
#define MID_GN_ITERATIONS 4
#define MID_GN_CG_STEPS 8
/* The frame's window moves by one keyframe interval and starts from the last
 * solution (paper 4.5): outer iterations per move after the first window.
 * 240 frames at 320x180 (gpu.frame.mid_*), f/h of the MID distortion with
 * 3 / 2: cubes 0.499 / 0.500, balloon 0.552 / 0.630. */
#define MID_GN_WARM_ITERATIONS 3
/* A budgeted solve (disparity_gpu_desc.budgeted) that a move overtakes
 * still finishes this many of them before it publishes: finishing only the
 * one under way, the bird at every third frame loses 0.16 of f/h to the
 * full solve (0.71 against 0.55; tests/gpu/test_steps_gpu.c budget); with
 * two it keeps it. */
#define MID_GN_BUDGET_ITERATIONS 2
/* A flow link is valid when the bilinear taps that pass the depth test
 * carry at least this much of the bilinear weight (occlusion, Sec. 4.4). */
#define MID_LINK_MIN_WEIGHT 0.5f
/* A tap is the same surface when the depths differ by less than this
 * relative amount, or when the flows there and back cancel to within
 * MID_FLOW_TOLERANCE coarse pixels (+10 % of the flow). */
#define MID_OCCLUSION_TOLERANCE 0.2f
#define MID_FLOW_TOLERANCE 0.5f
/* Elements per block of a CPU pass; partial sums are kept per block. */
#define MID_BLOCK 4096
/* Chains per group of the CPU preconditioner sweeps. */
#define MID_CHAIN_GROUP 256
/* Workgroup size of the GLSL passes that reduce in one workgroup. */
#define MID_LOCAL_SIZE 256
/* Element kernels run MID_TILE x MID_TILE coarse pixels of one keyframe per
 * workgroup (no integer division per element, no barriers: on a CPU
 * rasteriser both are expensive); sums are written per element and added in
 * chunks of MID_SUM_CHUNK elements, in a fixed order. */
#define MID_TILE 8u
#define MID_SUM_CHUNK 64u

/* Keyframe window defaults (paper 4.4): a keyframe every 10 frames of a
 * 60 Hz sequence, a coarse sample every 5 pixels. Every "0 = default" of a
 * frame rate or keyframe interval resolves to these. */
#define MID_FPS 60
#define MID_KEYFRAME_STRIDE 10
#define MID_KEYFRAME_SECONDS ((double)MID_KEYFRAME_STRIDE / MID_FPS)
#define MID_COARSE_STRIDE 5
/* Gauss-Newton control (mid_solver.c and mid_control.comp): Armijo constant
 * and halvings of the backtracking line search, relative CG residual that
 * stops CG, distance to a bound (arcmin) within which a variable can be held. */
#define MID_LINE_ARMIJO 1e-4f
#define MID_LINE_TRIALS 12
#define MID_CG_TOLERANCE 1e-8f
#define MID_BOUND_EPS 1e-4f
/* Joint bilateral upsampling (disp_upsample.c): spatial sigma in coarse
 * pixels, range sigma in arcmin of the guide h. */
#define MID_SIGMA_SPATIAL 0.5f
#define MID_SIGMA_RANGE 4.0f
/* Spatial upsampling: the tent-weighted 2 x 2 samples decide when their
 * weights (bilinear x range) sum to at least this; else the 4 x 4 Gaussian. */
#define MID_TENT_MIN_WEIGHT 1e-4f

/* Operators h = M(g, saliency) (disp_operator.c); kinds as disp_operator_kind. */
#define DISP_OP_NONE 1u
#define DISP_OP_LINEAR 2u
#define DISP_OP_LANG 3u
#define DISP_OP_LANG_SMOOTHED 4u
#define DISP_OP_BINS 128
#define DISP_OP_MAX_BINS 256
/* (Unsuffixed: double in the C reference, float in GLSL.) */
#define DISP_OP_RANGE_COMFORT 60.0  /* half-width of the target range, arcmin (1 degree rule) */
#define DISP_OP_RANGE_STUDY 30.0
#define DISP_OP_FLOOR_COMFORT 0.1   /* slope of an empty bin, relative to a uniform one */
#define DISP_OP_FLOOR_STUDY 0.02
#define DISP_OP_BLUR_BINS 1.5
#define DISP_OP_SALIENCY_FLOOR 0.1
#define DISP_OP_SMOOTH_SECONDS 0.5
/* The GPU histogram counts integer weights: 8-bit saliency a (0..255) weighs
 * (0.1 + a / 255) = (255 + 10 a) / 2550 exactly; no saliency weighs 1. */
#define DISP_OP_WEIGHT_SCALE 2550u

/* Link mask bits: taps base, base+1, base+nx, base+nx+1. Zero = no link. */
#define MID_TAP00 1u
#define MID_TAP10 2u
#define MID_TAP01 4u
#define MID_TAP11 8u

/* ------------------------------------------------------------------------- */
/* Layouts                                                                   */
/* ------------------------------------------------------------------------- */

/* Uniform parameters of a window solve (std430, 48 bytes). Index of a
 * coarse pixel: i = k * ns + y * nx + x (keyframe-major, top row first). */
VGX_STRUCT(mid_params) {
    uint nx, ny, nt, ns;
    float w_data, w_spatial, w_temporal, w_accel;
    float range_lo, range_hi, grad_scale, inv_n; /* grad_scale = 2 / n */
};

/* A_f or A_b row i (Sec. 4.3): bilinear interpolation of the neighbouring
 * keyframe at the flow target, restricted to the taps of the same surface
 * (mask) and renormalised. 16 bytes. */
VGX_STRUCT(mid_link) {
    uint base; /* index of the top-left tap in the neighbouring keyframe */
    float fx;  /* bilinear fractions in [0,1] */
    float fy;
    uint mask; /* MID_TAP* bits of the taps that passed the depth test; 0 = invalid */
};

/* One entry of the transposed link matrix (A_f^T or A_b^T) in CSR form:
 * row j lists the source pixels i whose links read j, sorted by i, so that
 * the adjoint is a gather summed in a fixed order. 8 bytes. */
VGX_STRUCT(mid_adj_entry) {
    uint src;
    float w;
};

/* Normalised tap weights of a link. */
VGX_STRUCT(mid_taps) {
    float w00, w10, w01, w11;
};

/* ------------------------------------------------------------------------- */
/* Per-element formulas                                                      */
/* ------------------------------------------------------------------------- */

/* p(v) = sign(v) ln(1 + |v|) / k (Sec. 4.2, symmetric form of DESIGN.md). */
VGX_FN float mid_p(float v)
{
    float s = v < 0.0f ? -STEREO_INV_WEBER_K : STEREO_INV_WEBER_K;
    return s * vgx_log(1.0f + vgx_abs(v));
}

/* dp/dv = 1 / (k (1 + |v|)). */
VGX_FN float mid_dp(float v)
{
    return STEREO_INV_WEBER_K / (1.0f + vgx_abs(v));
}

/* Edge weight a of Sec. 4.1 for a difference of h normalised to the range. */
VGX_FN float mid_edge_weight(float dh_normalised)
{
    return vgx_exp(-MID_EDGE_SHARPNESS * vgx_abs(dh_normalised));
}

VGX_FN mid_taps mid_link_taps(mid_link l)
{
    float w00 = (l.mask & MID_TAP00) != 0u ? (1.0f - l.fx) * (1.0f - l.fy) : 0.0f;
    float w10 = (l.mask & MID_TAP10) != 0u ? l.fx * (1.0f - l.fy) : 0.0f;
    float w01 = (l.mask & MID_TAP01) != 0u ? (1.0f - l.fx) * l.fy : 0.0f;
    float w11 = (l.mask & MID_TAP11) != 0u ? l.fx * l.fy : 0.0f;
    /* All four taps kept: the bilinear weights already sum to 1. */
    float s = w00 + w10 + w01 + w11;
    float inv = l.mask == 15u ? 1.0f : (s > 0.0f ? 1.0f / s : 0.0f);
    mid_taps t;
    t.w00 = w00 * inv;
    t.w10 = w10 * inv;
    t.w01 = w01 * inv;
    t.w11 = w11 * inv;
    return t;
}

/* (A x)_i from the four tap values x[base], x[base+1], x[base+nx], x[base+nx+1]. */
VGX_FN float mid_link_apply(mid_taps t, float x00, float x10, float x01, float x11)
{
    return t.w00 * x00 + t.w10 * x10 + t.w01 * x01 + t.w11 * x11;
}

/* Residuals of c_t and c_a at one pixel (Sec. 4.3), and their slopes.
 * fa = (A_f f)_i, fb = (A_b f)_i; inv_dt_f/b are 1/seconds to the next and
 * previous keyframe, or 0 where the link is invalid (which zeroes the terms). */
VGX_STRUCT(mid_pixel) {
    float r_t;  /* p(v+_f) - p(v+_h)                     (times m_f) */
    float r_a;  /* p(v+_f) - p(v-_f) - (p(v+_g) - p(v-_g)) (times m_f m_b) */
    float q_f;  /* d r / d (A_f f - f) = p'(v+) / dt        (times m_f) */
    float q_b;  /* d p(v-) / d (f - A_b f) = p'(v-) / dt    (times m_b) */
};
VGX_FN mid_pixel mid_pixel_eval(float f, float fa, float fb, float inv_dt_f, float inv_dt_b,
                                float m_f, float m_b, float ph, float pg_acc)
{
    float vf = (fa - f) * inv_dt_f;
    float vb = (f - fb) * inv_dt_b;
    float pf = mid_p(vf);
    float pb = mid_p(vb);
    mid_pixel r;
    r.r_t = m_f * (pf - ph);
    r.r_a = m_f * m_b * (pf - pb - pg_acc);
    r.q_f = m_f * mid_dp(vf) * inv_dt_f;
    r.q_b = m_b * mid_dp(vb) * inv_dt_b;
    return r;
}

/* ------------------------------------------------------------------------- */
/* Temporal upsampling (Sec. 4.4, docs/method.md Sec. 8)                     */
/* ------------------------------------------------------------------------- */

/* What the upsampling in time interpolates is the correction to the
 * original, m = f / g at the keyframes, and what it hands the spatial pass
 * is the ratio f / h of frame t: m g_t / h_t at the coarse sample. So f
 * between keyframes carries the original's motion (g_t: the paper's "add
 * them to the current high-resolution original frame", 4.4), not the
 * manipulation's: where h changes faster than the keyframes (a ball crossing
 * a gap the operator compresses, in 3 frames), f / h interpolated puts that
 * change into f (docs/method.md Sec. 8). Vergence is never 0; a missing g or
 * h (not a positive finite vergence: a video's unknown pixels) keeps m. */
VGX_FN float mid_ratio_to_h(float m, float g, float h)
{
    float r = m * g / h;
    return g > 0.0f && h > 0.0f && r < 1.0e3f ? r : m;
}

/* Slope in time (per second) of a ratio r (m = f / g) at a keyframe sample,
 * along the motion: the mean of the one-sided slopes to the keyframes its
 * links reach (rf = (A_f r)_i, rb = (A_b r)_i), one of them alone, or 0. */
VGX_FN float mid_ratio_slope(float r, float rf, float rb, uint has_f, uint has_b, float inv_dt_f, float inv_dt_b)
{
    float sf = (rf - r) * inv_dt_f, sb = (r - rb) * inv_dt_b;
    if (has_f != 0u && has_b != 0u)
        return 0.5f * (sf + sb);
    return has_f != 0u ? sf : has_b != 0u ? sb : 0.0f;
}

/* The ratio between keyframes k0 (r0, slope s0) and k1 (r1, s1) at
 * tau = (t - t0) / (t1 - t0), span = t1 - t0 seconds: cubic Hermite, so the
 * correction is C1 in time. Linear interpolation kinks at every keyframe
 * (an acceleration impulse of the whole interval's curvature in one frame);
 * with s0 = s1 = (r1 - r0) / span this is that linear interpolation. */
/* The temporal upsampling's trajectory test (docs/method.md Sec. 8), the
 * links' round trip for a frame between keyframes: a keyframe tap at (tx,
 * ty) whose own flow (fx, fy) to the interval's other keyframe lands where
 * frame t's sample is in that keyframe (ox, oy) follows the sample's motion;
 * all in coarse pixels, within MID_FLOW_TOLERANCE + 10 % of the flow. */
VGX_FN uint mid_on_trajectory(float tx, float ty, float fx, float fy, float ox, float oy)
{
    float dx = tx + fx - ox, dy = ty + fy - oy;
    float lim = MID_FLOW_TOLERANCE + 0.1f * (vgx_abs(fx) + vgx_abs(fy));
    return VGX_UINT(dx * dx + dy * dy <= lim * lim ? 1 : 0);
}

VGX_FN float mid_hermite(float r0, float s0, float r1, float s1, float tau, float span)
{
    float t2 = tau * tau, t3 = t2 * tau;
    return (2.0f * t3 - 3.0f * t2 + 1.0f) * r0 + (t3 - 2.0f * t2 + tau) * span * s0 +
           (3.0f * t2 - 2.0f * t3) * r1 + (t3 - t2) * span * s1;
}

/* Computed saliency, for scenes and videos without authored saliency
 * (docs/method.md section 3): a weighted sum of three cues in [0, 1],
 *   colour contrast  the CIELAB distance of the pixel's colour to the mean
 *                    colour (Achanta et al. 2009, frequency-tuned saliency:
 *                    S = |I_mean - I(x)|), full at DISP_SAL_DE_FULL;
 *   motion           1 - exp(-speed / DISP_SAL_SPEED), speed the pixel's
 *                    screen motion per keyframe interval over the image
 *                    width (moving things draw the eye: the motion channel
 *                    of Itti, Dhavale and Pighin 2003);
 *   nearness         exp(-depth / scale), scale the distance to the scene's
 *                    centre (the depth bias of stereoscopic viewing: Wang,
 *                    Da Silva, Le Callet, Ricordel 2013, "Computational
 *                    model of stereoscopic 3D visual saliency").
 * The weights are this project's choice (stated, not fitted). */
#define DISP_SAL_W_CONTRAST 0.5f
#define DISP_SAL_W_MOTION 0.3f
#define DISP_SAL_W_NEAR 0.2f
#define DISP_SAL_DE_FULL 50.0f
#define DISP_SAL_SPEED 0.02f

/* CIE 1976 L*a*b* of linear sRGB (D65): f(t) of one XYZ component. */
VGX_FN float disp_lab_f(float t)
{
    return t > 0.008856f ? vgx_pow(t, 1.0f / 3.0f) : 7.787f * t + 16.0f / 116.0f;
}

/* Delta E (CIE 1976) between two linear sRGB colours. */
VGX_FN float disp_delta_e(float r0, float g0, float b0, float r1, float g1, float b1)
{
    float x0 = disp_lab_f((0.4124f * r0 + 0.3576f * g0 + 0.1805f * b0) / 0.9505f);
    float y0 = disp_lab_f(0.2126f * r0 + 0.7152f * g0 + 0.0722f * b0);
    float z0 = disp_lab_f((0.0193f * r0 + 0.1192f * g0 + 0.9505f * b0) / 1.089f);
    float x1 = disp_lab_f((0.4124f * r1 + 0.3576f * g1 + 0.1805f * b1) / 0.9505f);
    float y1 = disp_lab_f(0.2126f * r1 + 0.7152f * g1 + 0.0722f * b1);
    float z1 = disp_lab_f((0.0193f * r1 + 0.1192f * g1 + 0.9505f * b1) / 1.089f);
    float dl = 116.0f * (y0 - y1), da = 500.0f * ((x0 - y0) - (x1 - y1)), db = 200.0f * ((y0 - z0) - (y1 - z1));
    return vgx_sqrt(dl * dl + da * da + db * db);
}

/* The saliency of a pixel from its colour contrast (Delta E to the mean),
 * its speed (fraction of the image width per keyframe interval) and its
 * depth (metres, scale the scene's). */
VGX_FN float disp_saliency_computed(float delta_e, float speed, float depth, float depth_scale)
{
    float c = delta_e < DISP_SAL_DE_FULL ? delta_e / DISP_SAL_DE_FULL : 1.0f;
    float m = 1.0f - vgx_exp(-speed / DISP_SAL_SPEED);
    float n = depth_scale > 0.0f ? vgx_exp(-depth / depth_scale) : 0.0f;
    float s = DISP_SAL_W_CONTRAST * c + DISP_SAL_W_MOTION * m + DISP_SAL_W_NEAR * n;
    return s < 0.0f ? 0.0f : (s > 1.0f ? 1.0f : s);
}

/* The causal gate (docs/method.md "Look-ahead"): a window whose future is
 * predicted publishes h + gain (f - h) instead of f. Each move, the keyframe
 * one before the newest observed one is realized (it and both neighbours
 * are observed, and their ratios were published), so the MID metric's c_a
 * residual of the solve's own f (h times its ratio, the candidate) and of h
 * are known there. Their squared sums over the keyframe's samples decay by
 * MID_GATE_DECAY a keyframe; the gain goes towards 1 where the candidate's
 * sum is at most MID_GATE_FULL of h's and 0 from MID_GATE_OPEN of it,
 * rising at most MID_GATE_RISE a keyframe and falling at once. So a
 * correction reaches the screen only after it was measured clearly better
 * than h on what was then shown (its RMS at most 84 % of h's to open at
 * all: a wrong correction costs more than a right one gains), and stops
 * when it is not. */
#define MID_GATE_DECAY 0.7f
#define MID_GATE_OPEN 0.7f
#define MID_GATE_FULL 0.4f
#define MID_GATE_RISE 0.5f
#define MID_GATE_EPS 0.01f /* JND^2 a sample: a keyframe without motion in depth leaves the gain shut */
#define MID_GATE_NONE 0xffffffffu /* no realized keyframe in the window: the gate starts shut */

/* The c_a residual of x along a sample's links (Sec. 4.3; the MID metric,
 * disp_metrics.c, and the causal gate): x and g at the sample, ahead (a)
 * and behind (b). */
VGX_FN float mid_accel_residual(float xa, float x, float xb, float ga, float g, float gb, float inv_dt_f,
                                float inv_dt_b)
{
    return (mid_p((xa - x) * inv_dt_f) - mid_p((x - xb) * inv_dt_b)) -
           (mid_p((ga - g) * inv_dt_f) - mid_p((g - gb) * inv_dt_b));
}

/* The gain for the keyframe published next, from the decayed sums (the
 * candidate's, h's) over `samples` samples and the gain published last. */
VGX_FN float mid_gate_gain(float sum_c, float sum_h, float samples, float gain_before)
{
    float eps = MID_GATE_EPS * samples;
    float q = (sum_c + eps) / (sum_h + eps);
    float t = (MID_GATE_OPEN - q) / (MID_GATE_OPEN - MID_GATE_FULL);
    t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    float rise = gain_before + MID_GATE_RISE;
    return t < rise ? t : rise;
}

/* ------------------------------------------------------------------------- */
/* GPU passes (docs/method.md "GPU passes")                                  */
/* ------------------------------------------------------------------------- */

/* Push constants of every mid_*.comp kernel (window build and solver; 128
 * bytes). The window is n = ns * nt elements; every array of the solver
 * arena is `cap` elements long (the largest window). */
VGX_STRUCT(mid_push) {
    uint nx, ny, nt, ns;
    uint n, cap, blocks, op;       /* blocks: chunks of MID_SUM_CHUNK over n; op: the kernel's operation */
    float w_data, w_spatial, w_temporal, w_accel;
    float grad_scale, scalar, log_tol, flow_tol; /* scalar: line-search step t or descent lambda */
    float range_lo, range_hi, dt;                /* dt: seconds between keyframes (gather) */
    uint nt_prev;                                /* keyframes of the previous window (warm start) */
    uint range_hull, jacobi, store_first, store_cap; /* store: ring slot of window keyframe 0 */
    uint publish_from, adj_cap, shift, warm;     /* first window keyframe to publish; warm start:
                                                    keyframe k takes the last solution's k + shift */
    uint gate, gate_k, pad0, pad1;               /* the causal gate applies to the publish; its
                                                    realized window keyframe (MID_GATE_NONE) */
};

/* Solver state on the GPU (mid_control.comp writes it; 96 bytes). The CPU
 * solver's scalars and branches (mid_solver.c) become these fields and the
 * dispatch sizes of the kernels that follow. */
VGX_STRUCT(mid_solve_state) {
    float c, c_try, decrease, pg2;     /* cost, trial cost, Armijo decrease, |projected gradient|^2 */
    float rz, rz0, rz_new, php;        /* CG scalars */
    float a_cg, b_cg, range_lo, range_hi;
    uint running, cg_running, accepted, iteration;
    uint cg_steps, line_trials, g_min_bits, g_max_bits; /* g range of the window (operator none) */
    float cost_initial, inv_range;
    uint heads;                        /* chain heads in MID_B_HEADS (window.heads) */
    float unused1;
};

/* Indirect dispatch sizes the control kernel writes (3 uints each): per
 * gate, the size of an element kernel, that of a chunk-sum kernel, then
 * that of a kernel over the chain heads (the line preconditioner's walks). */
#define MID_ARGS_ACTIVE 0u   /* the solve goes on */
#define MID_ARGS_CG 1u       /* ... and CG goes on */
#define MID_ARGS_LINE 2u     /* ... and the line search has not accepted a step */
#define MID_ARGS_COMMIT 3u   /* ... and it has */
#define MID_ARGS_GATES 4u
#define MID_ARGS_SIZES 3u    /* per gate: element, sum, chain heads */
#define MID_ARGS_COUNT 12u   /* gate g: element size at 3 g, sum size at 3 g + 1, heads at 3 g + 2 */

/* Bindings of the solver arena (set 0, one storage buffer range each; arrays
 * marked x2 hold the forward half then the backward half, each `cap` long). */
#define MID_B_STATE 0      /* mid_solve_state */
#define MID_B_ARGS 1       /* dispatch sizes (a separate buffer) */
#define MID_B_PARTIAL 2    /* 4 floats per workgroup */
#define MID_B_FIELD 3      /* g, h, depth (3 x cap) */
#define MID_B_FLOW 4       /* vec2 x2: to keyframe k+1, to k-1 (coarse px) */
#define MID_B_LINK 5       /* mid_link x2: A_f, A_b */
#define MID_B_ADJ_OFF 6    /* uint x2 (cap + 1 each): CSR rows of A_f^T, A_b^T */
#define MID_B_ADJ 7        /* mid_adj_entry x2 (adj_cap each) */
#define MID_B_CURSOR 8     /* uint x2: row counts, then fill cursors */
#define MID_B_EDGE 9       /* float x2: a^2 right, below */
#define MID_B_TARGET 10    /* float x2: ph, pg_acc */
#define MID_B_INVDT 11     /* float x2 (nt each): 1 / dt forward, backward */
#define MID_B_CHAIN 12     /* int x2: chain next, prev */
#define MID_B_HEAVY 13     /* int x2: heaviest forward tap, heaviest backward tap */
#define MID_B_SCAN 14      /* uint: block sums of the CSR scan */
#define MID_B_F 15
#define MID_B_FTRY 16
#define MID_B_GRAD 17
#define MID_B_DIAG 18
#define MID_B_S 19
#define MID_B_R 20
#define MID_B_Z 21
#define MID_B_P 22
#define MID_B_HP 23
#define MID_B_FREE 24
#define MID_B_L 25         /* l0, l1, l2 (3 x cap): line preconditioner factor */
#define MID_B_LIN 26       /* q_f, q_b, m_a, alpha, beta, c_f, c_b, d_self (8 x cap) */
#define MID_B_FPREV 27     /* the last solution (warm start, paper 4.5) */
#define MID_B_STORE 28     /* the keyframe store (a separate buffer) */
#define MID_B_PUBLISHED 29 /* published ratios f / h (a separate buffer) */
#define MID_B_DOT 30       /* per element terms of the sums (6 x cap): 4 cost terms, 2 of vector steps */
#define MID_B_HEADS 31     /* uint: the chains' heads, st.heads of them, in no particular order */
#define MID_B_COUNT 32     /* all pushed as one set: at most 32 (maxPushDescriptors' guaranteed minimum) */
#define MID_LIN_FIELDS 8u
#define MID_PARTIAL_FLOATS 8u  /* per chunk: 4 cost terms, 2 sums of a vector op */
#define MID_DOT_COLUMNS 6u
#define MID_MAX_KEYFRAMES 256u /* MID_B_INVDT holds 2 x this */
#define MID_SCAN_BLOCK 256u  /* counts per invocation of the CSR scan */

/* Operations of the kernels (mid_push.op). */
#define MID_OP_GATHER 0u       /* mid_window: window arrays from the keyframe store */
#define MID_OP_PREPARE 1u      /* mid_window: only clear the counts (inputs uploaded) */
#define MID_OP_LINKS 2u        /* mid_window: A_f, A_b rows and CSR counts */
#define MID_OP_FILL 3u         /* mid_window: CSR entries */
#define MID_OP_SORT 4u         /* mid_window: each CSR row by source index */
#define MID_OP_TARGETS 5u      /* mid_window: edge weights, targets, heaviest taps */
#define MID_OP_CHAINS 6u       /* mid_window: mutual heaviest taps */
#define MID_OP_HEADS 7u        /* mid_window: the list of chain heads */
#define MID_OP_SCAN_BLOCKS 10u /* mid_scan */
#define MID_OP_SCAN_TOP 11u
#define MID_OP_SCAN_ADD 12u
#define MID_OP_LIN_F 20u       /* mid_terms: linearise at f */
#define MID_OP_LIN_FTRY 21u    /* ... at the trial point */
#define MID_OP_GATHER_GRAD 22u
#define MID_OP_GATHER_HESS 23u
#define MID_OP_DIAGONAL 24u
#define MID_OP_DIRECTION 25u
#define MID_OP_CG_START 30u    /* mid_vec: element-wise steps of mid_solver.c */
#define MID_OP_ZP_INIT 31u
#define MID_OP_CG_UPDATE 32u
#define MID_OP_P_UPDATE 34u
#define MID_OP_TRIAL 35u
#define MID_OP_DESCENT 36u
#define MID_OP_COMMIT 37u
#define MID_OP_INIT 38u
#define MID_OP_PUBLISH 39u
#define MID_OP_ASSEMBLE 40u    /* mid_precond */
#define MID_OP_FACTOR 41u
#define MID_OP_APPLY 42u
#define MID_OP_APPLY_CG 43u    /* ... a CG step's r and s updates, the apply and r.z, in one walk */
#define MID_OP_GATE 44u        /* mid_publish: the causal gate's sums and gain (one workgroup) */
#define MID_OP_C_RESET 50u     /* mid_control: sums, then the solver's branches */
#define MID_OP_C_RANGE 51u
#define MID_OP_C_INIT_COST 52u
#define MID_OP_C_ITER_BEGIN 53u
#define MID_OP_C_PG2 54u
#define MID_OP_C_RZ0 55u
#define MID_OP_C_PHP 56u
#define MID_OP_C_RZNEW 57u
#define MID_OP_C_TRIAL 58u
#define MID_OP_C_ITER_END 59u
#define MID_OP_C_DESCENT 60u
#define MID_OP_SUM_COST 70u    /* mid_sum: chunks of the cost terms */
#define MID_OP_SUM_VEC 71u     /* ... of a vector step's two sums */
#define MID_OP_COUNT 72u

/* The keyframe store: a ring of keyframes, each ns coarse samples of
 * g, h, depth (arcmin, arcmin, m) and flows to the next and previous keyframe
 * (coarse px, x y interleaved): MID_STORE_FLOATS x ns floats per slot. */
#define MID_STORE_G 0u
#define MID_STORE_H 1u
#define MID_STORE_DEPTH 2u
#define MID_STORE_FLOW_F 3u  /* 2 floats per sample */
#define MID_STORE_FLOW_B 5u  /* 2 floats per sample */
#define MID_STORE_ID 7u      /* instance id (0: sky), as a float (exact below 2^24) */
#define MID_STORE_FLOATS 8u
/* Published solution: a header, then three planes of ring slots of ns
 * floats: the correction the upsampling reads (f as shown), its slope in
 * time, and the solve's own ratio f / h before the gate, which the gate
 * measures. The correction is m = f / g (docs/method.md Sec. 8); under the
 * causal gate (of_h) it is f / h, so that a closed gate shows h at every
 * frame, not only at keyframes. */
VGX_STRUCT(mid_published) {
    float range_lo, range_hi; /* the range f was solved in (the clamp of upsampling) */
    uint keyframe_lo, keyframe_hi; /* keyframes published so far (absolute, inclusive) */
    float gate_c, gate_h, gate_gain; /* the causal gate's sums and gain (MID_GATE_*) */
    uint of_h; /* 1: the first two planes hold f / h and its slope (causal gate), 0: f / g */
};

/* Operator passes (disparity_operator_*.comp): push constants (96 bytes). */
VGX_STRUCT(disp_op_push) {
    uint kind, bins, stride, fixed_domain; /* stride: statistics from every stride-th pixel */
    float screen_vergence, range_lo, range_hi, floor_slope;
    float blur_bins, saliency_floor, smooth_alpha, dom_lo; /* smooth_alpha: per call (frame) */
    float dom_hi, key_alpha;                               /* key_alpha: per keyframe interval */
    uint prev, keys;                                       /* the entry a frame fit blends with; keyframes' ring */
    uint width, height, tiles, tile_height;                /* frame size; keyframe tiles in the atlas */
    uint store_first, store_cap, entry, flags;             /* ring slot of tile 0; state entry; DISP_OP_FLAG_* */
};
#define DISP_OP_FLAG_NO_SALIENCY 1u /* every pixel weighs 1 */
#define DISP_OP_FLAG_RESET 2u       /* forget the temporal state (lang-smoothed) */
#define DISP_OP_FLAG_KEY_RING 4u    /* keyframe fits also go to the keyframes' ring */
#define DISP_OP_FLAG_CHAIN_FROM 8u  /* keyframe fits: the chain restarts from entry `prev` (a ring slot) */
/* State entries: the frame's mapping, the keyframes' running mapping, one
 * per keyframe tile rendered this frame, then a ring of each keyframe's
 * running mapping (the store's slots: a frame blends with its keyframe's). */
#define DISP_OP_ENTRY_FRAME 0u
#define DISP_OP_ENTRY_CHAIN 1u
#define DISP_OP_ENTRY_TILE0 2u
/* One mapping: its header, then DISP_OP_MAX_BINS + 1 knots (normalised
 * cumulative mapping in [0, 1]); DISP_OP_STATE_FLOATS floats per entry. */
VGX_STRUCT(disp_op_state) {
    float dom_lo, dom_hi, out_lo, out_hi;
    float scale, has_prev, lo, hi; /* lo, hi: target range */
};
#define DISP_OP_STATE_FLOATS 272u

/* Upsampling passes (mid_upsample_*.comp): push constants (64 bytes). */
VGX_STRUCT(disp_upsample_push) {
    uint full_w, full_h, stride, nx;
    uint ny, slot0, slot1, has1;  /* ring slots of the keyframes before (k0) and after (k1) */
    float tau, log_tol, inv_2ss, inv_2sr;
    uint at_key, store_cap;       /* at_key: frame t is keyframe k0 (tau = 0); store_cap: ring slots */
    float span;                   /* seconds from k0 to k1 */
    uint depth_only;              /* 1: the occlusion test in time by depth alone (no ids, no trajectory) */
};

#ifndef GL_core_profile
/* The std430 layouts the GLSL side assumes. */
#include <stddef.h>
_Static_assert(sizeof(mid_params) == 48 && offsetof(mid_params, w_data) == 16 &&
                   offsetof(mid_params, range_lo) == 32, "mid_params layout");
_Static_assert(sizeof(mid_link) == 16 && offsetof(mid_link, mask) == 12, "mid_link layout");
_Static_assert(sizeof(mid_adj_entry) == 8, "mid_adj_entry layout");
_Static_assert(sizeof(mid_push) == 128 && offsetof(mid_push, w_data) == 32 &&
                   offsetof(mid_push, publish_from) == 96, "mid_push layout");
_Static_assert(sizeof(mid_solve_state) == 96 && offsetof(mid_solve_state, running) == 48,
               "mid_solve_state layout");
_Static_assert(sizeof(mid_published) == 32, "mid_published layout");
_Static_assert(sizeof(disp_op_push) == 96 && offsetof(disp_op_push, width) == 64, "disp_op_push layout");
_Static_assert(sizeof(disp_op_state) == 32 && DISP_OP_STATE_FLOATS >= 8 + DISP_OP_MAX_BINS + 1,
               "disp_op_state layout");
_Static_assert(sizeof(disp_upsample_push) == 64, "disp_upsample_push layout");
#endif

#endif /* VG_MID_SHARED_H */
