/* vergence — the method of `vergence optimize` on the frames that
 * offline_read.c reads: h per frame (the operator over the saliency, or
 * --h), the keyframe samples of g, h and depth and the keyframe flows
 * composed from the per-frame ones (pass B), the window solve (foresight
 * or causal), and the upsampling of the keyframe correction to every pixel
 * of every frame (pass C), which hands each frame to offline_write.c. */
#include "offline_internal.h"

#include <math.h>
#include <stdlib.h>

#include "core/log.h"
#include "core/srgb.h"
#include "disparity/mid_causal.h"
#include "disparity/mid_shared.h"

/* ------------------------------------------------------------------------- */
/* h                                                                         */
/* ------------------------------------------------------------------------- */

static float srgb_linear(uint8_t v) { return vg_srgb_to_linear(v / 255.0f); }

/* Saliency of frame t when none is given: the engine's formula
 * (disp_saliency_computed, docs/method.md section 3) from what the sequence
 * has: the colour contrast of --image to the frame's mean colour (0 without
 * it), the speed of the flow to the next frame (or keyframe) per keyframe
 * interval, and the nearness of the depth against its mean. */
static vg_status computed_saliency(offline_seq *s, int t, const float *g, float *out)
{
    const offline_desc *d = s->desc;
    size_t np = (size_t)s->width * s->height;
    float *z = s->saliency_scratch, *flow = s->saliency_scratch + np;
    uint8_t *rgb = NULL;
    bool next = t < d->last && !offline_is_cut(s, t + 1); /* the last frame of a shot: its flow to the previous */
    vg_status st = offline_read_depth(s, t, g, z);
    if (st == VG_OK)
        st = offline_read_flow(s, t, next, flow);
    if (st == VG_OK && s->has_image)
        st = offline_read_image(s, t, &rgb);
    if (st != VG_OK)
        return st;
    double zs = 0, mean[3] = {0, 0, 0};
    long known = 0;
    for (size_t i = 0; i < np; i++) {
        if (!isfinite(g[i]) || !(z[i] > 0))
            continue;
        zs += z[i];
        for (int k = 0; rgb && k < 3; k++)
            mean[k] += srgb_linear(rgb[3 * i + (size_t)k]);
        known++;
    }
    float zc = known ? (float)(zs / known) : 1.0f, m[3];
    for (int k = 0; k < 3; k++)
        m[k] = known ? (float)(mean[k] / known) : 0.0f;
    /* Flows to the keyframe span the frames to it; frame flows one. */
    int span = abs(offline_flow_target(s, t, next) - t);
    float per_interval = (float)s->keyframe_stride / (float)(span > 0 ? span : 1) / (float)s->width;
    for (size_t i = 0; i < np; i++) {
        if (!isfinite(g[i]) || !(z[i] > 0)) {
            out[i] = 0.0f;
            continue;
        }
        float de = rgb ? disp_delta_e(srgb_linear(rgb[3 * i]), srgb_linear(rgb[3 * i + 1]),
                                      srgb_linear(rgb[3 * i + 2]), m[0], m[1], m[2])
                       : 0.0f;
        float speed = sqrtf(flow[2 * i] * flow[2 * i] + flow[2 * i + 1] * flow[2 * i + 1]) * per_interval;
        if (!isfinite(speed)) /* computed: a row with no consistent pixel (flow_fill_occluded) */
            speed = 0.0f;
        out[i] = disp_saliency_computed(de, speed, z[i], zc);
    }
    free(rgb);
    return VG_OK;
}

/* h of frame t: from --h, or the operator (called in frame order). The
 * saliency it used stays in s->saliency, for the preview. */
static vg_status frame_h(offline_seq *s, int t, const float *g, float *h)
{
    if (s->has_h)
        return offline_read_h(s, t, h);
    const float *sal = NULL;
    if (s->has_saliency || s->compute_saliency) {
        vg_status st = s->has_saliency ? offline_read_saliency(s, t, s->saliency)
                                       : computed_saliency(s, t, g, s->saliency);
        if (st != VG_OK)
            return st;
        sal = s->saliency;
    }
    if (s->desc->ema) {
        offline_ema_apply(s, t, g, h);
        return VG_OK;
    }
    disp_operator_apply(s->op, g, sal, s->width * s->height, h, s->pool);
    return VG_OK;
}

/* The operator's domain is the range of g over the whole sequence (pass A
 * measured it); its target range is the one every map is drawn in. */
vg_status offline_operator_create(offline_seq *s)
{
    const offline_desc *d = s->desc;
    vg_status st = disp_operator_create(&(disp_operator_desc){.kind = d->op, .preset = d->preset,
                                                              .screen_vergence = s->display.screen_vergence,
                                                              .range = d->target_range, .in_min = s->g_min,
                                                              .in_max = s->g_max > s->g_min ? s->g_max
                                                                                            : s->g_min + 1e-3,
                                                              .frame_seconds = 1.0 / s->fps},
                                        &s->op);
    if (st == VG_OK)
        disp_operator_range(s->op, &s->range_lo, &s->range_hi);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Pass B                                                                    */
/* ------------------------------------------------------------------------- */

/* Keyframe positions tracked through the per-frame flows from frame a to b
 * (forward when b > a), as coarse-pixel flows of the window. */
static vg_status keyframe_flow(offline_seq *s, int a, int b, float *flow_c, float *scratch, float *pos)
{
    int nc = s->grid.nx * s->grid.ny;
    disp_grid_positions(&s->grid, pos);
    /* Flows to the keyframes hold the whole interval in one step. */
    for (int t = a; t != b; t = s->flow_direct ? b : t + (b > a ? 1 : -1)) {
        vg_status st = offline_read_flow(s, t, b > a, scratch);
        if (st != VG_OK)
            return st;
        disp_flow_advect(scratch, s->width, s->height, pos, nc);
    }
    float half = (float)(s->grid.stride / 2), inv = 1.0f / (float)s->grid.stride;
    for (int q = 0; q < nc; q++) {
        /* Coarse coordinates of the uniform grid; lost points leave the frame. */
        bool lost = isnan(pos[2 * q]);
        flow_c[2 * q] = lost ? 1e6f : (pos[2 * q] - half) * inv - (float)(q % s->grid.nx);
        flow_c[2 * q + 1] = lost ? 1e6f : (pos[2 * q + 1] - half) * inv - (float)(q / s->grid.nx);
    }
    return VG_OK;
}

/* B: h per frame, keyframe samples and keyframe flows into the window. */
static vg_status pass_keyframes(offline_seq *s, mid_window *w, float *g, float *h, float *z, float *scratch,
                                float *pos)
{
    /* Only lang-smoothed has state that needs the frames between keyframes. */
    bool every_frame = !s->has_h && s->desc->op == DISP_OPERATOR_LANG_SMOOTHED;
    const int *key = s->keyframe_numbers;
    disp_operator_reset(s->op);
    for (int k = 0; k < s->keyframes; k++) {
        vg_progress("optimize: keyframes", k, s->keyframes);
        int t0 = key[k], t_end = k + 1 < s->keyframes ? key[k + 1] : t0 + 1;
        if (offline_is_cut(s, t0)) /* a new shot: no state from the last */
            disp_operator_reset(s->op);
        for (int t = t0; t < t_end; t++) {
            if (t != t0 && !every_frame)
                continue;
            vg_status st = offline_read_g(s, t, g);
            if (st == VG_OK)
                st = frame_h(s, t, g, h);
            if (st == VG_OK && t == t0)
                st = offline_read_depth(s, t, g, z);
            if (st != VG_OK)
                return st;
            if (t == t0) {
                size_t o = (size_t)k * w->ns;
                disp_grid_sample(&s->grid, g, 1, w->g + o);
                disp_grid_sample(&s->grid, h, 1, w->h + o);
                disp_grid_sample(&s->grid, z, 1, w->depth + o);
                if (s->has_ids) { /* z is free again */
                    vg_status st = offline_read_ids(s, t, z);
                    if (st != VG_OK)
                        return st;
                    disp_grid_sample(&s->grid, z, 1, w->id + o);
                }
                /* Samples on unknown g: out of the costs and the metrics. */
                for (int q = 0; q < w->ns; q++)
                    w->unknown[o + q] = s->unknown[(size_t)disp_grid_py(&s->grid, q / s->grid.nx) * s->width +
                                                   disp_grid_px(&s->grid, q % s->grid.nx)];
            }
        }
        if (k + 1 < s->keyframes && offline_is_cut(s, key[k + 1])) {
            /* Across a cut every sample is lost: no term links the shots. */
            w->dt[k] = (float)((key[k + 1] - t0) / s->fps);
            for (int q = 0; q < 2 * w->ns; q++)
                w->flow_fwd[(size_t)2 * k * w->ns + q] = w->flow_bwd[(size_t)2 * (k + 1) * w->ns + q] = 1e6f;
        } else if (k + 1 < s->keyframes) {
            w->dt[k] = (float)((key[k + 1] - t0) / s->fps);
            vg_status st = keyframe_flow(s, t0, key[k + 1], w->flow_fwd + (size_t)2 * k * w->ns, scratch, pos);
            if (st == VG_OK)
                st = keyframe_flow(s, key[k + 1], t0, w->flow_bwd + (size_t)2 * (k + 1) * w->ns, scratch, pos);
            if (st != VG_OK)
                return st;
        }
    }
    vg_progress("optimize: keyframes", s->keyframes, s->keyframes);
    return VG_OK;
}

/* The solver's window over the keyframes, filled by pass B and built; *w
 * (mid_window_destroy) is set as soon as it exists, also on failure. */
vg_status offline_window_build(offline_seq *s, mid_window **w)
{
    const offline_desc *d = s->desc;
    size_t np = (size_t)s->width * s->height;
    float *g = malloc(np * sizeof(float)), *h = malloc(np * sizeof(float)), *z = malloc(np * sizeof(float));
    s->saliency = malloc(np * sizeof(float));
    s->compute_saliency = !s->has_saliency && !s->has_h && !d->uniform_saliency &&
                          (d->op == DISP_OPERATOR_LANG || d->op == DISP_OPERATOR_LANG_SMOOTHED);
    s->saliency_scratch = s->compute_saliency ? malloc(3 * np * sizeof(float)) : NULL;
    float *scratch = malloc(2 * np * sizeof(float));
    float *pos = malloc(2 * (size_t)s->grid.nx * s->grid.ny * sizeof(float));
    vg_status st = VG_OK;
    if (!g || !h || !z || !s->saliency || !scratch || !pos || (s->compute_saliency && !s->saliency_scratch)) {
        st = VG_ERR_NOMEM;
        goto done;
    }
    float edge_scale = d->edge_norm == OFFLINE_EDGE_ARCMIN  ? 1.0f
                       : d->edge_norm == OFFLINE_EDGE_PIXEL ? 1.0f / (float)s->grid.stride
                                                            : 0.0f;
    float keyframe_seconds = (float)(s->keyframe_stride / s->fps);
    if ((st = mid_window_create(&(mid_window_desc){.width = s->grid.nx, .height = s->grid.ny,
                                                   .keyframes = s->keyframes, .range_lo = (float)s->range_lo,
                                                   .range_hi = (float)s->range_hi,
                                                   .occlusion_tolerance = d->occlusion_tolerance,
                                                   .edge_scale = edge_scale,
                                                   .time_unit = d->velocity_per_keyframe ? keyframe_seconds : 0.0f},
                                w)) == VG_OK &&
        (st = pass_keyframes(s, *w, g, h, z, scratch, pos)) == VG_OK)
        st = mid_window_build(*w, s->pool);
done:
    free(g); free(h); free(z); free(scratch); free(pos);
    return st;
}

/* ------------------------------------------------------------------------- */
/* The solve                                                                 */
/* ------------------------------------------------------------------------- */

/* f at the keyframe samples (f_sol, the window's n): one window over the
 * whole sequence, or with desc.causal the engine's sliding window whose
 * future is predicted from the past (its f before the gate in s->f_ungated). */
vg_status offline_solve(offline_seq *s, mid_window *w, float *f_sol, mid_solve_stats *ss)
{
    const offline_desc *d = s->desc;
    vg_info("optimize: %d frames of %dx%d, %d keyframes of %dx%d, target range [%.2f, %.2f] arcmin, %d threads",
            s->frames, s->width, s->height, s->keyframes, s->grid.nx, s->grid.ny, s->range_lo, s->range_hi,
            vg_pool_threads(s->pool));
    mid_solve_desc sd = {.solver = d->solver, .iterations = d->iterations, .cg_iterations = d->cg_iterations,
                         .weights = d->weights, .pool = s->pool};
    vg_status st;
    if (d->causal) {
        mid_causal_stats cs = {0};
        mid_window_split(MID_WINDOW_SECONDS, s->keyframe_stride / s->fps, MID_WINDOW_FUTURE, &s->causal_past,
                         &s->causal_future);
        if (!(s->f_ungated = malloc((size_t)w->n * sizeof(float))))
            return VG_ERR_NOMEM;
        if ((st = mid_causal_solve(w, &(mid_causal_desc){.past = s->causal_past, .future = s->causal_future,
                                                         .solve = sd,
                                                         .keyframe_seconds = (float)(s->keyframe_stride / s->fps),
                                                         .gate = true, .ungated = s->f_ungated},
                                   f_sol, &cs)) != VG_OK)
            return st;
        s->causal_windows = cs.windows;
        *ss = (mid_solve_stats){.ms = cs.ms, .cost_initial = cs.cost_initial, .cost_final = cs.cost_final};
        vg_info("optimize: causal: %d windows of %d keyframes behind and %d predicted ahead solved in %.1f ms",
                cs.windows, s->causal_past, s->causal_future, cs.ms);
    } else {
        if ((st = mid_solve(w, &sd, f_sol, ss)) != VG_OK)
            return st;
        vg_info("optimize: solved in %.1f ms: cost %.5g -> %.5g (%d iterations, %d CG steps)", ss->ms,
                ss->cost_initial, ss->cost_final, ss->iterations, ss->cg_steps);
    }
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Pass C                                                                    */
/* ------------------------------------------------------------------------- */

/* C: upsample the keyframe correction to every frame; each frame goes to
 * offline_write_frame (f, the pair, the videos, previews and slices). */
vg_status offline_upsample(offline_seq *s, const mid_window *w, const float *f_sol, offline_outputs *o)
{
    const offline_desc *d = s->desc;
    size_t np = (size_t)s->width * s->height, nf2 = 2 * np;
    int nc = w->ns;
    float *g = malloc(np * sizeof(float)), *h = malloc(np * sizeof(float)), *z = malloc(np * sizeof(float));
    float *f = malloc(np * sizeof(float)), *ratio = malloc((size_t)w->n * sizeof(float));
    float *slope = malloc((size_t)w->n * sizeof(float));
    float *zc = malloc(nc * sizeof(float)), *rt = malloc(nc * sizeof(float)), *idc = malloc(nc * sizeof(float));
    float *gc = malloc(nc * sizeof(float)), *hc = malloc(nc * sizeof(float));
    float *pos0 = malloc(2 * (size_t)nc * sizeof(float)), *pos1 = malloc(2 * (size_t)nc * sizeof(float));
    float *prev = malloc((size_t)s->keyframe_stride * nf2 * sizeof(float));
    float *next = malloc((size_t)s->keyframe_stride * nf2 * sizeof(float));
    vg_status st = VG_OK;
    if (!g || !h || !z || !f || !ratio || !slope || !zc || !rt || !idc || !gc || !hc || !pos0 || !pos1 || !prev ||
        !next) {
        st = VG_ERR_NOMEM;
        goto done;
    }
    if ((st = offline_videos_open(s, o)) != VG_OK)
        goto done;
    /* Fig. 4: the correction is the ratio f / g (vergence is never 0),
     * applied to each frame's g (mid_ratio_to_h); under the causal gate
     * f / h, applied to h, so that a closed gate shows h at every frame. */
    bool of_h = d->causal;
    for (int i = 0; i < w->n; i++)
        ratio[i] = f_sol[i] / (of_h ? w->h[i] : w->g[i]);
    mid_window_ratio_slopes(w, ratio, slope);
    disp_upsample_desc ud = {.grid = s->grid, .occlusion_tolerance = d->occlusion_tolerance,
                             .range_lo = (float)s->range_lo, .range_hi = (float)s->range_hi};
    const int *key = s->keyframe_numbers;
    disp_operator_reset(s->op);
    for (int k = 0; k < s->keyframes && st == VG_OK; k++) {
        int t0 = key[k], t1 = k + 1 < s->keyframes ? key[k + 1] : t0;
        int t_end = k + 1 < s->keyframes ? t1 : t0 + 1;
        /* The segment's per-frame flows, held for the tracking of each frame
         * (with flows to the keyframes, each frame's own). */
        for (int t = t0 + 1; t < t1 && st == VG_OK; t++) {
            st = offline_read_flow(s, t, false, prev + (size_t)(t - t0) * nf2);
            if (st == VG_OK)
                st = offline_read_flow(s, t, true, next + (size_t)(t - t0) * nf2);
        }
        size_t ko = (size_t)k * nc;
        disp_keyframe_view k0 = {pos0, ratio + ko, slope + ko, w->depth + ko, w->id + ko, w->flow_fwd + 2 * ko,
                                 of_h ? NULL : w->g + ko, of_h ? NULL : w->h + ko};
        disp_keyframe_view k1 = {pos1, ratio + ko + nc, slope + ko + nc, w->depth + ko + nc, w->id + ko + nc,
                                 w->flow_bwd + 2 * (ko + nc), of_h ? NULL : w->g + ko + nc,
                                 of_h ? NULL : w->h + ko + nc};
        bool has1 = k + 1 < s->keyframes;
        float span = has1 && w->inv_dt_f[k] > 0 ? 1.0f / w->inv_dt_f[k] : 0.0f;
        if (offline_is_cut(s, t0))
            disp_operator_reset(s->op);
        for (int t = t0; t < t_end && st == VG_OK; t++) {
            vg_progress("optimize: writing", t - d->first, s->frames);
            st = offline_read_g(s, t, g);
            if (st == VG_OK)
                st = frame_h(s, t, g, h);
            if (st == VG_OK)
                st = offline_read_depth(s, t, g, z);
            if (st != VG_OK)
                break;
            disp_grid_sample(&s->grid, z, 1, zc);
            disp_grid_sample(&s->grid, g, 1, gc);
            disp_grid_sample(&s->grid, h, 1, hc);
            if (s->has_ids) { /* f is free until the upsampling */
                if ((st = offline_read_ids(s, t, f)) != VG_OK)
                    break;
                disp_grid_sample(&s->grid, f, 1, idc);
            }
            /* Where frame t's coarse samples are in the two keyframes. */
            bool direct = s->flow_direct;
            disp_grid_positions(&s->grid, pos0);
            for (int m = t; m > t0; m = direct ? t0 : m - 1)
                disp_flow_advect(prev + (size_t)(m - t0) * nf2, s->width, s->height, pos0, nc);
            disp_grid_positions(&s->grid, pos1);
            for (int m = t; m < t1 && t > t0; m = direct ? t1 : m + 1) /* at a keyframe only k0 counts */
                disp_flow_advect(next + (size_t)(m - t0) * nf2, s->width, s->height, pos1, nc);
            float tau = t1 > t0 ? (float)(t - t0) / (float)(t1 - t0) : 0.0f;
            disp_upsample_temporal(&ud, tau, span, zc, s->has_ids ? idc : NULL, of_h ? NULL : gc, of_h ? NULL : hc,
                                   &k0, has1 ? &k1 : NULL, rt, s->pool);
            disp_upsample_spatial(&ud, h, rt, f, s->pool);
            /* A result is a vergence at every known pixel: never a map of
             * NaN or zeros written as if it were one (issue 44). */
            for (size_t i = 0; i < np; i++)
                if (!s->unknown[i] && !(f[i] > 0 && f[i] < OFFLINE_VERGENCE_MAX)) {
                    vg_error("optimize: f of frame %d is %g at pixel (%d, %d) (g %g, h %g arcmin): the solver failed "
                             "on these inputs; nothing more is written", t, f[i], (int)(i % (size_t)s->width),
                             (int)(i / (size_t)s->width), g[i], h[i]);
                    st = VG_ERR_UNSUPPORTED;
                    break;
                }
            if (st != VG_OK)
                break;
            if (t == t0) /* the written f at the keyframes, for its metrics */
                disp_grid_sample(&s->grid, f, 1, o->f_key + (size_t)k * nc);
            st = offline_write_frame(s, t, g, h, f, z, o);
        }
    }
    if (st == VG_OK)
        vg_progress("optimize: writing", s->frames, s->frames);
done:
    offline_videos_close(o);
    free(g); free(h); free(z); free(f); free(ratio); free(slope); free(zc); free(rt); free(idc); free(gc); free(hc);
    free(pos0); free(pos1); free(prev); free(next);
    return st;
}
