/* vergence — a small pthread pool with a deterministic parallel-for.
 *
 * Work is cut into fixed blocks whose boundaries depend only on the element
 * count and the block size, never on the number of threads. A kernel that
 * writes each output element from reads of its inputs (a gather) and keeps
 * one partial sum per block gives bit-identical results with 1 or N threads:
 * the caller adds the per-block partials in block order. This is the contract
 * the GPU passes follow too (one workgroup per block, a fixed reduction tree).
 *
 * A NULL pool runs everything on the calling thread. A pool runs one job at a
 * time and is not re-entrant (a kernel must not call vg_parallel_for). */
#pragma once
#include "status.h"

typedef struct vg_pool vg_pool;

typedef struct vg_pool_desc {
    int threads; /* worker threads including the caller; 0 = all online cores */
} vg_pool_desc;

vg_status vg_pool_create(const vg_pool_desc *desc, vg_pool **out);
/* NULL-safe; joins the workers. */
void vg_pool_destroy(vg_pool *pool);
/* Threads that run a job (1 for a NULL pool). */
int vg_pool_threads(const vg_pool *pool);
/* Online cores of this machine (at least 1). */
int vg_cpu_count(void);

/* fn(ctx, block, begin, end) for every block of [0, count): block b covers
 * [b * block_size, min((b + 1) * block_size, count)). Returns after all ran. */
typedef void (*vg_block_fn)(void *ctx, int block, int begin, int end);
void vg_parallel_for(vg_pool *pool, int count, int block_size, vg_block_fn fn, void *ctx);

/* Number of blocks vg_parallel_for makes for count elements. */
static inline int vg_block_count(int count, int block_size)
{
    return count <= 0 ? 0 : (count + block_size - 1) / block_size;
}

/* Adds partial[0..n) in order, in double: the fixed-order end of a reduction. */
double vg_sum_ordered(const double *partial, int n);
