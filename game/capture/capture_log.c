/* vergence — the frame loop of captures and what it records. */
#include "capture_log.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/stats.h"

vg_status capture_log_begin(capture_log *log, const frame *f, const capture_log_desc *desc)
{
    *log = (capture_log){.capacity = desc->frames, .warp_every_frame = desc->warp};
    size_t n = (size_t)(desc->frames > 0 ? desc->frames : 1);
    log->pass_ms = malloc(n * RG_MAX_PASSES * sizeof(double));
    log->cpu_ms = calloc(n, sizeof(double));
    log->cameras = calloc(n, sizeof(vg_camera));
    log->times = calloc(n, sizeof(frame_times));
    log->shadow_m = calloc(3 * (size_t)n, sizeof(double));
    log->shadow_px = calloc(n, sizeof(double));
    if (!log->pass_ms || !log->cpu_ms || !log->cameras || !log->times || !log->shadow_m || !log->shadow_px)
        return VG_ERR_NOMEM;
    for (size_t i = 0; i < n * RG_MAX_PASSES; i++)
        log->pass_ms[i] = NAN;
    frame_get_info(f, &log->info);
    log->shadow_map_px = frame_get_desc(f)->shadow_size;
    return desc->science && log->info.disparity ? science_metrics_create_for(f, &log->science) : VG_OK;
}

/* How many screen pixels a shadow texel covers where it lands: the texel's
 * world size (of the cascade that shades the pixel: the near one below the
 * split depth) over a pixel's at each geometry pixel's depth (a texel of
 * several pixels shows the shadow map's staircase along shadow edges through
 * the 3x3 filter), the median over the image; NAN without depth. */
static double shadow_texel_px(const frame_outputs *fo, const vg_camera *cam, uint32_t w, uint32_t h)
{
    if (!fo->depth || !fo->ids || !(fo->shadow_texel_m[0] > 0.0f))
        return NAN;
    /* A pixel's world size at depth 1 (orthographic: at every depth). */
    double px_at_1m = cam->orthographic ? 2.0 * cam->ymag / h : 2.0 * tan(0.5 * cam->yfov) / h;
    double *v = malloc((size_t)w * h * sizeof(double));
    if (!v)
        return NAN;
    size_t n = 0;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        double z = cam->orthographic ? 1.0 : fo->depth[i];
        if (fo->ids[i] && z > 0.0 && isfinite(z))
            v[n++] = fo->shadow_texel_m[z < fo->shadow_split_m] / (px_at_1m * z);
    }
    double m = vg_median(v, n, 1);
    free(v);
    return m;
}

/* The column of a pass: its name's, added when first seen. */
static uint32_t pass_slot(capture_log *log, const char *name)
{
    for (uint32_t p = 0; p < log->pass_count; p++)
        if (!strcmp(log->pass_names[p], name))
            return p;
    if (log->pass_count >= RG_MAX_PASSES)
        return RG_MAX_PASSES;
    snprintf(log->pass_names[log->pass_count], CAPTURE_PASS_NAME, "%s", name);
    return log->pass_count++;
}

vg_status capture_log_render(capture_log *log, frame *f, long index)
{
    frame_time_passes(f, true); /* capture.json's per-pass ms */
    double t0 = vg_now_ms();
    vg_status st = frame_render(f, index);
    if (st != VG_OK || log->frames >= log->capacity)
        return st;
    int i = log->frames++;
    log->cpu_ms[i] = vg_now_ms() - t0;
    const char *names[RG_MAX_PASSES];
    double ms[RG_MAX_PASSES];
    uint32_t n = frame_pass_timings(f, names, ms, RG_MAX_PASSES);
    for (uint32_t p = 0; p < n; p++) {
        uint32_t slot = pass_slot(log, names[p]);
        if (slot < RG_MAX_PASSES)
            log->pass_ms[(size_t)i * RG_MAX_PASSES + slot] = ms[p];
    }
    log->cameras[i] = *frame_get_camera(f);
    log->times[i] = *frame_get_times(f);
    const frame_outputs *fo = frame_get_outputs(f);
    const frame_desc *d = frame_get_desc(f);
    log->shadow_m[3 * i] = fo->shadow_texel_m[0];
    log->shadow_m[3 * i + 1] = fo->shadow_texel_m[1];
    log->shadow_m[3 * i + 2] = fo->shadow_split_m;
    log->shadow_px[i] = shadow_texel_px(fo, &log->cameras[i], d->width, d->height);
    if (log->warp_every_frame && d->stereo != FRAME_STEREO_OFF)
        st = warp_metrics_add(&log->warp, fo, d->width, d->height);
    if (st == VG_OK && log->science && fo->h && fo->f)
        science_metrics_add(log->science, index, fo->g, fo->h, fo->f, fo->depth, fo->motion, fo->ids);
    return st;
}

vg_status capture_log_finish(capture_log *log)
{
    if (log->warp_every_frame)
        warp_metrics_finish(&log->warp);
    return log->science ? science_metrics_finish(log->science, &log->result) : VG_OK;
}

void capture_log_free(capture_log *log)
{
    warp_metrics_free(&log->warp);
    science_metrics_destroy(log->science);
    free(log->pass_ms);
    free(log->cpu_ms);
    free(log->cameras);
    free(log->times);
    free(log->shadow_m);
    free(log->shadow_px);
    *log = (capture_log){0};
}

double capture_log_pass_median(const capture_log *log, uint32_t pass)
{
    return vg_median(log->pass_ms + pass, (size_t)log->frames, RG_MAX_PASSES);
}

double capture_log_frame_median(const capture_log *log) { return vg_median(log->cpu_ms, (size_t)log->frames, 1); }

void capture_log_shadow(const capture_log *log, double texel_m[2], double *split_m, double *texel_px)
{
    texel_m[0] = vg_median(log->shadow_m, (size_t)log->frames, 3);
    texel_m[1] = vg_median(log->shadow_m + 1, (size_t)log->frames, 3);
    *split_m = vg_median(log->shadow_m + 2, (size_t)log->frames, 3);
    *texel_px = vg_median(log->shadow_px, (size_t)log->frames, 1);
}
