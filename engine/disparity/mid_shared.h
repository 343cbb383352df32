/* vergence — constants, buffer layouts and per-element formulas of the
 * motion-in-depth (MID) optimiser, shared by the C reference and the GLSL
 * compute passes (paper Sec. 4.1-4.5; units in DESIGN.md; equations in
 * docs/method.md).
 *
 * Written in the subset of C17 and GLSL 4.50 that both accept:
 *   - structs of scalar float/uint members only, sizes a multiple of 16 bytes,
 *     so std430 and C agree on every offset (no vec3, no bool, no arrays);
 *   - float literals with an f suffix, uint literals with a u suffix;
 *   - casts through MID_UINT()/MID_FLOAT(), maths through mid_log/mid_exp/mid_abs;
 *   - functions marked MID_FN, taking and returning values (no pointers, no out).
 * The C side includes it from mid_*.c; GLSL includes it with
 * GL_GOOGLE_include_directive. Every field is float32; only reductions
 * (cost, dot products) are accumulated in double on the CPU. */
#ifndef VG_MID_SHARED_H
#define VG_MID_SHARED_H

#if defined(__STDC__) || defined(__cplusplus)
#include <math.h>
typedef unsigned int uint;
#define MID_FN static inline
#define MID_UINT(x) ((uint)(x))
#define MID_FLOAT(x) ((float)(x))
#define mid_log logf
#define mid_exp expf
#define mid_abs fabsf
#define mid_floor floorf
#else /* GLSL */
#define MID_FN
#define MID_UINT(x) uint(x)
#define MID_FLOAT(x) float(x)
#define mid_log log
#define mid_exp exp
#define mid_abs abs
#define mid_floor floor
#endif

/* ------------------------------------------------------------------------- */
/* Constants                                                                 */
/* ------------------------------------------------------------------------- */

/* Weber fraction of disparity-velocity discrimination (paper Sec. 4.2), and
 * its inverse (exact in float: the kernels multiply instead of divide). */
#define MID_WEBER_K 0.08f
#define MID_INV_WEBER_K 12.5f
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
/* Workgroup size of the GLSL passes. */
#define MID_LOCAL_SIZE 256

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
struct mid_params {
    uint nx, ny, nt, ns;
    float w_data, w_spatial, w_temporal, w_accel;
    float range_lo, range_hi, grad_scale, inv_n; /* grad_scale = 2 / n */
};

/* A_f or A_b row i (Sec. 4.3): bilinear interpolation of the neighbouring
 * keyframe at the flow target, restricted to the taps of the same surface
 * (mask) and renormalised. 16 bytes. */
struct mid_link {
    uint base; /* index of the top-left tap in the neighbouring keyframe */
    float fx;  /* bilinear fractions in [0,1] */
    float fy;
    uint mask; /* MID_TAP* bits of the taps that passed the depth test; 0 = invalid */
};

/* One entry of the transposed link matrix (A_f^T or A_b^T) in CSR form:
 * row j lists the source pixels i whose links read j, sorted by i, so that
 * the adjoint is a gather summed in a fixed order. 8 bytes. */
struct mid_adj_entry {
    uint src;
    float w;
};

/* Normalised tap weights of a link. */
struct mid_taps {
    float w00, w10, w01, w11;
};

#if defined(__STDC__) || defined(__cplusplus)
typedef struct mid_params mid_params;
typedef struct mid_link mid_link;
typedef struct mid_adj_entry mid_adj_entry;
typedef struct mid_taps mid_taps;
#endif

/* ------------------------------------------------------------------------- */
/* Per-element formulas                                                      */
/* ------------------------------------------------------------------------- */

/* p(v) = sign(v) ln(1 + |v|) / k (Sec. 4.2, symmetric form of DESIGN.md). */
MID_FN float mid_p(float v)
{
    float s = v < 0.0f ? -MID_INV_WEBER_K : MID_INV_WEBER_K;
    return s * mid_log(1.0f + mid_abs(v));
}

/* dp/dv = 1 / (k (1 + |v|)). */
MID_FN float mid_dp(float v)
{
    return MID_INV_WEBER_K / (1.0f + mid_abs(v));
}

/* Edge weight a of Sec. 4.1 for a difference of h normalised to the range. */
MID_FN float mid_edge_weight(float dh_normalised)
{
    return mid_exp(-MID_EDGE_SHARPNESS * mid_abs(dh_normalised));
}

MID_FN mid_taps mid_link_taps(mid_link l)
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
MID_FN float mid_link_apply(mid_taps t, float x00, float x10, float x01, float x11)
{
    return t.w00 * x00 + t.w10 * x10 + t.w01 * x01 + t.w11 * x11;
}

/* Residuals of c_t and c_a at one pixel (Sec. 4.3), and their slopes.
 * fa = (A_f f)_i, fb = (A_b f)_i; inv_dt_f/b are 1/seconds to the next and
 * previous keyframe, or 0 where the link is invalid (which zeroes the terms). */
struct mid_pixel {
    float r_t;  /* p(v+_f) - p(v+_h)                     (times m_f) */
    float r_a;  /* p(v+_f) - p(v-_f) - (p(v+_g) - p(v-_g)) (times m_f m_b) */
    float q_f;  /* d r / d (A_f f - f) = p'(v+) / dt        (times m_f) */
    float q_b;  /* d p(v-) / d (f - A_b f) = p'(v-) / dt    (times m_b) */
};
#if defined(__STDC__) || defined(__cplusplus)
typedef struct mid_pixel mid_pixel;
#endif

MID_FN mid_pixel mid_pixel_eval(float f, float fa, float fb, float inv_dt_f, float inv_dt_b,
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
/* Global depth -> disparity curve (Sec. 4.6)                                */
/* ------------------------------------------------------------------------- */

/* Bins of the curve, uniform in inverse depth (where vergence is nearly linear). */
#define DISP_CURVE_BINS 256

/* Header of the curve buffer (std430, 16 bytes), followed by DISP_CURVE_BINS
 * floats: the disparity (arcmin) at each bin centre. */
struct disp_curve_header {
    float inv_depth_lo; /* 1 / farthest depth */
    float inv_depth_hi; /* 1 / nearest depth */
    uint bins;
    uint populated;     /* bins that held at least one pair */
};
#if defined(__STDC__) || defined(__cplusplus)
typedef struct disp_curve_header disp_curve_header;
#endif

/* Continuous bin coordinate of a depth: bin centres at 0 .. bins-1. */
MID_FN float disp_curve_coord(float depth, float inv_lo, float inv_hi, uint bins)
{
    float u = (1.0f / depth - inv_lo) / (inv_hi - inv_lo);
    return u * MID_FLOAT(bins) - 0.5f;
}

#if defined(__STDC__) || defined(__cplusplus)
/* The std430 layouts the GLSL side assumes. */
#include <stddef.h>
_Static_assert(sizeof(mid_params) == 48 && offsetof(mid_params, w_data) == 16 &&
                   offsetof(mid_params, range_lo) == 32, "mid_params layout");
_Static_assert(sizeof(mid_link) == 16 && offsetof(mid_link, mask) == 12, "mid_link layout");
_Static_assert(sizeof(mid_adj_entry) == 8, "mid_adj_entry layout");
_Static_assert(sizeof(disp_curve_header) == 16, "disp_curve_header layout");
#endif

#endif /* VG_MID_SHARED_H */
