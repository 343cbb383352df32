/* vergence — small statistics over samples: the one median of the project
 * (benchmarks, reports, capture.json). */
#pragma once
#include <stddef.h>

/* The median of the finite values among v[0], v[stride], ..., v[(n-1) stride]
 * (the mean of the middle two for an even count); NAN when there is none. */
double vg_median(const double *v, size_t n, size_t stride);
/* The q-quantile (0..1) of the finite values, nearest rank: q = 1 is the
 * largest; NAN when there is none. */
double vg_quantile(const double *v, size_t n, size_t stride, double q);
