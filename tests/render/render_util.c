/* vergence — helpers of the render tests (see render_util.h). */
#include "render_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------- */
/* A rendering context                                                       */
/* ------------------------------------------------------------------------- */

int rt_open(rt_ctx *c, const char *scene_path, uint32_t width, uint32_t height)
{
    memset(c, 0, sizeof *c);
    c->width = width;
    c->height = height;
    /* A zeroed desc picks a device; VERGENCE_VALIDATE=1 (set by CTest) turns validation on. */
    vg_status st = gpu_create(&(gpu_desc){0}, &c->gpu);
    if (st != VG_OK) {
        fprintf(stderr, "gpu_create failed: %s\n", vg_status_text(st));
        return 1;
    }
    st = scene_load(scene_path, &c->scene);
    if (st != VG_OK) {
        fprintf(stderr, "scene_load(%s) failed: %s\n", scene_path, vg_status_text(st));
        return 1;
    }
    return rt_open_frame(c, &c->frame);
}

int rt_open_frame(const rt_ctx *c, frame **out)
{
    vg_status st = frame_create(c->gpu, c->scene,
                                &(frame_desc){.width = c->width, .height = c->height, .readback = true}, out);
    if (st != VG_OK) {
        fprintf(stderr, "frame_create(%ux%u) failed: %s\n", c->width, c->height, vg_status_text(st));
        return 1;
    }
    return 0;
}

int rt_close(rt_ctx *c)
{
    frame_destroy(c->frame);
    gpu_destroy(c->gpu);
    scene_destroy(c->scene);
    memset(c, 0, sizeof *c);
    int messages = gpu_validation_messages();
    if (messages)
        fprintf(stderr, "validation reported %d WARNING/ERROR message(s) (printed above)\n", messages);
    return messages;
}

/* ------------------------------------------------------------------------- */
/* Camera maths                                                              */
/* ------------------------------------------------------------------------- */

void rt_mat4_to_double(const float m[16], double out[16])
{
    for (int i = 0; i < 16; i++)
        out[i] = m[i];
}

/* Cofactor expansion (the MESA gluInvertMatrix layout, column-major). */
bool rt_mat4_invert(const double m[16], double out[16])
{
    double inv[16];
    inv[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] + m[9] * m[7] * m[14] +
             m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    inv[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] - m[8] * m[7] * m[14] -
             m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    inv[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] + m[8] * m[7] * m[13] +
             m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    inv[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] - m[8] * m[6] * m[13] -
              m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    inv[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] - m[9] * m[3] * m[14] -
             m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    inv[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] + m[8] * m[3] * m[14] +
             m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    inv[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] - m[8] * m[3] * m[13] -
             m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    inv[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] + m[8] * m[2] * m[13] +
              m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    inv[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] + m[5] * m[3] * m[14] +
             m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    inv[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] - m[4] * m[3] * m[14] -
             m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    inv[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] + m[4] * m[3] * m[13] +
              m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    inv[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] - m[4] * m[2] * m[13] -
              m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    inv[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] - m[5] * m[3] * m[10] -
             m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    inv[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] + m[4] * m[3] * m[10] +
             m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    inv[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] - m[4] * m[3] * m[9] -
              m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    inv[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] + m[4] * m[2] * m[9] +
              m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    double det = m[0] * inv[0] + m[1] * inv[4] + m[2] * inv[8] + m[3] * inv[12];
    if (det == 0.0 || !isfinite(det))
        return false;
    for (int i = 0; i < 16; i++)
        out[i] = inv[i] / det;
    return true;
}

void rt_mat4_mul_point(const double m[16], const double p[3], double out[4])
{
    for (int r = 0; r < 4; r++)
        out[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
}

static void unproject(const double inv_vp[16], double nx, double ny, double nz, double out[3])
{
    double p[3] = {nx, ny, nz}, h[4];
    rt_mat4_mul_point(inv_vp, p, h);
    for (int k = 0; k < 3; k++)
        out[k] = h[k] / h[3];
}

void rt_pixel_ray(const double inv_view_proj[16], uint32_t width, uint32_t height, double px,
                  double py, rt_ray *r)
{
    /* Vulkan NDC: y grows downwards like pixel rows, so no flip here. */
    double nx = px / width * 2.0 - 1.0, ny = py / height * 2.0 - 1.0, far[3];
    unproject(inv_view_proj, nx, ny, 0.0, r->org);
    unproject(inv_view_proj, nx, ny, 1.0, far);
    for (int k = 0; k < 3; k++)
        r->dir[k] = far[k] - r->org[k];
}

bool rt_project(const float view_proj[16], const double p[3], uint32_t width, uint32_t height,
                double out[2])
{
    double vp[16], c[4];
    rt_mat4_to_double(view_proj, vp);
    rt_mat4_mul_point(vp, p, c);
    if (!(c[3] > 0.0))
        return false;
    out[0] = (c[0] / c[3] * 0.5 + 0.5) * width;
    out[1] = (c[1] / c[3] * 0.5 + 0.5) * height;
    return true;
}

double rt_linear_depth(const vg_camera *cam, const double p[3])
{
    double d = 0.0;
    for (int k = 0; k < 3; k++)
        d += (p[k] - cam->position[k]) * cam->forward[k];
    return d;
}

/* ------------------------------------------------------------------------- */
/* Embree ground truth                                                       */
/* ------------------------------------------------------------------------- */

int rt_embree_build(rt_embree *e, const scene *s, const scene_state *st)
{
    memset(e, 0, sizeof *e);
    e->device = rtcNewDevice("threads=2");
    if (!e->device) {
        fprintf(stderr, "rtcNewDevice failed: %d\n", (int)rtcGetDeviceError(NULL));
        return 1;
    }
    e->scene = rtcNewScene(e->device);
    /* Robust mode: watertight edges, so shared edges never let a ray slip through. */
    rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(e->scene, RTC_BUILD_QUALITY_HIGH);
    for (int i = 0; i < s->instance_count; i++) {
        const scene_instance *in = &s->instances[i];
        const scene_primitive *p = &s->primitives[in->primitive];
        RTCGeometry geo = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
        float *v = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                           p->vertex_count);
        unsigned *t = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                              p->index_count / 3);
        if (!v || !t) {
            fprintf(stderr, "embree buffers for instance %d: error %d\n", i, (int)rtcGetDeviceError(e->device));
            rtcReleaseGeometry(geo);
            return 1;
        }
        /* scene->indices are relative to the instance's first vertex. */
        memcpy(v, st->positions + 3 * (size_t)in->first_vertex, 3 * sizeof(float) * p->vertex_count);
        memcpy(t, s->indices + in->first_index, sizeof(unsigned) * (p->index_count / 3) * 3);
        rtcCommitGeometry(geo);
        unsigned id = rtcAttachGeometry(e->scene, geo);
        rtcReleaseGeometry(geo);
        if (id != (unsigned)i) {
            fprintf(stderr, "embree geometry id %u for instance %d\n", id, i);
            return 1;
        }
    }
    rtcCommitScene(e->scene);
    enum RTCError err = rtcGetDeviceError(e->device);
    if (err != RTC_ERROR_NONE) {
        fprintf(stderr, "embree scene build: error %d\n", (int)err);
        return 1;
    }
    return 0;
}

void rt_embree_destroy(rt_embree *e)
{
    if (e->scene)
        rtcReleaseScene(e->scene);
    if (e->device)
        rtcReleaseDevice(e->device);
    memset(e, 0, sizeof *e);
}

int rt_embree_cast(const rt_embree *e, const rt_ray *r, double *t)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    memset(&rh, 0, sizeof rh);
    rh.ray.org_x = (float)r->org[0];
    rh.ray.org_y = (float)r->org[1];
    rh.ray.org_z = (float)r->org[2];
    rh.ray.dir_x = (float)r->dir[0];
    rh.ray.dir_y = (float)r->dir[1];
    rh.ray.dir_z = (float)r->dir[2];
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = 1.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(e->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return -1;
    *t = rh.ray.tfar;
    return (int)rh.hit.geomID;
}

/* ------------------------------------------------------------------------- */
/* Statistics                                                                */
/* ------------------------------------------------------------------------- */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double quantile(const double *sorted, size_t n, double q)
{
    size_t i = (size_t)floor(q * (double)(n - 1) + 0.5);
    return sorted[i < n ? i : n - 1];
}

rt_stats rt_stats_of(double *v, size_t n)
{
    rt_stats s = {.n = n, .median = NAN, .p95 = NAN, .p99 = NAN, .max = NAN, .mean = NAN};
    if (!n)
        return s;
    qsort(v, n, sizeof *v, cmp_double);
    double sum = 0.0;
    for (size_t i = 0; i < n; i++)
        sum += v[i];
    s.mean = sum / (double)n;
    s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    s.p95 = quantile(v, n, 0.95);
    s.p99 = quantile(v, n, 0.99);
    s.max = v[n - 1];
    return s;
}
