/* vergence — the space-time window of the MID optimiser (paper Sec. 4.3-4.5).
 *
 * n_t keyframes of an n_x x n_y coarse grid. The caller fills the inputs
 * (g, h, depth, flows, dt), then mid_window_build derives what every solver
 * iteration reads: the flow links A_f / A_b with their occlusion masks, their
 * transposes as CSR gathers, the edge weights of c_s, and the targets of c_t
 * and c_a. Build again whenever an input changes. */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "core/parallel.h"
#include "core/status.h"
#include "mid_shared.h"

typedef struct mid_window_desc {
    int width, height, keyframes;   /* n_x, n_y, n_t */
    float range_lo, range_hi;       /* target vergence range, arcmin (required) */
    float occlusion_tolerance;      /* relative depth difference, 0 = MID_OCCLUSION_TOLERANCE */
    float flow_tolerance;           /* round-trip flow error, coarse px, 0 = MID_FLOW_TOLERANCE */
    float keyframe_seconds;         /* initial dt of every interval, 0 = MID_KEYFRAME_SECONDS */
    /* Choices the paper leaves open, kept selectable for the sensitivity
     * study (docs/method.md section 16); zero = the defaults. */
    float edge_scale;               /* a = exp(-10 |dh| edge_scale): 0 = 1 / the target range's width (h
                                       normalised, Sec. 4.1); 1: dh in arcmin per coarse sample */
    float time_unit;                /* seconds per unit of the velocities p() sees: 0 = 1 s */
} mid_window_desc;

/* Transposed links: entries [offset[j], offset[j + 1]) are the sources reading j. */
typedef struct mid_adjoint {
    uint32_t *offset; /* n + 1 */
    mid_adj_entry *entry;
    uint32_t count;
} mid_adjoint;

typedef struct mid_window {
    int nx, ny, nt, ns, n;
    float range_lo, range_hi, occlusion_tolerance, flow_tolerance;
    float edge_scale, time_unit;    /* as the desc's, resolved */

    /* Inputs: n floats each, index k * ns + y * nx + x. */
    float *g, *h;       /* vergence, arcmin: original and manipulated */
    float *depth;       /* metres (any positive unit: only ratios are used) */
    float *id;          /* instance id of the surface (0: sky), exact below 2^24; all 0 (the
                           default) when unknown, as for sequences from files */
    uint8_t *unknown;   /* 1 where g is unknown (a dataset's inf or 0): no links, no edges, left out of
                           the metrics; all 0 (the default) for the engine's frames */
    float *flow_fwd;    /* 2n: (dx, dy) in coarse pixels to keyframe k+1 */
    float *flow_bwd;    /* 2n: (dx, dy) in coarse pixels to keyframe k-1 */
    float *dt;          /* nt - 1: seconds from keyframe k to k+1 */

    /* Derived by mid_window_build. */
    mid_link *fwd, *bwd;
    mid_adjoint fwd_adj, bwd_adj;
    float *edge_x, *edge_y; /* a^2 of the edge to the right / below (0 on the border) */
    float *ph;              /* p(v+_h), target of c_t */
    float *pg_acc;          /* p(v+_g) - p(v-_g), target of c_a */
    float *inv_dt_f;        /* nt: 1 / dt to the next keyframe (0 for the last) */
    float *inv_dt_b;        /* nt: 1 / dt to the previous keyframe (0 for the first) */
    /* Flow trajectories for the line preconditioner: i -> next[i] when i's
     * heaviest forward tap is next[i] and next[i]'s heaviest backward tap is i
     * (disjoint chains; a static pixel's chain is its column through time). */
    int32_t *chain_next, *chain_prev; /* -1 at the ends */
    int32_t *chain_head;              /* first node of every chain, ascending */
    int chain_count;
    /* Nodes of each group of MID_CHAIN_GROUP chains (consecutive heads),
     * keyframe by keyframe: a sweep over a group's list meets every node
     * after its chain predecessors, so groups run in parallel. */
    int32_t *chain_order;             /* n */
    int32_t *chain_group;             /* groups + 1 offsets into chain_order */
    int chain_groups;
    bool built;
} mid_window;

/* The sliding window's length (paper 4.2: "several seconds") and its share
 * ahead of the frame, by default. */
#define MID_WINDOW_SECONDS 3.0
#define MID_WINDOW_FUTURE 0.5
/* Keyframes of a sliding window of `seconds` behind and ahead of the frame's
 * keyframe: `future_share` of them ahead, at least 2 (the solve runs one
 * interval ahead: docs/method.md "GPU passes"). */
void mid_window_split(double seconds, double keyframe_seconds, double future_share, int *past, int *future);

vg_status mid_window_create(const mid_window_desc *desc, mid_window **out);
void mid_window_destroy(mid_window *w);
/* Derives links, adjoints, edge weights and targets from the inputs. */
vg_status mid_window_build(mid_window *w, vg_pool *pool);

/* The mid_params block of a solve with these weights. */
mid_params mid_window_params(const mid_window *w, float w_data, float w_spatial, float w_temporal,
                             float w_accel);

/* Warm start for a window that slid by `shift` keyframes: keyframe k of out
 * takes keyframe k + shift of prev where it exists, h elsewhere (Sec. 4.5). */
void mid_window_warm_start(const mid_window *w, const float *prev, int shift, float *out);

/* Slopes in time (per second) of a ratio (the correction m = f / g) at
 * every sample, along the links (mid_ratio_slope): what the upsampling in
 * time interpolates with (mid_hermite). The GPU's mid.solve publishes the
 * same. */
void mid_window_ratio_slopes(const mid_window *w, const float *ratio, float *slope);

/* Values of the links at pixel i: (A x)_i for a link array. */
static inline float mid_link_gather(const mid_link *links, int nx, int i, const float *x)
{
    mid_link l = links[i];
    if (!l.mask)
        return 0.0f;
    mid_taps t = mid_link_taps(l);
    uint b = l.base;
    /* Taps outside the mask have weight 0 and a clamped, valid index. */
    return mid_link_apply(t, x[b], x[b + 1], x[b + (uint)nx], x[b + (uint)nx + 1]);
}
