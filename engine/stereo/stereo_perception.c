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
