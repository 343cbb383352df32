/* vergence — memory bandwidth of this machine, for the benchmarks' "% of
 * bandwidth" figures: the STREAM triad (McCalpin), a[i] = b[i] + s c[i] over
 * three 64 MB arrays, far larger than the caches. */
#pragma once
#include "parallel.h"

/* GB/s (1e9 bytes: 3 arrays x 4 bytes per element per run), median of
 * `runs` runs after a warm-up, on the pool's threads; NaN when the arrays
 * cannot be allocated. */
double vg_stream_triad_gbs(vg_pool *pool, int runs);
