#include "stereo_display.h"
#include "stereo_shared.h"

#include "core/json.h"

#include <math.h>

#define METRES_PER_INCH 0.0254

/* ------------------------------------------------------------------------- */
/* Display                                                                   */
/* ------------------------------------------------------------------------- */

void stereo_display_init(stereo_display *d, const stereo_display_desc *desc)
{
    stereo_display_desc z = desc ? *desc : (stereo_display_desc){0};
    double diag = z.diagonal_in > 0 ? z.diagonal_in : 24.0;
    int aw = z.aspect_w > 0 ? z.aspect_w : 16, ah = z.aspect_h > 0 ? z.aspect_h : 9;
    double hyp = sqrt((double)aw * aw + (double)ah * ah);
    *d = (stereo_display){0};
    d->width_m = diag * METRES_PER_INCH * aw / hyp;
    d->height_m = diag * METRES_PER_INCH * ah / hyp;
    d->res_x = z.res_x > 0 ? z.res_x : 1920;
    d->res_y = z.res_y > 0 ? z.res_y : 1080;
    d->pitch_m = d->width_m / d->res_x;
    d->distance_m = z.distance_m > 0 ? z.distance_m : 0.80;
    d->ipd_m = z.ipd_m > 0 ? z.ipd_m : 0.065;
    d->screen_vergence = 2.0 * atan(d->ipd_m / (2.0 * d->distance_m)) * STEREO_ARCMIN_PER_RAD;
}

double stereo_vergence_from_distance(const stereo_display *d, double z_m)
{
    return 2.0 * atan(d->ipd_m / (2.0 * z_m)) * STEREO_ARCMIN_PER_RAD;
}

double stereo_distance_from_vergence(const stereo_display *d, double a_arcmin)
{
    return d->ipd_m / (2.0 * tan(0.5 * a_arcmin / STEREO_ARCMIN_PER_RAD));
}

/* Similar triangles between the eye baseline e at 0 and the screen at D. */
double stereo_parallax_from_distance(const stereo_display *d, double z_m)
{
    return d->ipd_m * (z_m - d->distance_m) / z_m;
}

double stereo_distance_from_parallax(const stereo_display *d, double p_m)
{
    return d->ipd_m * d->distance_m / (d->ipd_m - p_m);
}

/* a = 2 atan(e / 2Z) with Z = e D / (e - P) folds to 2 atan((e - P) / 2D),
 * which stays finite (and turns negative) past P = e. */
double stereo_vergence_from_parallax(const stereo_display *d, double p_m)
{
    return 2.0 * atan((d->ipd_m - p_m) / (2.0 * d->distance_m)) * STEREO_ARCMIN_PER_RAD;
}

double stereo_parallax_from_vergence(const stereo_display *d, double a_arcmin)
{
    return d->ipd_m - 2.0 * d->distance_m * tan(0.5 * a_arcmin / STEREO_ARCMIN_PER_RAD);
}

double stereo_pixels_from_parallax(const stereo_display *d, double p_m)
{
    return p_m / d->pitch_m;
}

double stereo_parallax_from_pixels(const stereo_display *d, double px)
{
    return px * d->pitch_m;
}

double stereo_vergence_from_pixels(const stereo_display *d, double px)
{
    return stereo_vergence_from_parallax(d, stereo_parallax_from_pixels(d, px));
}

double stereo_pixels_from_vergence(const stereo_display *d, double a_arcmin)
{
    return stereo_pixels_from_parallax(d, stereo_parallax_from_vergence(d, a_arcmin));
}

double stereo_vergence_from_dataset_px(const stereo_display *d, double disp_px, double zero_px,
                                       int image_width)
{
    double p = -(disp_px - zero_px) * d->width_m / (double)image_width;
    return stereo_vergence_from_parallax(d, p);
}

/* ------------------------------------------------------------------------- */
/* Stereo camera                                                             */
/* ------------------------------------------------------------------------- */

void stereo_camera_init(stereo_camera *cam, const stereo_camera_desc *desc, const stereo_display *d)
{
    stereo_camera_desc z = desc ? *desc : (stereo_camera_desc){0};
    *cam = (stereo_camera){0};
    cam->interaxial_m = z.interaxial_m > 0 ? z.interaxial_m : d->ipd_m;
    cam->convergence_m = z.convergence_m > 0 ? z.convergence_m : d->distance_m;
    cam->hfov_rad = z.hfov_deg > 0 ? z.hfov_deg * M_PI / 180.0
                                   : 2.0 * atan(0.5 * d->width_m / d->distance_m);
    cam->image_width = z.image_width > 0 ? z.image_width : d->res_x;
    /* Parallel rig, sensors shifted by f b / 2c: x_R - x_L = f b (1/c - 1/z) on the
     * sensor; the sensor width 2 f tan(fov/2) spans image_width pixels. */
    cam->gain_px = cam->image_width * cam->interaxial_m /
                   (2.0 * cam->convergence_m * tan(0.5 * cam->hfov_rad));
}

double stereo_camera_parallax_px(const stereo_camera *cam, double z_m)
{
    return cam->gain_px * (1.0 - cam->convergence_m / z_m);
}

double stereo_camera_depth_from_parallax_px(const stereo_camera *cam, double px)
{
    double t = 1.0 - px / cam->gain_px;
    return t > 0 ? cam->convergence_m / t : INFINITY;
}

/* The image fills the panel width: one image pixel is width_m / image_width. */
double stereo_camera_vergence(const stereo_camera *cam, const stereo_display *d, double z_m)
{
    double p = stereo_camera_parallax_px(cam, z_m) * d->width_m / cam->image_width;
    return stereo_vergence_from_parallax(d, p);
}

double stereo_camera_depth_from_vergence(const stereo_camera *cam, const stereo_display *d,
                                         double a_arcmin)
{
    double px = stereo_parallax_from_vergence(d, a_arcmin) * cam->image_width / d->width_m;
    return stereo_camera_depth_from_parallax_px(cam, px);
}

void stereo_camera_vergence_image(const stereo_camera *cam, const stereo_display *d,
                                  const float *depth_m, int n, float *vergence)
{
    for (int i = 0; i < n; i++)
        vergence[i] = (float)stereo_camera_vergence(cam, d, depth_m[i]);
}

void stereo_display_json(vg_json *j, const stereo_display_desc *desc)
{
    stereo_display d;
    stereo_display_init(&d, desc);
    vg_json_object_begin(j, "display");
    vg_json_num(j, "diagonal_in", desc->diagonal_in > 0 ? desc->diagonal_in : 24);
    vg_json_int(j, "width_px", d.res_x);
    vg_json_int(j, "height_px", d.res_y);
    vg_json_num(j, "width_m", d.width_m);
    vg_json_num(j, "height_m", d.height_m);
    vg_json_num(j, "distance_m", d.distance_m);
    vg_json_num(j, "ipd_m", d.ipd_m);
    vg_json_num(j, "screen_vergence_arcmin", d.screen_vergence);
    vg_json_object_end(j);
}
