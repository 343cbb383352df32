/* vergence — offline_run, `vergence optimize`'s pipeline in order (offline.h
 * describes the passes). Each step is a function of one of the files that
 * offline_internal.h lists: the inputs (offline_read.c), the method
 * (offline_solve.c), the result in --out (offline_write.c). */
#include "offline.h"

#include <float.h>
#include <stdlib.h>

#include "core/log.h"
#include "offline_internal.h"

/* The keyframes (offline_keyframes: every stride frames within each shot),
 * placed after pass A: nothing proportional to --frames is allocated before
 * every frame was found. */
static vg_status place_keyframes(offline_seq *s)
{
    s->keyframes = offline_keyframes(s, NULL);
    if (!(s->keyframe_numbers = malloc((size_t)s->keyframes * sizeof(int))))
        return VG_ERR_NOMEM;
    offline_keyframes(s, s->keyframe_numbers);
    return VG_OK;
}

static vg_status run(offline_seq *s)
{
    const offline_desc *d = s->desc;
    mid_window *w = NULL;
    float *f_sol = NULL;
    offline_outputs o = {0};
    mid_solve_stats ss = {0};
    if ((!d->g && !d->depth && !d->depth_video) || !d->out_dir) {
        vg_error("optimize: --g (or --depth) and --out are required");
        return VG_ERR_ARG;
    }
    if ((d->video_in && d->image) || (d->depth_video && d->depth)) {
        vg_error("optimize: give %s, not both", d->video_in && d->image ? "--video or --image" : "--depth-video or --depth");
        return VG_ERR_ARG;
    }
    if (d->first < 0 || d->last < d->first) {
        vg_error("optimize: --frames %d:%d is not a range of frame numbers >= 0", d->first, d->last);
        return VG_ERR_ARG;
    }
    /* The inputs named, and nothing optimize writes or removes one of them. */
    vg_status st = offline_patterns_parse(s);
    if (st != VG_OK || (st = offline_check_out_dir(s)) != VG_OK)
        return st;
    s->frames = d->last - d->first + 1;
    s->keyframe_stride = d->keyframe_stride > 0 ? d->keyframe_stride : MID_KEYFRAME_STRIDE;
    if ((st = offline_check_flows(s)) != VG_OK ||
        ((d->video_in || d->depth_video) && (st = offline_video_decode(s)) != VG_OK))
        return st;
    s->fps = d->fps > 0 ? d->fps : MID_FPS;
    stereo_display_init(&s->display, &d->display);
    stereo_camera_init(&s->rig, &d->rig, &s->display);
    /* A: every input read once. */
    if ((st = vg_pool_create(&(vg_pool_desc){.threads = d->threads}, &s->pool)) != VG_OK ||
        (st = offline_validate(s)) != VG_OK || (st = place_keyframes(s)) != VG_OK)
        goto done;
    /* The inputs hold: the earlier result in --out goes (metrics.json first,
     * then its files). */
    if ((st = vg_manifest_begin(&s->manifest, d->out_dir, "metrics.json")) != VG_OK)
        goto done;
    disp_grid_init(&s->grid, s->width, s->height, d->coarse > 0 ? d->coarse : 5);
    if (s->grid.nx < 2 || s->grid.ny < 2) {
        vg_error("optimize: %dx%d frames give a %dx%d coarse grid; use a smaller --coarse", s->width, s->height,
                 s->grid.nx, s->grid.ny);
        st = VG_ERR_ARG;
        goto done;
    }
    if (d->ema && !s->has_h && (st = offline_ema_ranges(s)) != VG_OK)
        goto done;
    /* B: h, the keyframe samples and flows, the window; then the solve. */
    if ((st = offline_operator_create(s)) != VG_OK || (st = offline_window_build(s, &w)) != VG_OK)
        goto done;
    f_sol = malloc((size_t)w->n * sizeof(float));
    if ((st = offline_outputs_alloc(s, w->n, &o)) == VG_OK && !f_sol)
        st = VG_ERR_NOMEM;
    if (st != VG_OK || (st = offline_solve(s, w, f_sol, &ss)) != VG_OK)
        goto done;
    /* C: every frame upsampled and written; metrics.json last. */
    if ((st = offline_upsample(s, w, f_sol, &o)) == VG_OK)
        st = offline_write_results(s, w, f_sol, &o, &ss);
    if (st == VG_OK && s->flow == OFFLINE_FLOW_COMPUTED)
        vg_info("optimize: %ld flow pairs computed (both ways) in %.0f ms; %.1f %% of their pixels failed the "
                "forward-backward check (filled from their neighbours)", s->flow_computed, s->flow_ms,
                s->flow_computed ? 100.0 * s->flow_occluded / (2.0 * s->flow_computed * s->width * s->height) : 0.0);
done:
    free(f_sol);
    free(s->f_ungated);
    offline_outputs_free(&o);
    free(s->saliency);
    free(s->saliency_scratch);
    free(s->unknown);
    free(s->keyframe_numbers);
    offline_flow_free(s);
    mid_window_destroy(w);
    disp_operator_destroy(s->op);
    vg_pool_destroy(s->pool);
    vg_manifest_end(&s->manifest);
    return st;
}

vg_status offline_run(const offline_desc *d)
{
    offline_seq s = {.desc = d, .g_min = DBL_MAX, .g_max = -DBL_MAX, .g_raw_min = DBL_MAX, .g_raw_max = -DBL_MAX};
    vg_status st = run(&s);
    offline_video_remove(&s);
    offline_cuts_free(&s);
    free(s.ema);
    return st;
}
