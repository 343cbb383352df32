/* vergence — resolving a view: the scene's camera nodes or an automatic
 * framing of the bounds.
 *
 * Vulkan clip space: x right, y DOWN, depth 0 at the near plane and 1 at
 * the far plane (standard, not reversed). glTF cameras look down their local
 * -Z with +Y up (spec 3.10.1); scale and shear of the camera node are
 * removed by orthonormalising its axes. Projection matrices follow spec
 * 3.10.3 with the depth range mapped to 0..1 and y flipped. */
#include <math.h>
#include <string.h>

#include "scene_internal.h"

#define AUTO_YFOV 0.785398163f        /* 45 degrees */
#define AUTO_ELEVATION 0.261799388f   /* 15 degrees above the horizon */

/* ------------------------------------------------------------------------- */
/* Vectors                                                                   */
/* ------------------------------------------------------------------------- */

static float dot3(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(float out[3], const float a[3], const float b[3])
{
    float r[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(out, r, sizeof r);
}

static bool normalize3(float v[3])
{
    float len = sqrtf(dot3(v, v));
    if (!(len > 1e-20f) || !isfinite(len))
        return false;
    v[0] /= len, v[1] /= len, v[2] /= len;
    return true;
}

/* ------------------------------------------------------------------------- */
/* View and projection                                                       */
/* ------------------------------------------------------------------------- */

/* Orthonormal frame from a forward direction and an up hint; false when
 * forward is degenerate. */
static bool look(vg_camera *cam, const float pos[3], const float fwd[3], const float up_hint[3])
{
    float f[3] = {fwd[0], fwd[1], fwd[2]}, r[3], u[3];
    if (!normalize3(f))
        return false;
    cross3(r, f, up_hint);
    if (!normalize3(r)) {
        /* Up parallel to forward: any perpendicular will do. */
        float alt[3] = {fabsf(f[1]) < 0.9f ? 0.0f : 1.0f, fabsf(f[1]) < 0.9f ? 1.0f : 0.0f, 0.0f};
        cross3(r, f, alt);
        if (!normalize3(r))
            return false;
    }
    cross3(u, r, f);
    memcpy(cam->position, pos, sizeof cam->position);
    memcpy(cam->forward, f, sizeof f);
    memcpy(cam->right, r, sizeof r);
    memcpy(cam->up, u, sizeof u);
    /* Rows of the view matrix are right, up, -forward (right-handed, -Z ahead). */
    float *v = cam->view;
    memset(v, 0, sizeof cam->view);
    for (int k = 0; k < 3; k++) {
        v[k * 4 + 0] = r[k];
        v[k * 4 + 1] = u[k];
        v[k * 4 + 2] = -f[k];
    }
    v[12] = -dot3(r, pos);
    v[13] = -dot3(u, pos);
    v[14] = dot3(f, pos);
    v[15] = 1.0f;
    return true;
}

static void perspective(vg_camera *cam, float yfov, float aspect, float n, float f)
{
    float t = 1.0f / tanf(0.5f * yfov);
    float *p = cam->proj;
    memset(p, 0, sizeof cam->proj);
    p[0] = t / aspect;
    p[5] = -t;              /* y down */
    p[10] = f / (n - f);    /* z_view = -n -> 0, z_view = -f -> 1 */
    p[11] = -1.0f;
    p[14] = n * f / (n - f);
    cam->yfov = yfov, cam->aspect = aspect, cam->znear = n, cam->zfar = f;
}

static void orthographic(vg_camera *cam, float xmag, float ymag, float n, float f)
{
    float *p = cam->proj;
    memset(p, 0, sizeof cam->proj);
    p[0] = 1.0f / xmag;
    p[5] = -1.0f / ymag;
    p[10] = -1.0f / (f - n);
    p[14] = -n / (f - n);
    p[15] = 1.0f;
    cam->orthographic = true;
    cam->ymag = ymag;
    cam->aspect = xmag / ymag, cam->znear = n, cam->zfar = f;
}

/* Union of the scene's t = 0 bounds and the state's, skipping non-finite. */
static bool bounds(const scene *s, const scene_state *st, float lo[3], float hi[3])
{
    bool any = false;
    const float *src[2][2] = {{s->bounds_min, s->bounds_max}, {st ? st->bounds_min : NULL, st ? st->bounds_max : NULL}};
    for (int b = 0; b < 2; b++) {
        if (!src[b][0] || !(s->vertex_count > 0))
            continue;
        bool finite = true;
        for (int k = 0; k < 3; k++)
            finite = finite && isfinite(src[b][0][k]) && isfinite(src[b][1][k]);
        if (!finite)
            continue;
        for (int k = 0; k < 3; k++) {
            lo[k] = any ? fminf(lo[k], src[b][0][k]) : src[b][0][k];
            hi[k] = any ? fmaxf(hi[k], src[b][1][k]) : src[b][1][k];
        }
        any = true;
    }
    if (!any)
        for (int k = 0; k < 3; k++)
            lo[k] = -1.0f, hi[k] = 1.0f;
    return any;
}

/* Depth along forward of the farthest bounds corner: a far plane that
 * encloses the scene when glTF says "infinite" (zfar absent). */
static float enclosing_far(const vg_camera *cam, const float lo[3], const float hi[3], float n)
{
    float far = 0.0f;
    for (int c = 0; c < 8; c++) {
        float p[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]};
        float d[3] = {p[0] - cam->position[0], p[1] - cam->position[1], p[2] - cam->position[2]};
        far = fmaxf(far, dot3(d, cam->forward));
    }
    far *= 1.01f;
    return far > n * 2.0f && isfinite(far) ? far : n * 1000.0f;
}

/* ------------------------------------------------------------------------- */
/* Resolve                                                                   */
/* ------------------------------------------------------------------------- */

static void automatic(const scene *s, float aspect, vg_camera *cam)
{
    float lo[3], hi[3];
    bounds(s, NULL, lo, hi);
    float c[3], ext[3];
    for (int k = 0; k < 3; k++)
        c[k] = 0.5f * (lo[k] + hi[k]), ext[k] = hi[k] - lo[k];
    float radius = 0.5f * sqrtf(dot3(ext, ext));
    if (!(radius > 1e-6f) || !isfinite(radius))
        radius = 1.0f;
    /* The bounding sphere fits the narrower of the two fields of view. */
    float half = 0.5f * AUTO_YFOV, half_x = atanf(tanf(half) * aspect);
    float dist = radius / sinf(fminf(half, half_x)) * 1.05f;
    float dir[3] = {0.0f, sinf(AUTO_ELEVATION), cosf(AUTO_ELEVATION)};
    float pos[3] = {c[0] + dir[0] * dist, c[1] + dir[1] * dist, c[2] + dir[2] * dist};
    float fwd[3] = {-dir[0], -dir[1], -dir[2]}, up[3] = {0.0f, 1.0f, 0.0f};
    look(cam, pos, fwd, up);
    float n = fmaxf((dist - radius) * 0.9f, dist * 1e-3f), f = (dist + radius) * 1.1f;
    perspective(cam, AUTO_YFOV, aspect, n, f);
    cam->source_node = -1;
}

static bool from_node(const scene *s, const scene_state *st, int node, float aspect, vg_camera *cam)
{
    const scene_camera *sc = &s->cameras[s->nodes[node].camera];
    const float *w = st->world + (size_t)node * 16;
    float pos[3] = {w[12], w[13], w[14]}, fwd[3] = {-w[8], -w[9], -w[10]}, up[3] = {w[4], w[5], w[6]};
    if (!look(cam, pos, fwd, up))
        return false;
    float lo[3], hi[3];
    bounds(s, st, lo, hi);
    if (sc->orthographic) {
        float ymag = fabsf(sc->ymag) > 0.0f ? fabsf(sc->ymag) : 1.0f;
        float xmag = aspect > 0.0f ? ymag * aspect : (fabsf(sc->xmag) > 0.0f ? fabsf(sc->xmag) : ymag);
        float n = sc->znear >= 0.0f ? sc->znear : 0.0f;
        float f = sc->zfar > n ? sc->zfar : enclosing_far(cam, lo, hi, fmaxf(n, 1e-3f));
        orthographic(cam, xmag, ymag, n, f);
    } else {
        float yfov = sc->yfov > 0.0f && sc->yfov < 3.14f ? sc->yfov : AUTO_YFOV;
        float a = aspect > 0.0f ? aspect : (sc->aspect > 0.0f ? sc->aspect : 1.0f);
        float n = sc->znear > 0.0f ? sc->znear : 0.01f;
        float f = sc->zfar > n ? sc->zfar : enclosing_far(cam, lo, hi, n);
        perspective(cam, yfov, a, n, f);
    }
    cam->source_node = node;
    return true;
}

int scene_camera_count(const scene *s)
{
    int count = 0;
    for (int i = 0; i < s->node_count; i++)
        count += s->nodes[i].camera >= 0;
    return count;
}

int scene_camera_node(const scene *s, int index)
{
    int count = scene_camera_count(s), node = -1;
    if (count == 0)
        return -1;
    /* Out-of-range indices clamp to the first or last camera. */
    int want = index < 0 ? 0 : index >= count ? count - 1 : index;
    for (int i = 0; i < s->node_count && node < 0; i++)
        if (s->nodes[i].camera >= 0 && want-- == 0)
            node = i;
    return node;
}

bool scene_camera_orthographic(const scene *s, int index)
{
    int node = scene_camera_node(s, index);
    return node >= 0 && s->cameras[s->nodes[node].camera].orthographic;
}

void scene_camera_resolve(const scene *s, const scene_state *st, int index, float aspect, vg_camera *cam)
{
    memset(cam, 0, sizeof *cam);
    int node = st && st->world ? scene_camera_node(s, index) : -1;
    if (node < 0 || !from_node(s, st, node, aspect, cam)) {
        memset(cam, 0, sizeof *cam);
        automatic(s, aspect > 0.0f && isfinite(aspect) ? aspect : 1.0f, cam);
    }
    scene_mat4_mul(cam->view_proj, cam->proj, cam->view);
}
