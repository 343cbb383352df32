/* vergence — the disparity passes of the frame on the GPU (DESIGN.md steps
 * 3-7), beside their CPU reference in this folder:
 *
 *   disparity.original      g from the G-buffer's linear depth (stereo rig + display)
 *   disparity.operator.fit  the operator's mapping from the frame's coarse samples
 *   disparity.operator      h = M(g, saliency) per pixel
 *   (mid.keyframes)         the keyframe entering the window, rendered by the
 *                           caller at coarse resolution at its (future) time
 *   mid.keyframes.fit/store its own mapping; g, h, depth, flows into the store
 *   mid.window              when the window moves: links, CSR, targets, chains
 *   mid.solve               this frame's share of the window's solve (warm start,
 *                           amortised over the keyframe interval), then publish
 *   mid.upsample.time/space f for this frame from the published keyframe ratios
 *
 * Reads res->depth, color (saliency), motion, ids and the keyframes the
 * caller renders into an atlas (keyframe_gpu in the frame, the host through
 * the SDK); fills res->g, h, f (R32F, arcmin). The window (paper 4.5: "previous frames combined with a prediction of future
 * frames") holds keyframes from history and predicted ones; docs/method.md
 * "GPU passes" has the timeline. */
#pragma once
#include "disparity/disp_operator.h"
#include "disparity/mid_solver.h"
#include "pass/frame_ctx.h"

typedef struct disparity_gpu disparity_gpu;

/* What the pipeline is made for; a zero field is its default
 * (disparity_gpu_desc_defaults, which the frame and the SDK resolve through
 * too). */
typedef struct disparity_gpu_desc {
    gpu *gpu;
    uint32_t width, height;      /* the frame */
    double fps;
    int keyframe_stride;         /* frames between keyframes */
    int coarse_stride;           /* the solver's grid (disparity_gpu_grid_stride widens it) */
    double window_seconds, window_future;
    disp_operator_kind op;
    disp_operator_preset op_preset;
    double target_range;         /* arcmin, 0 = the preset's */
    double screen_vergence;      /* the display's, arcmin */
    bool no_saliency;            /* every pixel weighs 1 in the operator (no saliency input) */
    mid_solver_kind solver;
    int solver_iterations;
    bool causal;                 /* every future keyframe is given again at each window move */
    bool temporal_depth_only;
    bool keyframes;              /* the caller renders the window's keyframes (disparity_gpu_keyframes) */
    bool f;                      /* steps 6 and 7 (needs keyframes): the window, the solve and f */
    bool readback;               /* the store and the published ratios host-visible (keyframe_read) */
    bool budgeted;               /* a constant share of the solve a rendered frame (a keyframe interval's
                                    work over its frames), not the share of the frames it skipped too;
                                    a window moves on with its solve settled, not finished (prepare) */
} disparity_gpu_desc;

/* The keyframes the frame renders into the atlas (docs/method.md "GPU
 * passes"): max_tiles tiles of nx x ny stacked vertically, in time order;
 * tile m holds keyframe first + m at its time (a future one: a prediction).
 * Colour (RGBA8, saliency in alpha), linear depth (R32F), instance ids
 * (R32UI) and motion to the neighbouring keyframes (RGBA32F, atlas pixels),
 * each a point sample of the full frame (keyframe_gpu's atlas matrix). */
typedef struct disparity_gpu_atlas {
    rg_res color, depth, ids, motion;
} disparity_gpu_atlas;

/* desc with every zero field at its default: 60 Hz, a keyframe every
 * MID_KEYFRAME_STRIDE frames, the MID_* window and grid, the operator's
 * default kind (disp_operator_desc_defaults), Gauss-Newton. */
disparity_gpu_desc disparity_gpu_desc_defaults(const disparity_gpu_desc *desc);
vg_status disparity_gpu_create(const disparity_gpu_desc *desc, disparity_gpu **out);
void disparity_gpu_destroy(disparity_gpu *d);
/* Reads res->ubo (rig, display), depth, color (saliency), motion, ids and
 * (desc.keyframes) the atlas; writes res->g, h and (desc.f) f: made here as
 * transient images unless the caller set them (imported). */
void disparity_gpu_add(disparity_gpu *d, rg_graph *g, frame_resources *res, const disparity_gpu_atlas *atlas);
/* Binds the pass's persistent buffers to the graph it was added to (prepare
 * does it each frame; again after the caller compiled a new graph). */
void disparity_gpu_bind(disparity_gpu *d, rg_graph *g);
/* Per-frame CPU work before frame `index` is recorded into frame-in-flight
 * `slot`: which keyframes to render, which part of the solve runs, where
 * the frame is between its keyframes.
 *
 * Any sequence of frame indices gives the f of rendering every index: the
 * solve's work due in frames that were skipped runs in the next one that is
 * rendered (a window moves on only once its solve is finished), an index
 * rendered again records nothing, and an index before the last one or past
 * the window starts the window afresh (docs/method.md "GPU passes"). With
 * desc.budgeted, a frame runs one frame's share whatever it skipped, and a
 * window that moves on settles its solve (the iteration under way and at
 * least MID_GN_BUDGET_ITERATIONS done) and publishes it (paper 4.5: a
 * constant number of iterations a frame): f then depends on how many
 * frames were rendered, not only on their indices. */
vg_status disparity_gpu_prepare(disparity_gpu *d, long index, int slot);
/* After prepare: the keyframes this frame renders into the atlas (count 0: none). */
void disparity_gpu_keyframes(const disparity_gpu *d, long *first, int *count);
/* Clip space of the full frame to the atlas's tile `tile` (column-major,
 * clip' = m clip): the centre of coarse pixel q lands where full-resolution
 * sample q s + s/2 has its centre (disp_grid), so a coarse keyframe is a
 * point sample of the frame it predicts. */
void disparity_gpu_atlas_matrix(const disparity_gpu *d, int tile, float m[16]);
/* The scene's future changed (the game threw a new ball): the predicted
 * keyframes are stale, so the next frame starts the window afresh. */
void disparity_gpu_restart(disparity_gpu *d);

/* The stride of the solver's grid for a frame size: coarse_stride (0 = 5),
 * widened until the grid is at most 192 x 108 (paper 4.5: the solve's
 * resolution is chosen by content, so its time does not grow with the
 * output's). */
uint32_t disparity_gpu_grid_stride(uint32_t width, uint32_t height, int coarse_stride);

/* The solver's grid and window, as resolved (for reports). */
typedef struct disparity_gpu_info {
    uint32_t stride, nx, ny;      /* coarse grid */
    int past, future;             /* keyframes of the window behind and ahead of the frame */
    uint32_t max_tiles;           /* keyframes rendered in one frame at most: the atlas's tiles */
    double range_lo, range_hi;    /* target range, arcmin */
    int items;                    /* steps of the current window's solve */
} disparity_gpu_info;
void disparity_gpu_get_info(const disparity_gpu *d, disparity_gpu_info *info);

/* Keyframe `keyframe`'s coarse samples as the solve sees them (frames with
 * readback only, after the frame was rendered): the store's g, h, depth,
 * instance ids and flows to the neighbouring keyframes (coarse pixels), and
 * f = h x the ratio the solve published for it (what the upsampling shows at
 * that keyframe). VG_ERR_ARG when the keyframe has left the store or its
 * ratio is not final yet: keyframe K is final from the first frame rendered
 * in interval K - 1 (causal look-ahead: interval K, when its samples stop
 * being a prediction) until keyframe K + ring enters the store. */
typedef struct disparity_gpu_keyframe {
    int ns;                                  /* samples (nx x ny of the info) */
    float *g, *h, *f, *depth, *id;           /* ns floats each */
    float *flow_fwd, *flow_bwd;              /* 2 ns floats each */
} disparity_gpu_keyframe;
/* Fills *out (allocated on first use, reused after; zero it before the first call). */
vg_status disparity_gpu_keyframe_read(const disparity_gpu *d, long keyframe, disparity_gpu_keyframe *out);
void disparity_gpu_keyframe_free(disparity_gpu_keyframe *k);
