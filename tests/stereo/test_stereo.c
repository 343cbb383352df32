/* Display geometry, stereo camera and perceptual model: round trips and
 * independent geometric truths. Run one case: test_stereo NAME. */
#include <math.h>
#include <stdio.h>

#include "../test.h"
#include "disparity/mid_shared.h"
#include "stereo/stereo_display.h"
#include "stereo/stereo_perception.h"

static stereo_display display_default(void)
{
    stereo_display d;
    stereo_display_init(&d, &(stereo_display_desc){0});
    return d;
}

/* The defaults of DESIGN.md, checked against their own definitions. */
static int display_defaults(void)
{
    stereo_display d = display_default();
    double diag = sqrt(d.width_m * d.width_m + d.height_m * d.height_m) / 0.0254;
    printf("panel %.4f x %.4f m (diag %.3f in, aspect %.4f), pitch %.4f mm, a_s %.3f arcmin\n",
           d.width_m, d.height_m, diag, d.width_m / d.height_m, d.pitch_m * 1e3, d.screen_vergence);
    CHECK(fabs(diag - 24.0) < 1e-9, "diagonal %.12f", diag);
    CHECK(fabs(d.width_m / d.height_m - 16.0 / 9.0) < 1e-12, "aspect %.12f", d.width_m / d.height_m);
    CHECK(d.res_x == 1920 && d.res_y == 1080, "%dx%d", d.res_x, d.res_y);
    /* On the screen the parallax is zero and the vergence is a_s. */
    double a = stereo_vergence_from_distance(&d, d.distance_m);
    double p = stereo_parallax_from_distance(&d, d.distance_m);
    CHECK(fabs(a - d.screen_vergence) < 1e-9 && fabs(p) < 1e-15, "a %.9f p %.3g", a, p);
    CHECK(fabs(stereo_vergence_from_parallax(&d, 0) - d.screen_vergence) < 1e-9, "a(P=0)");
    return 0;
}

static int display_roundtrips(void)
{
    stereo_display d = display_default();
    double worst = 0;
    for (double z = 0.3; z < 200.0; z *= 1.07) {
        double a = stereo_vergence_from_distance(&d, z);
        double p = stereo_parallax_from_distance(&d, z);
        double px = stereo_pixels_from_parallax(&d, p);
        double e1 = fabs(stereo_distance_from_vergence(&d, a) - z) / z;
        double e2 = fabs(stereo_distance_from_parallax(&d, p) - z) / z;
        double e3 = fabs(stereo_vergence_from_parallax(&d, p) - a);
        double e4 = fabs(stereo_parallax_from_vergence(&d, a) - p);
        double e5 = fabs(stereo_vergence_from_pixels(&d, px) - a);
        double e6 = fabs(stereo_pixels_from_vergence(&d, a) - px);
        double e = fmax(fmax(fmax(e1, e2), fmax(e3, e4)), fmax(e5, e6 * 1e-3));
        worst = fmax(worst, e);
        CHECK(e < 1e-9, "z %.4f m: a %.6f arcmin, P %.6f m, %.4f px; errors %.3g %.3g %.3g %.3g %.3g %.3g",
              z, a, p, px, e1, e2, e3, e4, e5, e6);
    }
    printf("display round trips: worst error %.3g\n", worst);
    return 0;
}

/* Similar triangles seen from the other side: a point at distance Z on the
 * axis subtends the vergence 2 atan(e/2Z) and its two screen images are the
 * intersections of the eye rays with the plane at D. */
static int display_ray_geometry(void)
{
    stereo_display d = display_default();
    for (double z = 0.4; z < 50.0; z *= 1.5) {
        double e = d.ipd_m, D = d.distance_m;
        double xl = -e / 2 + (0 + e / 2) * D / z; /* left eye at -e/2 looking at (0, z) */
        double xr = e / 2 + (0 - e / 2) * D / z;
        double p_rays = xr - xl;
        double p = stereo_parallax_from_distance(&d, z);
        double a_true = 2 * atan(e / (2 * z)) * 60 * 180 / M_PI;
        printf("z %.3f: P %.6f (rays %.6f), a %.4f (true %.4f)\n", z, p, p_rays, stereo_vergence_from_parallax(&d, p), a_true);
        CHECK(fabs(p - p_rays) < 1e-12, "parallax %.9f vs rays %.9f", p, p_rays);
        CHECK(fabs(stereo_vergence_from_parallax(&d, p) - a_true) < 1e-9, "vergence");
    }
    return 0;
}

/* A parallel rig with the viewer's geometry (b = e, c = D, the panel's field
 * of view) is ortho-stereo: it must give every depth its natural vergence. */
static int camera_orthostereo(void)
{
    stereo_display d = display_default();
    stereo_camera cam;
    stereo_camera_init(&cam, &(stereo_camera_desc){0}, &d);
    double worst = 0;
    for (double z = 0.3; z < 100.0; z *= 1.1) {
        double a = stereo_camera_vergence(&cam, &d, z);
        double a_true = stereo_vergence_from_distance(&d, z);
        worst = fmax(worst, fabs(a - a_true));
        CHECK(fabs(a - a_true) < 1e-9, "z %.3f: rig %.9f natural %.9f", z, a, a_true);
    }
    printf("ortho-stereo rig vs natural vergence: worst %.3g arcmin (K = %.2f px)\n", worst, cam.gain_px);
    return 0;
}

static int camera_roundtrips(void)
{
    stereo_display d = display_default();
    stereo_camera cam;
    stereo_camera_init(&cam, &(stereo_camera_desc){.interaxial_m = 0.02, .convergence_m = 3.0,
                                                    .hfov_deg = 60, .image_width = 960}, &d);
    /* Zero parallax at the convergence distance, parallax -> K at infinity. */
    CHECK(fabs(stereo_camera_parallax_px(&cam, 3.0)) < 1e-12, "zero parallax at c");
    CHECK(fabs(stereo_camera_parallax_px(&cam, 1e12) - cam.gain_px) < 1e-6, "K at infinity");
    double expect_k = 960 * 0.02 / (2 * 3.0 * tan(M_PI / 6));
    CHECK(fabs(cam.gain_px - expect_k) < 1e-9, "K %.9f vs %.9f", cam.gain_px, expect_k);
    double worst = 0;
    for (double z = 0.5; z < 500.0; z *= 1.13) {
        double px = stereo_camera_parallax_px(&cam, z);
        double z1 = stereo_camera_depth_from_parallax_px(&cam, px);
        double a = stereo_camera_vergence(&cam, &d, z);
        double z2 = stereo_camera_depth_from_vergence(&cam, &d, a);
        double e = fmax(fabs(z1 - z) / z, fabs(z2 - z) / z);
        worst = fmax(worst, e);
        CHECK(e < 1e-9, "z %.3f: px %.6f -> %.9f; a %.6f -> %.9f", z, px, z1, a, z2);
    }
    printf("camera depth round trips: worst relative error %.3g\n", worst);
    return 0;
}

/* Dataset pixel disparity (x_left - x_right, larger = nearer) to vergence. */
static int dataset_pixels(void)
{
    stereo_display d = display_default();
    double a0 = stereo_vergence_from_dataset_px(&d, 0, 0, 960);
    double a1 = stereo_vergence_from_dataset_px(&d, 50, 0, 960);
    double a2 = stereo_vergence_from_dataset_px(&d, 100, 0, 960);
    /* 100 px of a 960 px image shown 0.5313 m wide is 5.53 cm of crossed parallax. */
    double p = -100 * d.width_m / 960;
    double z = d.ipd_m * d.distance_m / (d.ipd_m - p);
    double a_true = stereo_vergence_from_distance(&d, z);
    printf("dataset px 0/50/100 -> %.3f / %.3f / %.3f arcmin (expected %.3f at 100 px)\n", a0, a1, a2, a_true);
    CHECK(fabs(a0 - d.screen_vergence) < 1e-9, "zero disparity on the screen");
    CHECK(a2 > a1 && a1 > a0, "nearer for larger disparity");
    CHECK(fabs(a2 - a_true) < 1e-9, "%.9f vs %.9f", a2, a_true);
    return 0;
}

static int perception_model(void)
{
    double k = STEREO_WEBER_K;
    /* Odd symmetry and zero at rest (DESIGN.md symmetric form). */
    for (double v = 0.01; v < 1e4; v *= 3.7)
        CHECK(fabs(stereo_p(v, k) + stereo_p(-v, k)) < 1e-12, "p(%g) + p(-%g)", v, v);
    CHECK(stereo_p(0, k) == 0, "p(0)");
    /* Weber: an 8 %% change of a fast velocity is one JND. */
    double j = stereo_jnd_difference(1.08e4, 1e4, k);
    printf("p(10800) - p(10000) = %.4f JND; ln(1.08)/0.08 = %.4f\n", j, log(1.08) / 0.08);
    CHECK(fabs(j - log(1.08) / 0.08) < 1e-3 && j > 0.95 && j < 1.0, "%.6f", j);
    /* Slope against a central difference, inverse round trip. */
    for (double v = -500; v <= 500; v += 37.3) {
        double fd = (stereo_p(v + 1e-5, k) - stereo_p(v - 1e-5, k)) / 2e-5;
        CHECK(fabs(fd - stereo_p_slope(v, k)) < 1e-6 * stereo_p_slope(v, k), "slope at %g: %.9g vs %.9g", v, fd, stereo_p_slope(v, k));
        CHECK(fabs(stereo_p_inverse(stereo_p(v, k), k) - v) < 1e-9 * (1 + fabs(v)), "inverse at %g", v);
    }
    /* The float kernels of mid_shared.h agree with the double model. */
    double worst = 0;
    for (double v = -3000; v <= 3000; v += 0.731) {
        double e = fabs(mid_p((float)v) - stereo_p((float)v, k));
        double es = fabs(mid_dp((float)v) - stereo_p_slope((float)v, k)) / stereo_p_slope(v, k);
        worst = fmax(worst, e);
        CHECK(e < 2e-4 && es < 1e-5, "v %g: p %.7f vs %.7f", v, mid_p((float)v), stereo_p(v, k));
    }
    printf("float p vs double p: worst %.3g JND\n", worst);
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"display_defaults", display_defaults},
        {"display_roundtrips", display_roundtrips},
        {"display_ray_geometry", display_ray_geometry},
        {"camera_orthostereo", camera_orthostereo},
        {"camera_roundtrips", camera_roundtrips},
        {"dataset_pixels", dataset_pixels},
        {"perception_model", perception_model},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
