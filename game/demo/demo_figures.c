/* vergence demo — a scene's figures once its runs are done: the x-t slices
 * of g, h and f (paper Figs. 1 and 8), the objects' vergence over time
 * (the plot of Fig. 8), the moving object's perceived velocity and
 * acceleration in depth (the paper's quantity, Sec. 4.2) and |f - h|. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/io.h"
#include "demo.h"
#include "demo_image.h"
#include "demo_svg.h"
#include "stereo/stereo_perception.h"

/* One colour per tracked object, the moving one first. */
static const char *const k_palette[DEMO_MAX_TRACKS] = {"#d62839", "#1f6fb4", "#2f9e44", "#8e5cc4", "#b0702c"};

static void range_of(const float *v, size_t n, float *lo, float *hi)
{
    for (size_t i = 0; i < n; i++)
        if (isfinite(v[i])) {
            *lo = fminf(*lo, v[i]);
            *hi = fmaxf(*hi, v[i]);
        }
}

static vg_status write_slices(const char *dir, demo_scene *sc)
{
    size_t n = (size_t)sc->samples * (size_t)sc->width;
    /* g on its own scale; h and f share one, so the compression shows and
     * the two can be compared pixel for pixel. */
    float lo_hf = INFINITY, hi_hf = -INFINITY;
    for (int m = 1; m < DEMO_MAPS; m++)
        if (sc->xt[m])
            range_of(sc->xt[m], n, &lo_hf, &hi_hf);
    /* Each frame is repeated so the slice is about as tall as it is wide. */
    int repeat = sc->samples > 0 ? (sc->width * 3 / 5) / sc->samples : 1;
    repeat = repeat < 1 ? 1 : repeat;
    vg_status st = VG_OK;
    for (int m = 0; m < DEMO_MAPS && st == VG_OK; m++) {
        if (!sc->xt[m])
            continue;
        float lo = INFINITY, hi = -INFINITY;
        if (m == 0)
            range_of(sc->xt[0], n, &lo, &hi);
        else {
            lo = lo_hf;
            hi = hi_hf;
        }
        sc->xt_lo[m] = lo;
        sc->xt_hi[m] = hi;
        char name[32];
        snprintf(name, sizeof name, "xt_%s.png", demo_map_names[m]);
        st = demo_png_xt(dir, name, sc->xt[m], sc->width, sc->samples, repeat, lo, hi);
    }
    return st;
}

static vg_status write_tracks(const char *dir, const demo_scene *sc)
{
    float *time = malloc(sizeof(float) * (size_t)sc->samples);
    if (!time)
        return VG_ERR_NOMEM;
    for (int i = 0; i < sc->samples; i++)
        time[i] = (float)(sc->frames[i] / sc->fps);
    demo_series series[2 * DEMO_MAX_TRACKS];
    char labels[2 * DEMO_MAX_TRACKS][DEMO_NAME + 8];
    vg_status st = VG_OK;

    /* g: the original disparity of each object. */
    int count = 0;
    for (int t = 0; t < sc->track_count; t++)
        if (sc->tracks[t].v[0])
            series[count++] = (demo_series){.y = sc->tracks[t].v[0], .label = sc->tracks[t].name,
                                            .color = k_palette[t], .width = t == 0 ? 2.5f : 1.6f};
    if (count)
        st = demo_svg_chart(dir, "tracks_g.svg", &(demo_chart){
            .title = "original g", .xlabel = "time (s)", .ylabel = "vergence (arcmin)", .x = time,
            .n = sc->samples, .series = series, .count = count});

    /* h (dashed) and f (solid) on one axis: where h bends, f should not. */
    count = 0;
    for (int t = 0; t < sc->track_count; t++)
        for (int m = 1; m < DEMO_MAPS; m++) {
            if (!sc->tracks[t].v[m])
                continue;
            snprintf(labels[count], sizeof labels[count], "%s %s", sc->tracks[t].name, demo_map_names[m]);
            series[count] = (demo_series){.y = sc->tracks[t].v[m], .color = k_palette[t], .dashed = m == 1,
                                          .width = t == 0 ? 2.5f : 1.6f,
                                          .label = t < 2 ? labels[count] : NULL};
            count++;
        }
    if (st == VG_OK && count)
        st = demo_svg_chart(dir, "tracks_hf.svg", &(demo_chart){
            .title = "manipulated h (dashed) and optimized f (solid)", .xlabel = "time (s)",
            .ylabel = "vergence (arcmin)", .x = time, .n = sc->samples, .series = series, .count = count});
    free(time);
    return st;
}

/* The moving object's (track 0) motion in depth as the paper measures it
 * (docs/method.md §11 on one sample): per keyframe interval the vergence
 * velocity v (arcmin/s) through p(v) = sign(v) ln(1 + |v|) / k (JND), and
 * per keyframe the perceived acceleration p(v+) - p(v-). One line each for
 * g, h and f: f should follow g's shape where h departs from it. */
static vg_status write_motion(const char *dir, const demo_opts *o, demo_scene *sc)
{
    const demo_track *t = &sc->tracks[0];
    int stride = o->keyframe_stride / (o->analysis_step > 0 ? o->analysis_step : 1);
    int keys = stride > 0 && sc->samples > 0 ? (sc->samples - 1) / stride + 1 : 0;
    sc->motion_points = 0;
    if (!sc->track_count || keys < 3 || !t->v[0])
        return VG_OK;
    float *buf = malloc(sizeof(float) * (size_t)keys * (2 + 2 * DEMO_MAPS));
    if (!buf)
        return VG_ERR_NOMEM;
    float *tv = buf, *ta = buf + keys, *pv[DEMO_MAPS], *pa[DEMO_MAPS];
    for (int m = 0; m < DEMO_MAPS; m++) {
        pv[m] = buf + (size_t)keys * (2 + 2 * m);
        pa[m] = pv[m] + keys;
    }
    double dt = (double)o->keyframe_stride / sc->fps; /* s between keyframes */
    for (int j = 0; j + 1 < keys; j++) {
        tv[j] = (float)((sc->frames[j * stride] + 0.5 * o->keyframe_stride) / sc->fps);
        ta[j] = (float)(sc->frames[j * stride] / sc->fps);
        for (int m = 0; m < DEMO_MAPS; m++) {
            const float *x = t->v[m];
            pv[m][j] = x ? (float)stereo_p((x[(j + 1) * stride] - x[j * stride]) / dt, 0) : NAN;
            pa[m][j] = j > 0 ? pv[m][j] - pv[m][j - 1] : NAN; /* NAN propagates a gap */
        }
    }
    static const char *const color[DEMO_MAPS] = {"#222222", "#d62839", "#1f6fb4"};
    static const char *const label[DEMO_MAPS] = {"g original", "h manipulated", "f optimized"};
    demo_series sv[DEMO_MAPS], sa[DEMO_MAPS];
    int count = 0;
    for (int m = 0; m < DEMO_MAPS; m++) {
        if (!t->v[m])
            continue;
        sv[count] = (demo_series){.y = pv[m], .label = label[m], .color = color[m], .dashed = m == 1,
                                  .width = m == 0 ? 3.0f : 2.2f};
        sa[count] = sv[count];
        sa[count++].y = pa[m] + 1; /* accelerations from the second keyframe on */
    }
    char title[2][DEMO_NAME + 64];
    snprintf(title[0], sizeof title[0], "%s: perceived velocity in depth p(v)", t->name);
    snprintf(title[1], sizeof title[1], "%s: perceived acceleration in depth", t->name);
    vg_status st = demo_svg_chart(dir, "motion_v.svg", &(demo_chart){
        .title = title[0], .xlabel = "time (s), the middle of each keyframe interval", .ylabel = "p(v) (JND)",
        .x = tv, .n = keys - 1, .series = sv, .count = count});
    if (st == VG_OK)
        st = demo_svg_chart(dir, "motion_a.svg", &(demo_chart){
            .title = title[1], .xlabel = "time (s), at each keyframe",
            .ylabel = "p(v+) - p(v-) (JND)", .x = ta + 1, .n = keys - 2, .series = sa, .count = count});
    sc->motion_points = keys;
    free(buf);
    return st;
}

/* |f - h| at the middle still: where f departs from the manipulation. */
static vg_status write_fh_diff(const char *dir, const demo_opts *o, demo_scene *sc)
{
    if (!sc->fh_diff)
        return VG_OK;
    size_t n = (size_t)sc->width * (size_t)o->height;
    float top = 0.0f;
    for (size_t i = 0; i < n; i++)
        top = isfinite(sc->fh_diff[i]) ? fmaxf(top, sc->fh_diff[i]) : top;
    sc->fh_max = top > 0.0f ? top : 1.0f;
    return demo_png_xt(dir, "fh_diff.png", sc->fh_diff, sc->width, o->height, 1, 0.0f, sc->fh_max);
}

vg_status demo_figures_write(const demo_opts *o, demo_scene *sc)
{
    char dir[4096];
    vg_status st = vg_path_join(dir, sizeof dir, o->out, sc->name);
    if (st == VG_OK)
        st = vg_dir_prepare(dir);
    if (st == VG_OK)
        st = write_slices(dir, sc);
    if (st == VG_OK)
        st = write_tracks(dir, sc);
    if (st == VG_OK)
        st = write_motion(dir, o, sc);
    if (st == VG_OK)
        st = write_fh_diff(dir, o, sc);
    return st;
}
