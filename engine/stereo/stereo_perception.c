#include "stereo_perception.h"

#include <math.h>

static double weber(double k)
{
    return k > 0 ? k : STEREO_WEBER_K;
}

double stereo_p(double v, double k)
{
    return copysign(log1p(fabs(v)), v) / weber(k);
}

double stereo_p_slope(double v, double k)
{
    return 1.0 / (weber(k) * (1.0 + fabs(v)));
}

double stereo_p_inverse(double j, double k)
{
    return copysign(expm1(fabs(j) * weber(k)), j);
}

double stereo_jnd_difference(double a, double b, double k)
{
    return stereo_p(a, k) - stereo_p(b, k);
}

/* Paper Sec. 4.2: velocities go to sensory units before the (second-order)
 * difference is taken, so the acceleration is a difference of p values. */
double stereo_jnd_acceleration(double v_before, double v_after, double k)
{
    return stereo_p(v_after, k) - stereo_p(v_before, k);
}

double stereo_track_mid_distortion(const double *x, const double *ref, const double *t, int n, double k)
{
    double sum = 0.0;
    int m = 0;
    for (int i = 1; i + 1 < n; i++) {
        double dp = t[i + 1] - t[i], dm = t[i] - t[i - 1];
        double rp = (ref[i + 1] - ref[i]) / dp, rm = (ref[i] - ref[i - 1]) / dm;
        if (fmax(fabs(rp), fabs(rm)) < 1.0)
            continue; /* not moving in depth */
        double xp = (x[i + 1] - x[i]) / dp, xm = (x[i] - x[i - 1]) / dm;
        double e = stereo_jnd_acceleration(xm, xp, k) - stereo_jnd_acceleration(rm, rp, k);
        sum += e * e, m++;
    }
    return m ? sqrt(sum / m) : 0.0;
}
