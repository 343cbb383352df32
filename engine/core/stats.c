/* vergence — small statistics over samples. */
#include "stats.h"

#include <math.h>
#include <stdlib.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The finite values, sorted (*k of them); NULL when out of memory. */
static double *sorted_finite(const double *v, size_t n, size_t stride, size_t *k)
{
    double *t = malloc(sizeof(double) * (n ? n : 1));
    *k = 0;
    if (!t)
        return NULL;
    for (size_t i = 0; i < n; i++)
        if (isfinite(v[i * stride]))
            t[(*k)++] = v[i * stride];
    qsort(t, *k, sizeof *t, cmp_double);
    return t;
}

double vg_median(const double *v, size_t n, size_t stride)
{
    size_t k;
    double *t = sorted_finite(v, n, stride, &k);
    double m = t && k ? (k % 2 ? t[k / 2] : 0.5 * (t[k / 2 - 1] + t[k / 2])) : NAN;
    free(t);
    return m;
}

double vg_quantile(const double *v, size_t n, size_t stride, double q)
{
    size_t k;
    double *t = sorted_finite(v, n, stride, &k);
    double m = NAN;
    if (t && k) {
        double r = floor(fmin(fmax(q, 0.0), 1.0) * (double)(k - 1) + 0.5);
        m = t[(size_t)r];
    }
    free(t);
    return m;
}
