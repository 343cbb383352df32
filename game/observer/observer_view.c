/* vergence — the observer's view: g, h and f of a moving object on the CPU. */
#include "observer_view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "disparity/mid_solver.h"
#include "disparity/mid_window.h"
#include "rules/game.h"

struct observer_view {
    observer_view_desc d;
    const scene *scene;
    vg_camera cam;
    stereo_display display;
    stereo_camera rig;
    disp_operator *op;
    int w, h, n;
    float *depth, *g_static, *sal_static;   /* the static scene, once */
    float *g_frame, *sal_frame, *h_frame;   /* one frame with the object splatted in */
    double radius, saliency;                /* of the moving object */
    double tan_y, tan_x;
};

/* ------------------------------------------------------------------------- */
/* A small z-buffer render of the static scene                               */
/* ------------------------------------------------------------------------- */

typedef struct screen_pt {
    double x, y, z; /* pixels, view depth */
} screen_pt;

static screen_pt to_screen(const observer_view *v, const float *p)
{
    double q[3] = {p[0], p[1], p[2]}, u, w;
    double z = game_project(&v->cam, q, &u, &w);
    return (screen_pt){u * v->w, w * v->h, z};
}

/* Depth interpolated as 1/z across the screen (perspective-correct), both
 * windings (the ground and walls are seen from one side anyway). */
static void raster_triangle(observer_view *v, screen_pt a, screen_pt b, screen_pt c, float saliency)
{
    double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (fabs(area) < 1e-12)
        return;
    int x0 = (int)floor(fmin(a.x, fmin(b.x, c.x))), x1 = (int)ceil(fmax(a.x, fmax(b.x, c.x)));
    int y0 = (int)floor(fmin(a.y, fmin(b.y, c.y))), y1 = (int)ceil(fmax(a.y, fmax(b.y, c.y)));
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 > v->w ? v->w : x1, y1 = y1 > v->h ? v->h : y1;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            double px = x + 0.5, py = y + 0.5;
            double w0 = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) / area;
            double w1 = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) / area;
            double w2 = 1.0 - w0 - w1;
            if (w0 < 0 || w1 < 0 || w2 < 0)
                continue;
            double z = 1.0 / (w0 / a.z + w1 / b.z + w2 / c.z);
            int i = y * v->w + x;
            if (z < v->depth[i]) {
                v->depth[i] = (float)z;
                v->sal_static[i] = saliency;
            }
        }
}

static void raster_static(observer_view *v, const scene_state *st)
{
    const scene *s = v->scene;
    for (int i = 0; i < v->n; i++) {
        v->depth[i] = v->cam.zfar; /* the G-buffer's background: the far plane */
        v->sal_static[i] = 0.0f;
    }
    for (int k = 0; k < s->instance_count; k++) {
        const scene_instance *in = &s->instances[k];
        if (in->node == v->d.moving_node)
            continue;
        const scene_primitive *p = &s->primitives[in->primitive];
        const uint32_t *idx = s->indices + in->first_index;
        const float *pos = st->positions + (size_t)in->first_vertex * 3;
        for (uint32_t t = 0; t + 2 < p->index_count; t += 3) {
            screen_pt q[3];
            bool front = true;
            for (int j = 0; j < 3; j++) {
                q[j] = to_screen(v, pos + (size_t)idx[t + (uint32_t)j] * 3);
                front = front && q[j].z > v->cam.znear;
            }
            /* Triangles crossing the near plane lie under the player's feet,
             * outside the view (the arena's ground is seen from 3 m on). */
            if (front)
                raster_triangle(v, q[0], q[1], q[2], in->saliency);
        }
    }
}

/* The moving object's size and saliency from its instances at t = 0. */
static void measure_object(observer_view *v, const scene_state *st)
{
    const scene *s = v->scene;
    const float *world = st->world + (size_t)v->d.moving_node * 16;
    v->radius = 0.0;
    v->saliency = 1.0;
    for (int k = 0; k < s->instance_count; k++) {
        const scene_instance *in = &s->instances[k];
        if (in->node != v->d.moving_node)
            continue;
        v->saliency = in->saliency;
        const scene_primitive *p = &s->primitives[in->primitive];
        for (uint32_t j = 0; j < p->vertex_count; j++) {
            const float *q = st->positions + ((size_t)in->first_vertex + j) * 3;
            double dx = q[0] - world[12], dy = q[1] - world[13], dz = q[2] - world[14];
            v->radius = fmax(v->radius, sqrt(dx * dx + dy * dy + dz * dz));
        }
    }
}

/* ------------------------------------------------------------------------- */
/* Lifetime                                                                  */
/* ------------------------------------------------------------------------- */

vg_status observer_view_create(const observer_view_desc *desc, observer_view **out)
{
    *out = NULL;
    observer_view *v = calloc(1, sizeof *v);
    if (!v)
        return VG_ERR_NOMEM;
    v->d = *desc;
    v->scene = desc->scene;
    v->w = desc->width > 0 ? desc->width : 160;
    v->h = desc->height > 0 ? desc->height : 90;
    v->n = v->w * v->h;
    if (!(v->d.fps > 0))
        v->d.fps = 60;
    if (v->d.keyframe_stride <= 0)
        v->d.keyframe_stride = MID_KEYFRAME_STRIDE;
    stereo_display_init(&v->display, &desc->display);
    scene_state st;
    vg_status status = scene_state_init(v->scene, &st);
    if (status != VG_OK) {
        free(v);
        return status;
    }
    scene_evaluate(v->scene, 0.0f, &st);
    scene_camera_resolve(v->scene, &st, desc->camera, (float)v->w / (float)v->h, &v->cam);
    v->tan_y = tan(0.5 * v->cam.yfov);
    v->tan_x = v->tan_y * v->cam.aspect;
    /* The original rig as the frame sets it up (frame/frame.c stereo_setup). */
    stereo_camera_desc rig = desc->rig;
    if (!(rig.interaxial_m > 0))
        rig.interaxial_m = FRAME_DEFAULT_INTERAXIAL;
    if (!(rig.convergence_m > 0))
        rig.convergence_m = FRAME_DEFAULT_CONVERGENCE;
    rig.hfov_deg = 2.0 * atan(v->tan_x) * 180.0 / M_PI;
    rig.image_width = v->w;
    stereo_camera_init(&v->rig, &rig, &v->display);

    size_t nf = (size_t)v->n * sizeof(float);
    v->depth = malloc(nf), v->g_static = malloc(nf), v->sal_static = malloc(nf);
    v->g_frame = malloc(nf), v->sal_frame = malloc(nf), v->h_frame = malloc(nf);
    if (!v->depth || !v->g_static || !v->sal_static || !v->g_frame || !v->sal_frame || !v->h_frame)
        status = VG_ERR_NOMEM;
    if (status == VG_OK)
        status = disp_operator_create(&(disp_operator_desc){
            .kind = desc->op, .preset = desc->preset, .range = desc->range,
            .screen_vergence = v->display.screen_vergence, .frame_seconds = 1.0 / v->d.fps}, &v->op);
    if (status == VG_OK) {
        raster_static(v, &st);
        measure_object(v, &st);
        stereo_camera_vergence_image(&v->rig, &v->display, v->depth, v->n, v->g_static);
    }
    scene_state_free(&st);
    if (status != VG_OK) {
        observer_view_destroy(v);
        return status;
    }
    *out = v;
    return VG_OK;
}

void observer_view_destroy(observer_view *v)
{
    if (!v)
        return;
    disp_operator_destroy(v->op);
    free(v->depth), free(v->g_static), free(v->sal_static);
    free(v->g_frame), free(v->sal_frame), free(v->h_frame);
    free(v);
}

const vg_camera *observer_view_camera(const observer_view *v) { return &v->cam; }
const stereo_display *observer_view_display(const observer_view *v) { return &v->display; }
const stereo_camera *observer_view_rig(const observer_view *v) { return &v->rig; }
double observer_view_radius(const observer_view *v) { return v->radius; }
int observer_view_keyframe_stride(const observer_view *v) { return v->d.keyframe_stride; }

/* ------------------------------------------------------------------------- */
/* Tracks                                                                    */
/* ------------------------------------------------------------------------- */

/* The frame's g and saliency with the object drawn as a disc at its centre
 * depth (at least the one pixel it is in: a far ball still counts). */
static void splat_object(observer_view *v, screen_pt c, double g)
{
    memcpy(v->g_frame, v->g_static, (size_t)v->n * sizeof(float));
    memcpy(v->sal_frame, v->sal_static, (size_t)v->n * sizeof(float));
    if (!(c.z > v->cam.znear))
        return;
    double r = v->radius / c.z * 0.5 * v->h / v->tan_y;
    int cx = (int)floor(c.x), cy = (int)floor(c.y);
    int x0 = (int)floor(c.x - r), x1 = (int)ceil(c.x + r), y0 = (int)floor(c.y - r), y1 = (int)ceil(c.y + r);
    for (int y = y0 < 0 ? 0 : y0; y < (y1 > v->h ? v->h : y1); y++)
        for (int x = x0 < 0 ? 0 : x0; x < (x1 > v->w ? v->w : x1); x++) {
            double dx = x + 0.5 - c.x, dy = y + 0.5 - c.y;
            bool inside = dx * dx + dy * dy <= r * r || (x == cx && y == cy);
            int i = y * v->w + x;
            if (inside && c.z < v->depth[i]) {
                v->g_frame[i] = (float)g;
                v->sal_frame[i] = (float)v->saliency;
            }
        }
}

/* f over the track's keyframes (frames 0, S, 2S, ...): paper Sec. 4.3 on a
 * 2 x 2 window whose four samples all follow the object (zero flow: the
 * samples move with it), then f/h between keyframes as the upsampling in
 * time does (Sec. 4.4: cubic Hermite on the keyframes' ratios and slopes). */
static vg_status optimize_track(observer_view *v, const double *g, const double *z, int count, double *a)
{
    int stride = v->d.keyframe_stride, nk = (count - 1) / stride + 1;
    if (nk < 3)
        return VG_OK; /* no acceleration to restore: f = h */
    double lo, hi;
    disp_operator_range(v->op, &lo, &hi);
    float span = (float)(stride / v->d.fps); /* seconds between keyframes */
    mid_window *w;
    vg_status st = mid_window_create(&(mid_window_desc){
        .width = 2, .height = 2, .keyframes = nk, .range_lo = (float)lo, .range_hi = (float)hi,
        .keyframe_seconds = span}, &w);
    if (st != VG_OK)
        return st;
    for (int k = 0; k < nk; k++)
        for (int s = 0; s < 4; s++) {
            int i = k * 4 + s, f = k * stride;
            w->g[i] = (float)g[f];
            w->h[i] = (float)a[f];
            w->depth[i] = (float)z[f];
        }
    float *f = malloc((size_t)w->n * sizeof(float));
    float *ratio = malloc((size_t)w->n * sizeof(float)), *slope = malloc((size_t)w->n * sizeof(float));
    st = f && ratio && slope ? mid_window_build(w, NULL) : VG_ERR_NOMEM;
    if (st == VG_OK)
        st = mid_solve(w, &(mid_solve_desc){0}, f, NULL);
    if (st == VG_OK) {
        /* The correction f / g, in time as the engine's upsampling
         * interpolates it, applied to the original (mid_ratio_to_h). */
        for (int i = 0; i < w->n; i++)
            ratio[i] = f[i] / w->g[i];
        mid_window_ratio_slopes(w, ratio, slope);
        for (int i = 0; i < count; i++) {
            int k0 = i / stride;
            float tau = (float)(i - k0 * stride) / (float)stride;
            float m = k0 + 1 < nk ? mid_hermite(ratio[k0 * 4], slope[k0 * 4], ratio[(k0 + 1) * 4],
                                                slope[(k0 + 1) * 4], tau, span)
                                  : ratio[k0 * 4];
            a[i] = fmin(hi, fmax(lo, a[i] * mid_ratio_to_h(m, (float)g[i], (float)a[i])));
        }
    }
    free(f);
    free(ratio);
    free(slope);
    mid_window_destroy(w);
    return st;
}

vg_status observer_view_track(observer_view *v, const double (*pos)[3], int count, frame_mode mode,
                              double *vergence)
{
    double *g = malloc((size_t)count * sizeof(double)), *z = malloc((size_t)count * sizeof(double));
    if (!g || !z) {
        free(g), free(z);
        return VG_ERR_NOMEM;
    }
    disp_operator_reset(v->op);
    for (int i = 0; i < count; i++) {
        float p[3] = {(float)pos[i][0], (float)pos[i][1], (float)pos[i][2]};
        screen_pt c = to_screen(v, p);
        z[i] = c.z;
        g[i] = stereo_camera_vergence(&v->rig, &v->display, c.z);
        if (mode == FRAME_MODE_ORIGINAL) {
            vergence[i] = g[i];
            continue;
        }
        /* h = M(g, saliency) of the whole frame; the object's value through
         * the frame's mapping (exact at its centre depth). */
        splat_object(v, c, g[i]);
        disp_operator_apply(v->op, v->g_frame, v->sal_frame, v->n, v->h_frame, NULL);
        vergence[i] = disp_operator_map(v->op, g[i]);
    }
    vg_status st = mode == FRAME_MODE_OPTIMIZED || mode == FRAME_MODE_DEFAULT
                       ? optimize_track(v, g, z, count, vergence) : VG_OK;
    free(g), free(z);
    return st;
}

double observer_view_surround(const observer_view *v, const observer_shown *shown, frame_mode mode, double depth_m,
                              double u, double vv)
{
    double g = stereo_camera_vergence(&v->rig, &v->display, depth_m);
    if (mode == FRAME_MODE_ORIGINAL)
        return g;
    if (!shown)
        return disp_operator_map(v->op, g);
    int x = (int)floor(u * shown->width), y = (int)floor(vv * shown->height);
    x = x < 0 ? 0 : x >= shown->width ? shown->width - 1 : x;
    y = y < 0 ? 0 : y >= shown->height ? shown->height - 1 : y;
    return g + shown->surround[(size_t)y * shown->width + x];
}
