#include "testlib.h"

#include <math.h>
#include <stdlib.h>

#include "stereo/stereo_perception.h"

float rnd_uniform(unsigned *s, float lo, float hi)
{
    *s = *s * 1664525u + 1013904223u;
    return lo + (hi - lo) * (float)((*s >> 8) & 0xFFFFFF) / (float)0x1000000;
}

/* ------------------------------------------------------------------------- */
/* Synthetic scene                                                           */
/* ------------------------------------------------------------------------- */

typedef struct synth_geom {
    int nx, ny, nt;
    double dt, g0, g1;
} synth_geom;

static synth_geom geom(const synth_desc *d)
{
    synth_geom s = {d->nx ? d->nx : 48, d->ny ? d->ny : 27, d->nt ? d->nt : 16, 1.0 / 6.0, 35.0, 230.0};
    if (d->h_equals_g) {
        s.g0 = 225.0;
        s.g1 = 330.0;
    }
    return s;
}

static double ball_vergence(const synth_desc *d, int k)
{
    synth_geom s = geom(d);
    double u = (double)k / (s.nt - 1);
    return d->motion == SYNTH_CONSTANT_ACCEL ? s.g0 + (s.g1 - s.g0) * u * u : s.g0 + (s.g1 - s.g0) * u;
}

static double ball_x(const synth_desc *d, int k)
{
    synth_geom s = geom(d);
    return 8.0 + (s.nx - 20.0) * k / (s.nt - 1);
}

bool synth_is_ball(const synth_desc *d, int k, int x, int y)
{
    synth_geom s = geom(d);
    double dx = x - ball_x(d, k), dy = y - 0.5 * (s.ny - 1);
    return dx * dx + dy * dy <= 4.0 * 4.0;
}

/* Static layers: vergence of the scene behind the ball at (x, y). */
static double layer_vergence(const stereo_display *disp, const synth_desc *d, int x, int y)
{
    synth_geom s = geom(d);
    if (d->h_equals_g)
        return 230.0 + 20.0 * x / s.nx; /* a tilted wall inside the range */
    if (y < s.ny / 4)
        return stereo_vergence_from_distance(disp, 3.0);
    if (y >= s.ny - s.ny / 4)
        return stereo_vergence_from_distance(disp, 1.5);
    if (x >= s.nx - 6)
        return stereo_vergence_from_distance(disp, 0.9);
    return stereo_vergence_from_distance(disp, 10.0);
}

mid_window *synth_window(const synth_desc *d)
{
    stereo_display disp;
    stereo_display_init(&disp, &(stereo_display_desc){0});
    synth_geom s = geom(d);
    mid_window *w;
    if (mid_window_create(&(mid_window_desc){.width = s.nx, .height = s.ny, .keyframes = s.nt,
                                             .range_lo = (float)(disp.screen_vergence - 60),
                                             .range_hi = (float)(disp.screen_vergence + 60),
                                             .keyframe_seconds = (float)s.dt},
                          &w) != VG_OK)
        return NULL;
    float *sal = malloc((size_t)w->ns * sizeof(float));
    disp_operator *op = NULL;
    double dom_lo = 1e9, dom_hi = -1e9;
    for (int k = 0; k < s.nt; k++)
        for (int p = 0; p < w->ns; p++) {
            int x = p % s.nx, y = p / s.nx, i = k * w->ns + p;
            bool ball = synth_is_ball(d, k, x, y);
            double g = ball ? ball_vergence(d, k) : layer_vergence(&disp, d, x, y);
            w->g[i] = (float)g;
            w->depth[i] = (float)stereo_distance_from_vergence(&disp, g);
            double mx_f = k + 1 < s.nt ? ball_x(d, k + 1) - ball_x(d, k) : 0.0;
            double mx_b = k > 0 ? ball_x(d, k - 1) - ball_x(d, k) : 0.0;
            w->flow_fwd[2 * i] = ball ? (float)mx_f : 0.0f;
            w->flow_bwd[2 * i] = ball ? (float)mx_b : 0.0f;
            dom_lo = fmin(dom_lo, g);
            dom_hi = fmax(dom_hi, g);
        }
    if (d->h_equals_g) {
        for (int i = 0; i < w->n; i++)
            w->h[i] = w->g[i];
    } else if (sal && disp_operator_create(&(disp_operator_desc){.kind = d->op, .screen_vergence = disp.screen_vergence,
                                                                  .in_min = dom_lo, .in_max = dom_hi,
                                                                  .frame_seconds = s.dt},
                                           &op) == VG_OK) {
        for (int k = 0; k < s.nt; k++) {
            for (int p = 0; p < w->ns; p++)
                sal[p] = synth_is_ball(d, k, p % s.nx, p / s.nx) ? 1.0f : 0.1f;
            disp_operator_apply(op, w->g + (size_t)k * w->ns, d->salient_ball ? sal : NULL, w->ns,
                                w->h + (size_t)k * w->ns, NULL);
        }
    }
    disp_operator_destroy(op);
    free(sal);
    if (mid_window_build(w, NULL) != VG_OK) {
        mid_window_destroy(w);
        return NULL;
    }
    return w;
}

/* ------------------------------------------------------------------------- */
/* Random window                                                             */
/* ------------------------------------------------------------------------- */

mid_window *random_window(int nx, int ny, int nt, unsigned seed)
{
    mid_window *w;
    if (mid_window_create(&(mid_window_desc){.width = nx, .height = ny, .keyframes = nt,
                                             .range_lo = 200, .range_hi = 340},
                          &w) != VG_OK)
        return NULL;
    unsigned s = seed;
    for (int k = 0; k + 1 < nt; k++)
        w->dt[k] = rnd_uniform(&s, 0.08f, 0.25f);
    for (int i = 0; i < w->n; i++) {
        int p = i % w->ns, x = p % nx, y = p / nx;
        w->g[i] = rnd_uniform(&s, 150, 400);
        w->h[i] = rnd_uniform(&s, 205, 335);
        /* Two depth layers in 3x3 patches, varying per keyframe: occlusions. */
        unsigned cell = (unsigned)((x / 3) * 131 + (y / 3) * 71 + (i / w->ns) * 17) * 2654435761u;
        w->depth[i] = ((cell >> 13) & 3) == 0 ? 2.5f : 1.0f + rnd_uniform(&s, 0.0f, 0.05f);
        w->flow_fwd[2 * i] = rnd_uniform(&s, -2.0f, 2.0f);
        w->flow_fwd[2 * i + 1] = rnd_uniform(&s, -2.0f, 2.0f);
        w->flow_bwd[2 * i] = rnd_uniform(&s, -2.0f, 2.0f);
        w->flow_bwd[2 * i + 1] = rnd_uniform(&s, -2.0f, 2.0f);
    }
    if (mid_window_build(w, NULL) != VG_OK) {
        mid_window_destroy(w);
        return NULL;
    }
    return w;
}

/* ------------------------------------------------------------------------- */
/* Reference cost                                                            */
/* ------------------------------------------------------------------------- */

static double link_apply_d(const mid_window *w, const mid_link *links, int i, const double *x)
{
    mid_link l = links[i];
    mid_taps t = mid_link_taps(l);
    uint b = l.base, nx = (uint)w->nx;
    return t.w00 * x[b] + t.w10 * x[b + 1] + t.w01 * x[b + nx] + t.w11 * x[b + nx + 1];
}

double reference_cost(const mid_window *w, mid_weights wt, const double *f)
{
    wt = mid_weights_resolve(wt);
    double *g = malloc((size_t)w->n * sizeof(double)), *h = malloc((size_t)w->n * sizeof(double));
    for (int i = 0; i < w->n; i++) {
        g[i] = w->g[i];
        h[i] = w->h[i];
    }
    double k = STEREO_WEBER_K, cm = 0, cs = 0, ct = 0, ca = 0;
    double inv_range = 1.0 / ((double)w->range_hi - w->range_lo);
    for (int i = 0; i < w->n; i++) {
        int kf = i / w->ns, p = i % w->ns, x = p % w->nx, y = p / w->nx;
        cm += (f[i] - h[i]) * (f[i] - h[i]);
        /* c_s: a = exp(-10 |dh| / range) per edge, residual a * D(f - h). */
        if (x + 1 < w->nx) {
            double a = exp(-10.0 * fabs(h[i + 1] - h[i]) * inv_range);
            double d = (f[i + 1] - h[i + 1]) - (f[i] - h[i]);
            cs += a * a * d * d;
        }
        if (y + 1 < w->ny) {
            double a = exp(-10.0 * fabs(h[i + w->nx] - h[i]) * inv_range);
            double d = (f[i + w->nx] - h[i + w->nx]) - (f[i] - h[i]);
            cs += a * a * d * d;
        }
        bool vf = w->fwd[i].mask != 0, vb = w->bwd[i].mask != 0;
        double dtf = kf + 1 < w->nt ? w->dt[kf] : 1, dtb = kf > 0 ? w->dt[kf - 1] : 1;
        if (vf) {
            double pf = stereo_p((link_apply_d(w, w->fwd, i, f) - f[i]) / dtf, k);
            double ph = stereo_p((link_apply_d(w, w->fwd, i, h) - h[i]) / dtf, k);
            ct += (pf - ph) * (pf - ph);
            if (vb) {
                double pb = stereo_p((f[i] - link_apply_d(w, w->bwd, i, f)) / dtb, k);
                double gf = stereo_p((link_apply_d(w, w->fwd, i, g) - g[i]) / dtf, k);
                double gb = stereo_p((g[i] - link_apply_d(w, w->bwd, i, g)) / dtb, k);
                double r = (pf - pb) - (gf - gb);
                ca += r * r;
            }
        }
    }
    free(g);
    free(h);
    return (wt.data * cm + wt.spatial * cs + wt.temporal * ct + wt.accel * ca) / w->n;
}
