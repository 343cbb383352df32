/* vergence — the simulated observer: perception, fit, extrapolation, click. */
#include "observer.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "stereo/stereo_perception.h"

struct observer {
    observer_desc d;
    observer_view *view;
    double k, fps;
    bool noiseless;
    int window;         /* frames per integration window */
    double cal0, cal1;  /* displayed vergence = cal0 + cal1 g, fitted to the surround */
    const observer_shown *shown; /* the trial's frames as the engine showed them, NULL = the CPU view */
};

vg_status observer_create(const observer_desc *desc, observer **out)
{
    *out = NULL;
    observer *o = calloc(1, sizeof *o);
    if (!o)
        return VG_ERR_NOMEM;
    o->d = *desc;
    o->fps = desc->view.fps > 0 ? desc->view.fps : 60.0;
    o->k = desc->weber_k > 0 ? desc->weber_k : STEREO_WEBER_K;
    o->noiseless = desc->weber_k < 0;
    o->cal1 = 1.0;
    /* ~100 ms: the disparity-modulation cutoff near 10 Hz (paper Sec. 2). */
    double win = desc->window_s > 0 ? desc->window_s : 0.1;
    o->window = (int)lround(win * o->fps);
    o->window = o->window < 1 ? 1 : o->window;
    vg_status st = observer_view_create(&desc->view, &o->view);
    if (st != VG_OK) {
        free(o);
        return st;
    }
    *out = o;
    return VG_OK;
}

void observer_destroy(observer *o)
{
    if (!o)
        return;
    observer_view_destroy(o->view);
    free(o);
}

const vg_camera *observer_camera(const observer *o)
{
    return observer_view_camera(o->view);
}

/* ------------------------------------------------------------------------- */
/* Perception                                                                */
/* ------------------------------------------------------------------------- */

/* Perceived vergence velocity per window (arcmin/s): the window's mean
 * velocity with one JND of Gaussian noise in p-space, i.e. a Weber noise of
 * about k (1 + |v|) (paper Sec. 4.2; DESIGN.md's symmetric p). */
static double perceive_velocity(const observer *o, double v, game_rng *noise)
{
    if (o->noiseless)
        return v;
    return stereo_p_inverse(stereo_p(v, o->k) + game_rng_normal(noise), o->k);
}

/* The vergence track as perceived: the first value as shown, then the
 * shown per-frame velocities shifted by each window's perceptual error. */
static void perceive_track(const observer *o, const double *a, int n, game_rng *noise, double *out)
{
    out[0] = a[0];
    for (int j = 0; j + 1 < n; j += o->window) {
        int end = j + o->window < n - 1 ? j + o->window : n - 1;
        double mean = (a[end] - a[j]) * o->fps / (end - j);
        double delta = perceive_velocity(o, mean, noise) - mean;
        for (int i = j; i < end; i++)
            out[i + 1] = out[i] + (a[i + 1] - a[i]) + delta / o->fps;
    }
}

/* The observer knows the arena (a flat field seen from eye height, with
 * distance lines): it relates the vergence the field is shown with to the
 * field's distances by one compression about a level, displayed = c0 + c1 g,
 * fitted over the visible ground (least squares in vergence). Unmodified
 * stereo gives c0 = 0, c1 = 1; a linear operator is undone exactly; what a
 * nonlinear or time-varying mapping does beyond that stays a distortion. */
static void calibrate(observer *o, frame_mode mode)
{
    const vg_camera *c = observer_camera(o);
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (int j = 0; j < 24; j++)
        for (int i = 0; i < 16; i++) {
            double u = (i + 0.5) / 16, v = (j + 0.5) / 24, org[3], d[3];
            game_ray(c, u, v, org, d);
            if (!(d[1] < -1e-3))
                continue; /* sky */
            double s = -org[1] / d[1];
            double zv = s * (d[0] * c->forward[0] + d[1] * c->forward[1] + d[2] * c->forward[2]);
            if (zv > 42.0)
                continue; /* the field ends at the far wall */
            double g = stereo_camera_vergence(observer_view_rig(o->view), observer_view_display(o->view), zv);
            double a = observer_view_surround(o->view, o->shown, mode, zv, u, v);
            sx += g, sy += a, sxx += g * g, sxy += g * a, n++;
        }
    double det = n * sxx - sx * sx;
    o->cal1 = n > 1 && det > 1e-9 ? (n * sxy - sx * sy) / det : 1.0;
    o->cal1 = o->cal1 > 1e-3 ? o->cal1 : 1e-3;
    o->cal0 = n > 0 ? (sy - o->cal1 * sx) / n : 0.0;
}

/* Vergence -> the original vergence it stands for (the calibration), then
 * distance through the display model and the original rig's inverse: the
 * world depth unmodified stereo would have meant. */
static double decode_depth(const observer *o, double a)
{
    a = (a - o->cal0) / o->cal1;
    double z = stereo_camera_depth_from_vergence(observer_view_rig(o->view), observer_view_display(o->view), a);
    const vg_camera *c = observer_camera(o);
    if (!(z < 10.0 * c->zfar))
        z = 10.0 * c->zfar; /* beyond infinity: as far as it gets */
    return z > c->znear ? z : c->znear;
}

/* The two-cue observer's single motion-in-depth stage (RB79: changing
 * size and changing disparity feed the same stage; Duke and Rushton 2012:
 * the sum of the looming and the changing-disparity signals) sees the sum
 * of the ball's displayed angular diameter and its displayed vergence, both
 * in arcmin, so each cue weighs by its own rate of change: for a ball of
 * diameter D at distance Z, looming D Z'/Z^2 beside disparity I Z'/Z^2.
 * The display shows a camera angle alpha at alpha * m, m = the screen's
 * half width / (viewing distance tan(horizontal fov / 2)) (small angles). */
static double ball_size_arcmin(const observer *o, double u, double v, double z)
{
    const vg_camera *c = observer_camera(o);
    const stereo_display *d = observer_view_display(o->view);
    double ty = tan(0.5 * c->yfov), tx = ty * c->aspect;
    double x = (2.0 * u - 1.0) * tx, y = (1.0 - 2.0 * v) * ty;
    double dist = z * sqrt(1.0 + x * x + y * y), r = observer_view_radius(o->view);
    double alpha = 2.0 * asin(fmin(1.0, r / fmax(dist, r)));
    return alpha * (0.5 * d->width_m / (d->distance_m * tx)) * STEREO_ARCMIN_PER_RAD;
}

/* What the stage's signal (ball size + calibrated vergence) means: the
 * view depth on the ray through (u, v) at which unmodified stereo would
 * give it (both terms fall with depth: bisection in 1/z). */
static double decode_depth_two_cue(const observer *o, double s, double u, double v)
{
    const vg_camera *c = observer_camera(o);
    double lo = c->znear, hi = 10.0 * c->zfar;
    for (int it = 0; it < 60; it++) {
        double z = 2.0 / (1.0 / lo + 1.0 / hi);
        double at = ball_size_arcmin(o, u, v, z) + o->cal0 +
                    o->cal1 * stereo_camera_vergence(observer_view_rig(o->view), observer_view_display(o->view), z);
        if (at > s)
            lo = z; /* the signal at z is larger: the ball is farther */
        else
            hi = z;
    }
    return 0.5 * (lo + hi);
}

/* The world point at view depth z on the ray through (u, v). */
static void point_at(const vg_camera *c, double u, double v, double z, double p[3])
{
    double ty = tan(0.5 * c->yfov), tx = ty * c->aspect;
    double x = (2.0 * u - 1.0) * tx, y = (1.0 - 2.0 * v) * ty;
    for (int k = 0; k < 3; k++)
        p[k] = c->position[k] + z * (c->forward[k] + x * c->right[k] + y * c->up[k]);
}

/* ------------------------------------------------------------------------- */
/* Fit and extrapolation                                                     */
/* ------------------------------------------------------------------------- */

typedef struct path_fit {
    double p0[3], v0[3], gravity;
} path_fit;

static void fit_eval(const path_fit *f, double t, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = f->p0[k] + f->v0[k] * t;
    out[1] -= 0.5 * f->gravity * t * t;
}

/* Least squares per coordinate: x and z linear in t; y linear after adding
 * back the known gravity (a ballistic throw's observer expects an arc). */
static void fit_path(const double (*p)[3], int n, double fps, double gravity, path_fit *out)
{
    double st = 0, stt = 0;
    for (int i = 0; i < n; i++) {
        double t = i / fps;
        st += t, stt += t * t;
    }
    double det = n * stt - st * st;
    out->gravity = gravity;
    for (int k = 0; k < 3; k++) {
        double sy = 0, sty = 0;
        for (int i = 0; i < n; i++) {
            double t = i / fps, y = p[i][k] + (k == 1 ? 0.5 * gravity * t * t : 0.0);
            sy += y, sty += t * y;
        }
        out->v0[k] = det > 0 ? (n * sty - st * sy) / det : 0.0;
        out->p0[k] = (sy - out->v0[k] * st) / n;
    }
}

/* > 0 while the fitted ball's lowest point is still in front of the ground
 * as displayed: its view depth against the decoded depth of the ground
 * seen in the same direction. Sky (no ground that way) counts as air. */
static double air_gap(const observer *o, const path_fit *f, double t, frame_mode mode, double contact[3])
{
    const vg_camera *c = observer_camera(o);
    fit_eval(f, t, contact);
    contact[1] -= observer_view_radius(o->view);
    double u, v, o3[3], d[3];
    double zc = game_project(c, contact, &u, &v);
    if (zc < 2.0 * c->znear)
        return 0.0; /* reached the player */
    game_ray(c, u, v, o3, d);
    if (!(d[1] < -1e-9))
        return 1.0;
    double s = -o3[1] / d[1];
    double ground[3] = {o3[0] + s * d[0], 0.0, o3[2] + s * d[2]};
    double zg = (ground[0] - c->position[0]) * c->forward[0] + (ground[1] - c->position[1]) * c->forward[1] +
                (ground[2] - c->position[2]) * c->forward[2];
    return decode_depth(o, observer_view_surround(o->view, o->shown, mode, zg, u, v)) - zc;
}

static double find_contact(const observer *o, const path_fit *f, double t0, frame_mode mode, double contact[3])
{
    const double step = 1.0 / 120.0, horizon = 10.0;
    double prev = t0;
    if (air_gap(o, f, t0, mode, contact) <= 0)
        return t0;
    for (double t = t0 + step; t <= t0 + horizon; t += step) {
        if (air_gap(o, f, t, mode, contact) > 0) {
            prev = t;
            continue;
        }
        double lo = prev, hi = t; /* bisection: in the air at lo, on the ground at hi */
        for (int it = 0; it < 40; it++) {
            double mid = 0.5 * (lo + hi);
            if (air_gap(o, f, mid, mode, contact) > 0)
                lo = mid;
            else
                hi = mid;
        }
        air_gap(o, f, hi, mode, contact);
        return hi;
    }
    /* It never comes down in view: click where the fit leaves it. */
    air_gap(o, f, t0 + horizon, mode, contact);
    return t0 + horizon;
}

/* ------------------------------------------------------------------------- */
/* Trials                                                                    */
/* ------------------------------------------------------------------------- */

vg_status observer_play(observer *o, const game_throw *th, frame_mode mode, const observer_shown *shown,
                        game_rng *noise, observer_result *out)
{
    memset(out, 0, sizeof *out);
    const vg_camera *cam = observer_camera(o);
    int n = (int)ceil(th->visible_s * o->fps - 1e-9);
    n = n < 2 ? 2 : n;
    double (*pos)[3] = malloc((size_t)n * sizeof *pos), (*seen)[3] = malloc((size_t)n * sizeof *seen);
    double *a = malloc((size_t)n * sizeof(double)), *ap = malloc((size_t)n * sizeof(double));
    double *g = malloc((size_t)n * sizeof(double));
    vg_status st = pos && seen && a && ap && g ? VG_OK : VG_ERR_NOMEM;
    for (int i = 0; i < n && st == VG_OK; i++)
        game_throw_position(th, i / o->fps, pos[i]);
    if (st == VG_OK && shown && shown->count < n)
        st = VG_ERR_ARG;
    /* The engine's frames: the exact g of the ball's centre plus the
     * displacement the frame gave the ball's pixels. */
    if (st == VG_OK)
        st = observer_view_track(o->view, (const double (*)[3])pos, n, shown ? FRAME_MODE_ORIGINAL : mode, a);
    /* g, to measure what the condition did to the ball as shown. */
    if (st == VG_OK && (shown || mode == FRAME_MODE_ORIGINAL))
        memcpy(g, a, (size_t)n * sizeof *g);
    else if (st == VG_OK)
        st = observer_view_track(o->view, (const double (*)[3])pos, n, FRAME_MODE_ORIGINAL, g);
    for (int i = 0; shown && st == VG_OK && i < n; i++)
        a[i] += shown->offset[i];
    int stride = observer_view_keyframe_stride(o->view);
    if (st == VG_OK)
        out->ball_mid_jnd = (n - 1) / stride + 1 < 3 ? NAN : observer_track_mid_distortion(a, g, n, stride, o->fps,
                                                                                             o->k);
    o->shown = shown;
    if (st == VG_OK) {
        calibrate(o, mode);
        /* Two cues: the stage's signal is the ball's displayed size (the
         * geometry is the same in every mode) plus its displayed vergence. */
        for (int i = 0; o->d.size_cue && i < n; i++) {
            double u, v, z = game_project(cam, pos[i], &u, &v);
            a[i] += ball_size_arcmin(o, u, v, z);
        }
        perceive_track(o, a, n, noise, ap);
        for (int i = 0; i < n; i++) {
            double u, v;
            game_project(cam, pos[i], &u, &v);
            point_at(cam, u, v, o->d.size_cue ? decode_depth_two_cue(o, ap[i], u, v) : decode_depth(o, ap[i]), seen[i]);
        }
        path_fit fit;
        fit_path((const double (*)[3])seen, n, o->fps, th->path == GAME_PATH_BALLISTIC ? GAME_GRAVITY : 0.0, &fit);
        double contact[3];
        find_contact(o, &fit, (n - 1) / o->fps, mode, contact);
        game_project(cam, contact, &out->click_u, &out->click_v);
        out->click_u = fmin(1.0, fmax(0.0, out->click_u));
        out->click_v = fmin(1.0, fmax(0.0, out->click_v));
        memcpy(out->perceived_ground, contact, sizeof contact);
        out->error_m = game_click_error(cam, out->click_u, out->click_v, th->ground);
        out->frames_seen = n;
    }
    o->shown = NULL;
    free(pos), free(seen), free(a), free(ap), free(g);
    return st;
}

/* Perceived velocity changes (JND) of a track, one per window boundary. */
static int perceived_changes(const observer *o, const double *a, int n, game_rng *noise, double *dp)
{
    int m = 0;
    double prev = 0;
    for (int j = 0; j + o->window < n; j += o->window) {
        double v = (a[j + o->window] - a[j]) * o->fps / o->window;
        double p = stereo_p(perceive_velocity(o, v, noise), o->k);
        if (j > 0)
            dp[m++] = p - prev;
        prev = p;
    }
    return m;
}

/* The paper's measure on a track, at its keyframes (stereo_perception.h). */
double observer_track_mid_distortion(const double *x, const double *ref, int n, int stride, double fps, double k)
{
    int m = n > 0 ? (n - 1) / stride + 1 : 0;
    double *a = malloc(3 * (size_t)(m ? m : 1) * sizeof(double));
    if (!a)
        return NAN;
    for (int i = 0; i < m; i++)
        a[i] = x[i * stride], a[m + i] = ref[i * stride], a[2 * m + i] = i * stride / fps;
    double d = stereo_track_mid_distortion(a, a + m, a + 2 * m, m, k);
    free(a);
    return d;
}

vg_status observer_prefer(observer *o, const double (*pos)[3], int count, const frame_mode modes[3],
                          const observer_shown *const shown[3], game_rng *noise, observer_choice *out)
{
    double *a = malloc(3 * (size_t)count * sizeof(double)), *dp = malloc(3 * (size_t)count * sizeof(double));
    double *g = malloc((size_t)count * sizeof(double));
    vg_status st = a && dp && g ? VG_OK : VG_ERR_NOMEM;
    int m = 0;
    if (st == VG_OK)
        st = observer_view_track(o->view, pos, count, FRAME_MODE_ORIGINAL, g);
    for (int s = 0; s < 3 && st == VG_OK; s++) {
        double *x = a + (size_t)s * count;
        const observer_shown *sh = shown ? shown[s] : NULL;
        if (sh && sh->count < count)
            st = VG_ERR_ARG;
        else if (sh)
            for (int i = 0; i < count; i++)
                x[i] = g[i] + sh->offset[i];
        else
            st = observer_view_track(o->view, pos, count, modes[s], x);
        if (st == VG_OK)
            m = perceived_changes(o, x, count, noise, dp + (size_t)s * count);
    }
    if (st == VG_OK) {
        *out = (observer_choice){0};
        for (int s = 0; s < 2; s++) {
            for (int i = 0; i < m; i++) {
                double e = dp[(size_t)s * count + i] - dp[2 * (size_t)count + i];
                out->compared[s] += e * e;
            }
            out->mid_jnd[s] = observer_track_mid_distortion(a + (size_t)s * count, a + 2 * (size_t)count, count,
                                                            observer_view_keyframe_stride(o->view), o->fps, o->k);
        }
        const double *d = out->compared;
        out->side = d[0] < d[1] ? 0 : d[1] < d[0] ? 1 : (int)(game_rng_next(noise) & 1);
    }
    free(a), free(dp), free(g);
    return st;
}
