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
    for (int m = 0; m < DEMO_MAPS; m++) {
        free(sc->xt[m]);
        for (int t = 0; t < sc->track_count; t++)
            free(sc->tracks[t].v[m]);
    }
    for (int r = 0; r < DEMO_MODES; r++)
        demo_run_free(&sc->runs[r]);
    *sc = (demo_scene){0};
}

/* ------------------------------------------------------------------------- */
/* capture.json                                                              */
/* ------------------------------------------------------------------------- */

/* The baseline's figures: holes and PSNR against the two cameras. */
static void json_holes(vg_json *j, const char *key, const warp_metrics *m)
{
    vg_json_object_begin(j, key);
    vg_json_num(j, "hole_fraction", m->hole_fraction);
    vg_json_object_begin(j, "psnr_db");
    vg_json_num(j, "left", m->psnr[0]);
    vg_json_num(j, "right", m->psnr[1]);
    vg_json_object_end(j);
    vg_json_object_end(j);
}

/* Shaped as `vergence capture`'s (and `vergence optimize`'s) metrics. */
static void json_mid(vg_json *j, const char *key, const disp_metrics *m, double range_violation,
                     const double second_difference[2])
{
    vg_json_object_begin(j, key);
    vg_json_num(j, "mid_distortion_jnd", m->mid_distortion_jnd);
    vg_json_num(j, "range_violation", range_violation);
    vg_json_num(j, "static_rms", m->static_rms);
    vg_json_num(j, "static_grad_rms", m->static_grad_rms);
    vg_json_int(j, "moving_samples", m->moving_measured);
    vg_json_object_begin(j, "second_difference");
    vg_json_num(j, "at_keyframe_boundaries", second_difference[0]);
    vg_json_num(j, "between_keyframes", second_difference[1]);
    vg_json_object_end(j);
    vg_json_object_end(j);
}

vg_status demo_capture_json(const char *dir, const scene *s, const demo_scene *sc, const demo_run *r,
                            const demo_opts *o, const char *device_name, const char *device_type)
{
    vg_json j = {0};
    vg_json_object_begin(&j, NULL);
    vg_json_str(&j, "vergence", VERGENCE_VERSION);
    vg_json_str(&j, "scene", sc->path);
    vg_json_object_begin(&j, "scene_info");
    vg_json_int(&j, "nodes", s->node_count);
    vg_json_int(&j, "animations", s->animation_count);
    vg_json_int(&j, "skins", s->skin_count);
    vg_json_int(&j, "instances", s->instance_count);
    vg_json_int(&j, "triangles", s->index_count / 3);
    vg_json_num(&j, "duration", s->duration);
    vg_json_object_end(&j);
    vg_json_array_begin(&j, "size");
    vg_json_int(&j, NULL, o->width);
    vg_json_int(&j, NULL, o->height);
    vg_json_array_end(&j);
    vg_json_num(&j, "fps", sc->fps);
    vg_json_int(&j, "keyframe_stride", o->keyframe_stride);
    vg_json_int(&j, "frame_step", r->step);
    vg_json_int(&j, "frames", r->frames);
    vg_json_int(&j, "first_frame", 0);
    vg_json_bool(&j, "analysis", r->analysis);
    vg_json_object_begin(&j, "device");
    vg_json_str(&j, "name", device_name);
    vg_json_str(&j, "type", device_type);
    vg_json_object_end(&j);
    vg_json_object_begin(&j, "stereo");
    vg_json_str(&j, "render", "warp");
    vg_json_str(&j, "mode", frame_mode_names[r->mode]);
    vg_json_str(&j, "operator", disp_operator_kind_name(o->op ? o->op : DISP_OPERATOR_LANG));
    vg_json_object_end(&j);
    vg_json_array_begin(&j, "still_frames");
    for (int i = 0; i < r->still_count; i++)
        vg_json_int(&j, NULL, r->still_frames[i]);
    vg_json_array_end(&j);

    vg_json_array_begin(&j, "passes");
    for (uint32_t p = 0; p < r->pass_count; p++) {
        vg_json_object_begin(&j, NULL);
        vg_json_str(&j, "name", r->pass_names[p]);
        vg_json_num(&j, "ms_median", r->pass_ms[p]);
        vg_json_object_end(&j);
    }
    vg_json_array_end(&j);
    vg_json_num(&j, "frame_ms_median", r->frame_ms);

    /* The warp at the stills, against the two-camera reference; the same
     * keys as a stereo capture's, plus the image-warping baseline. */
    static const char *const stages[5] = {"none", "direct", "neighborhood", "halton", "curve"};
    vg_json_object_begin(&j, "cascade");
    for (int st = 1; st < 5; st++)
        vg_json_num(&j, stages[st], r->warp.stage_fraction[st]);
    vg_json_object_end(&j);
    vg_json_object_begin(&j, "warp_error_px");
    vg_json_num(&j, "median", r->warp.error_median);
    vg_json_num(&j, "p99", r->warp.error_p99);
    vg_json_num(&j, "p99_curve", r->warp.error_p99_curve);
    vg_json_object_end(&j);
    vg_json_num(&j, "hole_fraction", r->warp.hole_fraction);
    vg_json_object_begin(&j, "psnr_db");
    vg_json_num(&j, "left", r->warp.psnr[0]);
    vg_json_num(&j, "right", r->warp.psnr[1]);
    vg_json_object_end(&j);
    json_holes(&j, "imagewarp", &r->imagewarp);

    if (r->has_mid) {
        vg_json_object_begin(&j, "metrics");
        json_mid(&j, "h", &r->mid[0], r->range_violation[0], r->second_difference[0]);
        json_mid(&j, "f", &r->mid[1], r->range_violation[1], r->second_difference[1]);
        vg_json_num(&j, "mid_reduction", r->mid[0].mid_distortion_jnd > 0
                                             ? 1.0 - r->mid[1].mid_distortion_jnd / r->mid[0].mid_distortion_jnd : 0.0);
        vg_json_str(&j, "operator", disp_operator_kind_name(o->op ? o->op : DISP_OPERATOR_LANG));
        vg_json_num(&j, "range_lo", r->range_lo);
        vg_json_num(&j, "range_hi", r->range_hi);
        vg_json_int(&j, "keyframes", r->keyframes);
        vg_json_object_end(&j);
    }
    vg_json_int(&j, "validation_messages", gpu_validation_messages());
    vg_json_object_end(&j);

    char path[4096];
    vg_status st = vg_path_join(path, sizeof path, dir, "capture.json");
    if (st == VG_OK)
        st = vg_json_write_file(&j, path);
    vg_json_free(&j);
    return st;
}
