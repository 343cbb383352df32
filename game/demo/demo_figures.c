/* vergence demo — a scene's figures once its runs are done: the x-t slices
 * of g, h and f (paper Figs. 1 and 8) and the objects' vergence over time
 * (the plot of Fig. 8). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/io.h"
#include "demo.h"
#include "demo_image.h"
#include "demo_svg.h"

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
    return st;
}
