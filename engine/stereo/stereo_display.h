/* vergence — display and stereo-camera geometry (DESIGN.md "Units and conventions").
 *
 * Quantities and signs, for a viewer centred in front of the screen:
 *   vergence a      arcmin, always > 0, larger = nearer; a_s = 2 atan(e / 2D) on the screen
 *   distance Z      metres from the eyes to the perceived point
 *   parallax P      metres on the screen, x_right - x_left: > 0 behind the screen (uncrossed)
 *   pixels   d      P in display pixels (same sign as P)
 * With e the interocular distance and D the viewing distance (similar triangles):
 *   P = e (Z - D) / Z,   Z = e D / (e - P),   a = 2 atan(e / 2Z) = 2 atan((e - P) / 2D).
 * Points are taken on the viewing axis (the cyclopean line of sight), the usual
 * approximation in disparity retargeting; P >= e would need diverging eyes. */
#pragma once

typedef struct stereo_display_desc {
    double diagonal_in;   /* panel diagonal in inches, 0 = 24 */
    int aspect_w, aspect_h; /* panel aspect, 0 = 16:9 */
    int res_x, res_y;     /* pixels, 0 = 1920 x 1080 */
    double distance_m;    /* viewing distance D, 0 = 0.80 */
    double ipd_m;         /* interocular distance e, 0 = 0.065 */
} stereo_display_desc;

typedef struct stereo_display {
    double width_m, height_m; /* visible panel size */
    double pitch_m;           /* width of one pixel */
    double distance_m, ipd_m;
    int res_x, res_y;
    double screen_vergence;   /* a_s, arcmin */
} stereo_display;

/* Resolves the zero defaults (paper Sec. 5 setup: 24" 16:9, 1920x1080, 0.80 m). */
void stereo_display_init(stereo_display *d, const stereo_display_desc *desc);
/* The resolved display as the JSON object "display" (capture.json,
 * metrics.json): a valid `--display FILE` (docs/formats.md). */
struct vg_json;
void stereo_display_json(struct vg_json *j, const stereo_display_desc *desc);

double stereo_vergence_from_distance(const stereo_display *d, double z_m);
double stereo_distance_from_vergence(const stereo_display *d, double a_arcmin);
double stereo_parallax_from_distance(const stereo_display *d, double z_m);
double stereo_distance_from_parallax(const stereo_display *d, double p_m);
double stereo_vergence_from_parallax(const stereo_display *d, double p_m);
double stereo_parallax_from_vergence(const stereo_display *d, double a_arcmin);
double stereo_pixels_from_parallax(const stereo_display *d, double p_m);
double stereo_parallax_from_pixels(const stereo_display *d, double px);
double stereo_vergence_from_pixels(const stereo_display *d, double px);
double stereo_pixels_from_vergence(const stereo_display *d, double a_arcmin);

/* Vergence of an image disparity in the stereo-dataset convention
 * (d = x_left - x_right, larger = nearer; FlyingThings3D, Middlebury, KITTI)
 * of an image image_width pixels wide shown across the full panel width:
 * P = -(d - zero_px) * width_m / image_width, so d == zero_px lands on the screen. */
double stereo_vergence_from_dataset_px(const stereo_display *d, double disp_px, double zero_px,
                                       int image_width);

/* A parallel stereo rig with shifted sensors (off-axis frusta) rendering for
 * the display. Each eye's image is image_width pixels across the panel width. */
typedef struct stereo_camera_desc {
    double interaxial_m;    /* b, 0 = the display's e (ortho-stereo) */
    double convergence_m;   /* c, zero-parallax distance, 0 = the display's D */
    double hfov_deg;        /* horizontal field of view, 0 = the panel's angle at D */
    int image_width;        /* pixels, 0 = the display's res_x */
} stereo_camera_desc;

typedef struct stereo_camera {
    double interaxial_m, convergence_m, hfov_rad;
    int image_width;
    double gain_px; /* K = W b / (2 c tan(fov/2)): parallax_px = K (1 - c / z) */
} stereo_camera;

void stereo_camera_init(stereo_camera *cam, const stereo_camera_desc *desc, const stereo_display *d);
/* Image parallax in pixels (x_right - x_left) of a point at depth z (metres along the view axis). */
double stereo_camera_parallax_px(const stereo_camera *cam, double z_m);
/* Inverse: depth of an image parallax; +inf when px >= K (beyond infinity). */
double stereo_camera_depth_from_parallax_px(const stereo_camera *cam, double px);
/* g of the paper: the vergence a viewer of the display gets for scene depth z. */
double stereo_camera_vergence(const stereo_camera *cam, const stereo_display *d, double z_m);
/* Inverse of stereo_camera_vergence. */
double stereo_camera_depth_from_vergence(const stereo_camera *cam, const stereo_display *d,
                                         double a_arcmin);
/* g for a whole depth image (n values); writes arcmin floats. */
void stereo_camera_vergence_image(const stereo_camera *cam, const stereo_display *d,
                                  const float *depth_m, int n, float *vergence);
