/* vergence — perceived disparity velocity (paper Sec. 4.2, symmetric form of DESIGN.md).
 *
 *   p(v) = sign(v) ln(1 + |v|) / k,   v in arcmin/s, k = 0.08 (Weber fraction)
 *
 * p is in JND units: two velocities whose p differ by less than 1 cannot be
 * told apart. The paper's ln(v + 1) is undefined for approaching motion; the
 * symmetric form keeps the same JND scale in both directions (Weber fraction
 * independent of direction, paper Sec. 2). Double precision here; the float
 * kernels of the optimiser use the same formula from disparity/mid_shared.h. */
#pragma once

#include "stereo_shared.h" /* STEREO_WEBER_K */

/* p(v) for Weber fraction k (0 = STEREO_WEBER_K). */
double stereo_p(double v_arcmin_s, double k);
/* dp/dv = 1 / (k (1 + |v|)): continuous at 0, so p is C1 (not C2). */
double stereo_p_slope(double v_arcmin_s, double k);
/* Inverse of p: the velocity with perceived value j (JND). */
double stereo_p_inverse(double j, double k);
/* Perceived difference of two velocities in JND: p(a) - p(b). */
double stereo_jnd_difference(double a_arcmin_s, double b_arcmin_s, double k);
/* Perceived acceleration between two consecutive velocities, in JND. */
double stereo_jnd_acceleration(double v_before, double v_after, double k);
/* The paper's MID distortion on one track (docs/method.md §11 on one
 * sample, noiseless): x against its reference ref, both sampled at times t
 * (seconds, increasing), n samples; RMS over the inner samples where ref
 * moves in depth (|v| >= 1 arcmin/s on either side) of
 * [p(v+(x)) - p(v-(x))] - [p(v+(ref)) - p(v-(ref))], v over the two
 * neighbouring intervals, JND. 0 with no such sample. */
double stereo_track_mid_distortion(const double *x, const double *ref, const double *t, int n, double k);
