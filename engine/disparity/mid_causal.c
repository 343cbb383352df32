/* vergence — the causal window on the CPU: see mid_causal.h. */
#include "mid_causal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

/* Bilinear lookup of a keyframe plane at coarse position (x, y), clamped to
 * the grid. */
static float lookup(const float *v, int nx, int ny, float x, float y)
{
    x = fminf(fmaxf(x, 0.0f), (float)(nx - 1));
    y = fminf(fmaxf(y, 0.0f), (float)(ny - 1));
    int x0 = (int)x, y0 = (int)y;
    int x1 = x0 + 1 < nx ? x0 + 1 : x0, y1 = y0 + 1 < ny ? y0 + 1 : y0;
    float fx = x - (float)x0, fy = y - (float)y0;
    float a = v[y0 * nx + x0] + fx * (v[y0 * nx + x1] - v[y0 * nx + x0]);
    float b = v[y1 * nx + x0] + fx * (v[y1 * nx + x1] - v[y1 * nx + x0]);
    return a + fy * (b - a);
}

static int nearest(int nx, int ny, float x, float y)
{
    int xi = (int)lroundf(fminf(fmaxf(x, 0.0f), (float)(nx - 1)));
    int yi = (int)lroundf(fminf(fmaxf(y, 0.0f), (float)(ny - 1)));
    return yi * nx + xi;
}

/* Keyframe k of obs n intervals on (forward splat and hole fill) into w's
 * samples from od, from the per-sample velocities and rates. */
static void predict_step(const mid_window *obs, size_t o, const float *ux, const float *uy, const float *rg,
                         const float *rh, const float *rz, float *zb, int *src, float n, mid_window *w, size_t od)
{
    int nx = obs->nx, ny = obs->ny, ns = obs->ns;
    for (int i = 0; i < ns; i++) {
        src[i] = -1;
        zb[i] = INFINITY;
    }
    for (int i = 0; i < ns; i++) {
        int x = (int)lroundf((float)(i % nx) + n * ux[i]), y = (int)lroundf((float)(i / nx) + n * uy[i]);
        if (x < 0 || y < 0 || x >= nx || y >= ny)
            continue;
        float z = fmaxf(obs->depth[o + i] + n * rz[i], 0.1f * obs->depth[o + i]);
        if (z < zb[y * nx + x]) {
            zb[y * nx + x] = z;
            src[y * nx + x] = i;
        }
    }
    /* A grid sample nothing landed on (a disocclusion, a gap in a surface
     * that grows) takes the farther of the nearest landed samples left and
     * right of it in its row, as image warping fills holes (warp/image_warp.h). */
    for (int y = 0; y < ny; y++) {
        int *row = src + y * nx;
        const float *zr = zb + y * nx;
        for (int x = 0, l = -1; x < nx; x++) {
            if (row[x] >= 0 && isfinite(zr[x])) {
                l = x;
                continue;
            }
            int r = x + 1;
            while (r < nx && row[r] < 0)
                r++;
            int pick = l >= 0 && (r >= nx || zr[l] >= zr[r]) ? l : r < nx ? r : -1;
            row[x] = pick >= 0 ? row[pick] : y * nx + x;
        }
    }
    for (int i = 0; i < ns; i++) {
        int j = src[i];
        w->g[od + i] = obs->g[o + j] + n * rg[j];
        w->h[od + i] = fminf(fmaxf(obs->h[o + j] + n * rh[j], obs->range_lo), obs->range_hi);
        w->depth[od + i] = fmaxf(obs->depth[o + j] + n * rz[j], 0.1f * obs->depth[o + j]);
        w->id[od + i] = obs->id[o + j];
        w->unknown[od + i] = obs->unknown[o + j];
        w->flow_fwd[2 * (od + i)] = ux[j];
        w->flow_fwd[2 * (od + i) + 1] = uy[j];
        w->flow_bwd[2 * (od + i)] = -ux[j];
        w->flow_bwd[2 * (od + i) + 1] = -uy[j];
    }
}

vg_status mid_causal_predict(const mid_window *obs, int k, int count, mid_window *w, int dst)
{
    int nx = obs->nx, ny = obs->ny, ns = obs->ns;
    size_t o = (size_t)k * ns, op = (size_t)(k - 1) * ns;
    float *rate = malloc((size_t)6 * ns * sizeof(float) + (size_t)ns * sizeof(int));
    if (!rate)
        return VG_ERR_NOMEM;
    float *ux = rate, *uy = rate + ns, *rg = rate + 2 * ns, *rh = rate + 3 * ns, *rz = rate + 4 * ns;
    float *zb = rate + 5 * ns;
    int *src = (int *)(rate + 6 * ns);
    /* Per sample of k: the image velocity u = -(flow to k - 1) and the rates
     * of g, h and depth per interval, where the sample's track to k - 1
     * holds (inside, known, the same instance, or without ids the depth
     * test); elsewhere it is held still. */
    for (int i = 0; i < ns; i++) {
        ux[i] = uy[i] = rg[i] = rh[i] = rz[i] = 0.0f;
        if (k == 0 || obs->unknown[o + i])
            continue;
        float bx = obs->flow_bwd[2 * (o + i)], by = obs->flow_bwd[2 * (o + i) + 1];
        float x = (float)(i % nx) + bx, y = (float)(i / nx) + by;
        if (!(x >= 0.0f && y >= 0.0f && x <= (float)(nx - 1) && y <= (float)(ny - 1)))
            continue;
        int j = nearest(nx, ny, x, y);
        float z = obs->depth[o + i], zp = lookup(obs->depth + op, nx, ny, x, y);
        bool same = obs->id[o + i] != 0.0f || obs->id[op + j] != 0.0f
                        ? obs->id[op + j] == obs->id[o + i]
                        : fabsf(zp - z) <= obs->occlusion_tolerance * fminf(z, zp);
        if (!same || obs->unknown[op + j])
            continue;
        ux[i] = -bx;
        uy[i] = -by;
        rg[i] = obs->g[o + i] - lookup(obs->g + op, nx, ny, x, y);
        rh[i] = obs->h[o + i] - lookup(obs->h + op, nx, ny, x, y);
        rz[i] = z - zp;
    }
    /* Forward: each sample of k moves n velocities on, to the nearest grid
     * sample (the nearest surface wins). A backward lookup (the velocity at
     * the target) would never move a surface into the background ahead of
     * it. */
    for (int step = 1; step <= count; step++)
        predict_step(obs, o, ux, uy, rg, rh, rz, zb, src, (float)step, w, (size_t)(dst + step - 1) * ns);
    free(rate);
    return VG_OK;
}

/* Keyframe j of `all` into keyframe dst of w as observed. */
static void copy_keyframe(const mid_window *all, int j, mid_window *w, int dst)
{
    size_t ns = (size_t)all->ns, o = (size_t)j * ns, od = (size_t)dst * ns;
    memcpy(w->g + od, all->g + o, ns * sizeof(float));
    memcpy(w->h + od, all->h + o, ns * sizeof(float));
    memcpy(w->depth + od, all->depth + o, ns * sizeof(float));
    memcpy(w->id + od, all->id + o, ns * sizeof(float));
    memcpy(w->unknown + od, all->unknown + o, ns);
    memcpy(w->flow_fwd + 2 * od, all->flow_fwd + 2 * o, 2 * ns * sizeof(float));
    memcpy(w->flow_bwd + 2 * od, all->flow_bwd + 2 * o, 2 * ns * sizeof(float));
}

/* The gate's sums over keyframe m of w (mid_shared.h MID_GATE_*): the
 * squared c_a residuals of the candidate x (window-indexed, at m - 1 ..
 * m + 1) and of h; samples without both links count 0, as in the MID
 * metric. */
static void gate_sums(const mid_window *w, int m, const float *x, double *sc, double *sh)
{
    float idf = w->inv_dt_f[m] / w->time_unit, idb = w->inv_dt_b[m] / w->time_unit;
    *sc = *sh = 0.0;
    for (int q = 0; q < w->ns; q++) {
        int i = m * w->ns + q;
        if (!w->fwd[i].mask || !w->bwd[i].mask)
            continue;
        float ga = mid_link_gather(w->fwd, w->nx, i, w->g), gb = mid_link_gather(w->bwd, w->nx, i, w->g);
        float ec = mid_accel_residual(mid_link_gather(w->fwd, w->nx, i, x), x[i], mid_link_gather(w->bwd, w->nx, i, x),
                                      ga, w->g[i], gb, idf, idb);
        float eh = mid_accel_residual(mid_link_gather(w->fwd, w->nx, i, w->h), w->h[i],
                                      mid_link_gather(w->bwd, w->nx, i, w->h), ga, w->g[i], gb, idf, idb);
        *sc += (double)ec * ec;
        *sh += (double)eh * eh;
    }
}

vg_status mid_causal_solve(const mid_window *all, const mid_causal_desc *d, float *f, mid_causal_stats *stats)
{
    int nt = all->nt, ns = all->ns, past = d->past > 0 ? d->past : 0, future = d->future;
    if (future < 2) {
        vg_error("causal window: %d keyframes ahead (at least 2: the solve runs one interval ahead)", future);
        return VG_ERR_ARG;
    }
    int cap = past + future + 1;
    float *ratio = malloc((size_t)all->n * sizeof(float) * 2);
    float *sol = malloc((size_t)cap * ns * sizeof(float) * 4);
    if (!ratio || !sol) {
        free(ratio);
        free(sol);
        return VG_ERR_NOMEM;
    }
    /* cand: the ratio each keyframe's solve gave, before the gate (the
     * GPU's third plane of published ratios); xw: the candidate f in the
     * window's indexing. */
    float *prev = sol + (size_t)cap * ns, *init = prev + (size_t)cap * ns, *xw = init + (size_t)cap * ns;
    float *cand = ratio + all->n;
    float gate_c = 0.0f, gate_h = 0.0f, gain = 0.0f;
    int prev_first = 0, prev_nt = 0;
    mid_causal_stats s = {0};
    vg_status st = VG_OK;
    for (int k = 0; k + 2 < nt || (k == 0 && nt > 0); k++) {
        vg_progress("optimize: causal windows", k, nt > 2 ? nt - 2 : 1);
        int first = k - past > 0 ? k - past : 0, wnt = k + future - first + 1;
        mid_window *w = NULL;
        st = mid_window_create(&(mid_window_desc){.width = all->nx, .height = all->ny, .keyframes = wnt,
                                                  .range_lo = all->range_lo, .range_hi = all->range_hi,
                                                  .occlusion_tolerance = all->occlusion_tolerance,
                                                  .flow_tolerance = all->flow_tolerance,
                                                  .edge_scale = all->edge_scale, .time_unit = all->time_unit},
                               &w);
        if (st != VG_OK)
            break;
        float dt_pred = d->keyframe_seconds > 0 ? d->keyframe_seconds
                        : nt > 1                ? all->dt[nt - 2]
                                                : (float)MID_KEYFRAME_SECONDS;
        for (int j = first; j <= k + future; j++) {
            int m = j - first;
            if (j <= k)
                copy_keyframe(all, j, w, m);
            if (m + 1 < wnt) /* the keyframes' times are known ahead; their content is not */
                w->dt[m] = j + 1 < nt ? all->dt[j] : dt_pred;
        }
        st = mid_causal_predict(all, k, future, w, k + 1 - first);
        /* Keyframe k's flow to k + 1 is a prediction too: its velocity. */
        size_t ok = (size_t)(k - first) * ns;
        for (size_t i = 0; i < (size_t)ns; i++) {
            w->flow_fwd[2 * (ok + i)] = k > 0 ? -all->flow_bwd[2 * ((size_t)k * ns + i)] : 0.0f;
            w->flow_fwd[2 * (ok + i) + 1] = k > 0 ? -all->flow_bwd[2 * ((size_t)k * ns + i) + 1] : 0.0f;
        }
        if (st == VG_OK)
            st = mid_window_build(w, d->solve.pool);
        if (st == VG_OK) {
            /* Warm start: the last window's solution where it has the keyframe. */
            for (int m = 0; m < wnt; m++) {
                int src = first + m - prev_first;
                const float *from = src >= 0 && src < prev_nt ? prev + (size_t)src * ns : w->h + (size_t)m * ns;
                memcpy(init + (size_t)m * ns, from, (size_t)ns * sizeof(float));
            }
            mid_solve_desc sd = d->solve;
            sd.f_init = prev_nt ? init : NULL;
            if (prev_nt && !sd.iterations && sd.solver != MID_SOLVER_DESCENT)
                sd.iterations = (int)MID_GN_WARM_ITERATIONS;
            mid_solve_stats ss = {0};
            st = mid_solve(w, &sd, sol, &ss);
            s.windows++;
            s.ms += ss.ms;
            s.cost_initial = ss.cost_initial;
            s.cost_final = ss.cost_final;
        }
        if (st == VG_OK && d->gate) {
            /* The gate (mid_shared.h MID_GATE_*), as the GPU's publish.gate:
             * keyframe k - 1 is realized once k - 2 is in the window. */
            int m = k - 1 - first;
            if (m >= 1) {
                for (int t = m - 1; t <= m + 1; t++)
                    for (int i = 0; i < ns; i++) {
                        size_t b = (size_t)t * ns + i;
                        xw[b] = w->h[b] * cand[(size_t)(first + t) * ns + i];
                    }
                double sc, sh;
                gate_sums(w, m, xw, &sc, &sh);
                gate_c = MID_GATE_DECAY * gate_c + (float)sc;
                gate_h = MID_GATE_DECAY * gate_h + (float)sh;
                gain = mid_gate_gain(gate_c, gate_h, (float)ns, gain);
            } else {
                gate_c = gate_h = gain = 0.0f;
            }
        }
        if (st == VG_OK) {
            /* Publish k + 2 (the first window: k .. k + 2). */
            for (int j = k == 0 ? 0 : k + 2; j <= k + 2 && j < nt; j++) {
                size_t om = (size_t)(j - first) * ns, oj = (size_t)j * ns;
                for (int i = 0; i < ns; i++) {
                    float r = w->h[om + i] != 0.0f ? sol[om + i] / w->h[om + i] : 1.0f;
                    cand[oj + i] = r;
                    ratio[oj + i] = d->gate ? 1.0f + gain * (r - 1.0f) : r;
                }
            }
            memcpy(prev, sol, (size_t)wnt * ns * sizeof(float));
            prev_first = first;
            prev_nt = wnt;
        }
        mid_window_destroy(w);
        if (st != VG_OK)
            break;
    }
    vg_progress("optimize: causal windows", 1, 1);
    if (st == VG_OK)
        for (int i = 0; i < all->n; i++) {
            f[i] = fminf(fmaxf(all->h[i] * ratio[i], all->range_lo), all->range_hi);
            if (d->ungated)
                d->ungated[i] = fminf(fmaxf(all->h[i] * cand[i], all->range_lo), all->range_hi);
        }
    free(ratio);
    free(sol);
    if (stats)
        *stats = s;
    return st;
}
