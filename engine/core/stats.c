/* vergence — small statistics over samples. */
#include "stats.h"

#include <math.h>
#include <stdlib.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double vg_median(const double *v, size_t n, size_t stride)
{
    double *t = malloc(sizeof(double) * (n ? n : 1));
    if (!t)
        return NAN;
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        if (isfinite(v[i * stride]))
            t[k++] = v[i * stride];
    double m = NAN;
    if (k) {
        qsort(t, k, sizeof *t, cmp_double);
        m = k % 2 ? t[k / 2] : 0.5 * (t[k / 2 - 1] + t[k / 2]);
    }
    free(t);
    return m;
}
