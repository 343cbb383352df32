/* vergence — the probe: how a frame shows a few instances in depth (the
 * game's ball), measured on the GPU each frame it is asked for: the number
 * of their pixels and the mean of (shown map - g) over them. The shown map
 * is the one the warp renders (g, h or f by the frame's mode), so the
 * original mode measures exactly 0. One partial sum per 16 x 16 workgroup
 * lands in this slot's host-visible buffer; the host adds them once the
 * slot's frame has completed. */
#pragma once
#include "pass/frame_ctx.h"

typedef struct probe_gpu probe_gpu;

/* ids: the probed instances, 0-terminated. */
vg_status probe_gpu_create(frame_ctx *fc, const uint32_t ids[FRAME_PROBE_MAX_IDS], probe_gpu **out);
void probe_gpu_destroy(probe_gpu *p);
/* The pass: reads res->ids, res->g and `shown`. */
void probe_gpu_add(probe_gpu *p, rg_graph *g, const frame_resources *res, rg_res shown);
/* This slot's partials buffer, before the graph executes. */
void probe_gpu_bind(probe_gpu *p, rg_graph *g);
/* The partials of the frame `index` completed in `slot`, added. */
frame_probe probe_gpu_read(const probe_gpu *p, int slot, long index);
