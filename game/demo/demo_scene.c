/* vergence demo — per scene: the sampled frames, the x-t row, the tracked
 * objects; the keyframe window of the MID metrics; capture.json of a run. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/io.h"
#include "core/json.h"
#include "core/log.h"
#include "demo.h"

const frame_mode demo_modes[DEMO_MODES] = {FRAME_MODE_ORIGINAL, FRAME_MODE_MANIPULATED, FRAME_MODE_OPTIMIZED};
const char *const demo_map_names[DEMO_MAPS] = {"g", "h", "f"};

/* ------------------------------------------------------------------------- */
/* Scene                                                                     */
/* ------------------------------------------------------------------------- */

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The effective saliency of a node (its instances'), -1 when it draws nothing. */
static float node_saliency(const scene *s, int node)
{
    for (int i = 0; i < s->instance_count; i++)
        if (s->instances[i].node == node)
            return s->instances[i].saliency;
    return -1.0f;
}

/* Objects worth a line in the plot: the salient ones (the moving object, the
 * landmarks), most salient first, node order among equals. */
static void pick_tracks(demo_scene *sc, const scene *s)
{
    bool taken[256] = {0};
    while (sc->track_count < DEMO_MAX_TRACKS) {
        int best = -1;
        float best_sal = 0.29f;
        for (int n = 0; n < s->node_count && n < 256; n++) {
            float sal = node_saliency(s, n);
            if (!taken[n] && sal > best_sal) {
                best = n;
                best_sal = sal;
            }
        }
        if (best < 0)
            break;
        taken[best] = true;
        demo_track *t = &sc->tracks[sc->track_count++];
        snprintf(t->name, sizeof t->name, "%s", s->nodes[best].name[0] ? s->nodes[best].name : "object");
        t->node = best;
        t->saliency = best_sal;
    }
}

/* The image row of the x-t slices: the median row of the most salient
 * object's origin over the clip (where it is in view), so the slice cuts
 * through its path the way the paper's Fig. 1 does. */
static vg_status pick_row(demo_scene *sc, const scene *s, const demo_opts *o)
{
    sc->row = o->height / 2;
    if (sc->track_count == 0)
        return VG_OK;
    scene_state st;
    vg_status status = scene_state_init(s, &st);
    float *rows = malloc(sizeof(float) * (size_t)sc->samples);
    if (status != VG_OK || !rows) {
        if (status == VG_OK)
            scene_state_free(&st);
        free(rows);
        return status != VG_OK ? status : VG_ERR_NOMEM;
    }
    int n = 0, node = sc->tracks[0].node;
    for (int i = 0; i < sc->samples; i++) {
        scene_evaluate(s, (float)(sc->frames[i] / sc->fps), &st);
        vg_camera cam;
        scene_camera_resolve(s, &st, 0, (float)o->width / (float)o->height, &cam);
        /* The centroid of the object's vertices (a skinned mesh's node
         * transform says nothing about where it is). */
        double p[3] = {0, 0, 0}, count = 0;
        for (int k = 0; k < s->instance_count; k++) {
            const scene_instance *in = &s->instances[k];
            if (in->node != node)
                continue;
            uint32_t vc = s->primitives[in->primitive].vertex_count;
            for (uint32_t v = 0; v < vc; v++)
                for (int a = 0; a < 3; a++)
                    p[a] += st.positions[3 * (size_t)(in->first_vertex + v) + (size_t)a];
            count += vc;
        }
        if (count == 0)
            continue;
        const float *vp = cam.view_proj;
        float c[4];
        for (int r = 0; r < 4; r++)
            c[r] = (float)(vp[r] * p[0] / count + vp[4 + r] * p[1] / count + vp[8 + r] * p[2] / count) + vp[12 + r];
        if (c[3] <= 0 || fabsf(c[0]) > c[3] || fabsf(c[1]) > c[3])
            continue;
        rows[n++] = (0.5f + 0.5f * c[1] / c[3]) * (float)o->height;
    }
    if (n) {
        qsort(rows, (size_t)n, sizeof *rows, cmp_float);
        int r = (int)rows[n / 2];
        sc->row = r < 0 ? 0 : r >= o->height ? o->height - 1 : r;
    }
    free(rows);
    scene_state_free(&st);
    return VG_OK;
}

long demo_clip_last(const demo_opts *o, const scene *s)
{
    double seconds = o->seconds > 0 ? o->seconds : s->duration > 0 ? s->duration : 4.0;
    return lround(seconds * o->fps) / o->step * o->step;
}

vg_status demo_scene_init(demo_scene *sc, const scene *s, const char *name, const char *path,
                          const demo_opts *o)
{
    *sc = (demo_scene){.fps = o->fps, .width = o->width};
    snprintf(sc->name, sizeof sc->name, "%s", name);
    snprintf(sc->path, sizeof sc->path, "%s", path);
    sc->last = demo_clip_last(o, s);
    sc->samples = (int)(sc->last / o->analysis_step) + 1;
    sc->frames = malloc(sizeof(long) * (size_t)sc->samples);
    if (!sc->frames)
        return VG_ERR_NOMEM;
    for (int i = 0; i < sc->samples; i++)
        sc->frames[i] = (long)i * o->analysis_step;
    pick_tracks(sc, s);
    for (int r = 0; r < DEMO_MODES; r++)
        sc->runs[r].mode = demo_modes[r];
    return pick_row(sc, s, o);
}

void demo_scene_free(demo_scene *sc)
{
    if (!sc)
        return;
    free(sc->frames);
    free(sc->fh_diff);
    for (int m = 0; m < DEMO_MAPS; m++) {
        free(sc->xt[m]);
        for (int t = 0; t < sc->track_count; t++)
            free(sc->tracks[t].v[m]);
    }
    for (int r = 0; r < DEMO_MODES; r++)
        demo_run_free(&sc->runs[r]);
    *sc = (demo_scene){0};
}
