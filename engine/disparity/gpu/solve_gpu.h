/* vergence — the keyframe window and its solve on the GPU (DESIGN.md steps
 * 5-6, paper 4.3-4.5): mid_window_build() and mid_solver_run() of the CPU
 * reference as compute kernels over one buffer, the solver arena.
 *
 * The Gauss-Newton solve is hundreds of dependent dispatches, with branches
 * that depend on data (CG stops, the line search accepts). Each kind of step
 * is a small frame graph of its own (one dispatch per pass, so the graph
 * derives every barrier), recorded into the caller's command buffer as many
 * times as the program says; the branches run on the GPU (mid_control.comp)
 * as indirect dispatch sizes, so no readback is ever needed.
 *
 * A solve is a program: build, init, iterations, publish. Its items can be
 * recorded all at once (tests, the first frame) or spread over the frames of
 * a keyframe interval (the frame: paper 4.5's real-time solver, amortised).
 * Equations: docs/method.md "GPU passes". */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "gpu/gpu.h"
#include "graph/graph.h"
#include "disparity/mid_solver.h"

typedef struct solve_gpu_desc {
    int nx, ny;            /* coarse grid */
    int max_keyframes;     /* capacity of a window (at most MID_MAX_KEYFRAMES) */
    bool host_visible;     /* arena in host-visible memory (tests read and write it) */
    VkBuffer store;        /* keyframe store ring (mid.window's gather); may be null */
    VkBuffer published;    /* published ratios (the publish step); may be null */
    VkDeviceSize store_size, published_size;
} solve_gpu_desc;

/* One solve. Zero = defaults (the CPU reference's: Gauss-Newton 4 x 8, lines). */
typedef struct solve_gpu_params {
    int keyframes;                  /* n_t of this window */
    float range_lo, range_hi;       /* target range, arcmin */
    bool range_hull;                /* widen the range to hold g (operator none) */
    float occlusion_tolerance;      /* 0 = MID_OCCLUSION_TOLERANCE */
    float flow_tolerance;           /* 0 = MID_FLOW_TOLERANCE */
    bool gather;                    /* window inputs from the store; false: already in the arena */
    float keyframe_seconds;         /* dt of the gathered window */
    uint32_t store_first, store_cap;/* ring slot of window keyframe 0, ring size */
    mid_solver_kind solver;
    mid_precond_kind precond;
    int iterations, cg_steps;       /* 0 = MID_GN_ITERATIONS / MID_DESCENT_ITERATIONS, MID_GN_CG_STEPS */
    float step;                     /* descent lambda, 0 = MID_DESCENT_STEP */
    mid_weights weights;            /* all zero = the paper's */
    bool warm;                      /* start from the last solution (paper 4.5) */
    int shift;                      /* ... whose keyframe k + shift is this window's k */
    int prev_keyframes;             /* n_t of the last solution */
    bool publish;                   /* end with the publish step */
    int publish_from;               /* first window keyframe whose ratio is published */
    bool gate;                      /* the causal gate (mid_shared.h MID_GATE_*) scales what is published */
    int gate_keyframe;              /* ... measured at this realized window keyframe (-1: none, the gate shuts) */
} solve_gpu_params;

typedef struct solve_gpu solve_gpu;

vg_status solve_gpu_create(gpu *g, const solve_gpu_desc *desc, solve_gpu **out);
void solve_gpu_destroy(solve_gpu *m);

/* Starts a program for one window (no GPU work). The program it replaces
 * stays recordable as the previous one: a frame that skipped the frames its
 * last items were due in records them before the new window's build. */
void solve_gpu_begin(solve_gpu *m, const solve_gpu_params *solve);
/* The first item at or after `from` of the previous program where its
 * solution is settled: its start (f0) made, at least `iterations` outer
 * iterations done and none under way, so its publish step may run next (a
 * budgeted solve stopped early). */
int solve_gpu_previous_settled(const solve_gpu *m, int from, int iterations);
/* Items of the current (previous) program and their estimated cost (element traversals). */
int solve_gpu_item_count(const solve_gpu *m);
int solve_gpu_previous_item_count(const solve_gpu *m);
double solve_gpu_item_cost(const solve_gpu *m, int item);
/* Records items [first, last) of the current (previous) program into cmd
 * (outside any render pass); slot picks the timestamp queries of the frame
 * in flight. */
void solve_gpu_record(solve_gpu *m, VkCommandBuffer cmd, uint32_t slot, int first, int last);
void solve_gpu_record_previous(solve_gpu *m, VkCommandBuffer cmd, uint32_t slot, int first, int last);

/* The arena and the dispatch-size buffer, for the frame graph's declarations. */
VkBuffer solve_gpu_arena(const solve_gpu *m);
VkDeviceSize solve_gpu_arena_size(const solve_gpu *m);
VkBuffer solve_gpu_args(const solve_gpu *m);
/* Host pointer to an array of the arena (MID_B_*), host_visible arenas only;
 * its byte size in *bytes. */
void *solve_gpu_host(const solve_gpu *m, int binding, VkDeviceSize *bytes);
/* Element capacity (array stride) and CSR entries per direction. */
uint32_t solve_gpu_capacity(const solve_gpu *m);
uint32_t solve_gpu_adj_capacity(const solve_gpu *m);

/* The step graphs, for the documentation's dumps. */
void solve_gpu_dump(const solve_gpu *m, FILE *out);
