#include "disp_metrics.h"

#include <math.h>
#include <stdlib.h>

#include "core/json.h"

/* A pixel moves in depth when g changes along a valid link by at least the
 * threshold velocity (the image-space motion alone is not motion in depth). */
/* Velocities per second whatever unit the window's solve uses (time_unit:
 * the sensitivity study), so every variant is measured alike. */
static bool is_moving(const mid_window *w, int i, float thr, float idf, float idb)
{
    float speed = 0.0f;
    if (w->fwd[i].mask)
        speed = fmaxf(speed, fabsf(mid_link_gather(w->fwd, w->nx, i, w->g) - w->g[i]) * idf);
    if (w->bwd[i].mask)
        speed = fmaxf(speed, fabsf(w->g[i] - mid_link_gather(w->bwd, w->nx, i, w->g)) * idb);
    return speed >= thr;
}

void disp_metrics_window(const mid_window *w, const float *x, const disp_metrics_desc *desc,
                         disp_metrics *out)
{
    float thr = desc && desc->moving_threshold > 0 ? desc->moving_threshold : 1.0f;
    double mid2 = 0, st2 = 0, grad2 = 0;
    disp_metrics m = {0};
    long out_of_range = 0;
    for (int i = 0; i < w->n; i++) {
        int k = i / w->ns, p = i % w->ns, px = p % w->nx, py = p / w->nx;
        if (w->unknown[i])
            continue; /* g unknown: nothing to measure against */
        m.samples++;
        out_of_range += !disp_metrics_in_range(x[i], w->range_lo, w->range_hi);
        float idf = w->inv_dt_f[k] / w->time_unit, idb = w->inv_dt_b[k] / w->time_unit;
        if (is_moving(w, i, thr, idf, idb)) {
            m.moving++;
            if (w->fwd[i].mask && w->bwd[i].mask) {
                /* The c_a residual of Sec. 4.3 with x in place of f (g's term
                 * as the solve's pg_acc, in arcmin/s). */
                double e = mid_accel_residual(mid_link_gather(w->fwd, w->nx, i, x), x[i],
                                              mid_link_gather(w->bwd, w->nx, i, x),
                                              mid_link_gather(w->fwd, w->nx, i, w->g), w->g[i],
                                              mid_link_gather(w->bwd, w->nx, i, w->g), idf, idb);
                mid2 += e * e;
                m.moving_measured++;
            }
            continue;
        }
        m.static_count++;
        double d = (double)x[i] - w->h[i];
        st2 += d * d;
        double gx = px + 1 < w->nx && !w->unknown[i + 1] ? ((double)x[i + 1] - w->h[i + 1]) - d : 0.0;
        double gy = py + 1 < w->ny && !w->unknown[i + w->nx] ? ((double)x[i + w->nx] - w->h[i + w->nx]) - d : 0.0;
        grad2 += gx * gx + gy * gy;
    }
    m.mid_distortion_jnd = m.moving_measured ? sqrt(mid2 / m.moving_measured) : 0.0;
    m.static_rms = m.static_count ? sqrt(st2 / m.static_count) : 0.0;
    m.static_grad_rms = m.static_count ? sqrt(grad2 / m.static_count) : 0.0;
    m.range_violation = m.samples ? (double)out_of_range / m.samples : 0.0;
    *out = m;
}

void disp_metrics_write_json(vg_json *j, const disp_metrics *m, double range_violation)
{
    vg_json_num(j, "mid_distortion_jnd", m->mid_distortion_jnd);
    vg_json_num(j, "range_violation", range_violation);
    vg_json_num(j, "static_rms", m->static_rms);
    vg_json_num(j, "static_grad_rms", m->static_grad_rms);
    vg_json_int(j, "moving_samples", m->moving_measured);
}

/* ------------------------------------------------------------------------- */
/* TEPE                                                                      */
/* ------------------------------------------------------------------------- */

vg_status disp_tepe_init(disp_tepe *t, size_t n, float same_surface)
{
    *t = (disp_tepe){.n = n, .same_surface = same_surface};
    for (int k = 0; k < 2; k++) {
        t->e[k] = malloc(n * sizeof(float));
        t->z[k] = malloc(n * sizeof(float));
        if (!t->e[k] || !t->z[k]) {
            disp_tepe_free(t);
            return VG_ERR_NOMEM;
        }
        for (size_t i = 0; i < n; i++)
            t->e[k][i] = t->z[k][i] = NAN;
    }
    return VG_OK;
}

static bool same_surface(float a, float b, float tol)
{
    return isfinite(a) && isfinite(b) && fabsf(a - b) <= tol * fminf(a, b);
}

void disp_tepe_frame(disp_tepe *t, const float *x, const float *g, const float *z, const uint8_t *unknown)
{
    float *e1 = t->e[0], *z1 = t->z[0], *e2 = t->e[1], *z2 = t->z[1]; /* frames t-1 and t-2 */
    for (size_t i = 0; i < t->n; i++) {
        bool known = !(unknown && unknown[i]) && isfinite(g[i]) && isfinite(x[i]);
        float e = known ? x[i] - g[i] : NAN, zi = known ? z[i] : NAN;
        if (t->frames >= 1 && isfinite(e) && isfinite(e1[i]) && same_surface(zi, z1[i], t->same_surface)) {
            t->sum_v += fabs((double)e - e1[i]);
            t->count_v++;
            if (t->frames >= 2 && isfinite(e2[i]) && same_surface(z1[i], z2[i], t->same_surface)) {
                t->sum_a += fabs((double)e - 2.0 * e1[i] + e2[i]);
                t->count_a++;
            }
        }
        e2[i] = e1[i], z2[i] = z1[i];
        e1[i] = e, z1[i] = zi;
    }
    t->frames++;
}

void disp_tepe_restart(disp_tepe *t)
{
    t->frames = 0;
}

double disp_tepe_velocity(const disp_tepe *t) { return t->count_v ? t->sum_v / (double)t->count_v : NAN; }
double disp_tepe_accel(const disp_tepe *t) { return t->count_a ? t->sum_a / (double)t->count_a : NAN; }

void disp_tepe_free(disp_tepe *t)
{
    for (int k = 0; k < 2; k++) {
        free(t->e[k]);
        free(t->z[k]);
    }
    *t = (disp_tepe){0};
}
