#include "mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* ------------------------------------------------------------------------- */
/* Transforms                                                                */
/* ------------------------------------------------------------------------- */

xform xform_identity(void)
{
    return (xform){.r = {1, 0, 0, 0, 1, 0, 0, 0, 1}};
}

xform xform_translate(double x, double y, double z)
{
    xform a = xform_identity();
    a.t[0] = x;
    a.t[1] = y;
    a.t[2] = z;
    return a;
}

xform xform_axis_angle(double ax, double ay, double az, double angle)
{
    double len = sqrt(ax * ax + ay * ay + az * az);
    if (len == 0)
        return xform_identity();
    ax /= len, ay /= len, az /= len;
    double c = cos(angle), s = sin(angle), k = 1 - c;
    return (xform){.r = {
        c + ax * ax * k,      ax * ay * k - az * s, ax * az * k + ay * s,
        ay * ax * k + az * s, c + ay * ay * k,      ay * az * k - ax * s,
        az * ax * k - ay * s, az * ay * k + ax * s, c + az * az * k,
    }};
}

xform xform_mul(xform a, xform b)
{
    xform o = {0};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                o.r[i * 3 + j] += a.r[i * 3 + k] * b.r[k * 3 + j];
        o.t[i] = a.t[i];
        for (int k = 0; k < 3; k++)
            o.t[i] += a.r[i * 3 + k] * b.t[k];
    }
    return o;
}

xform xform_at(double x, double y, double z, double yaw)
{
    return xform_mul(xform_translate(x, y, z), xform_axis_angle(0, 1, 0, yaw));
}

static void apply_point(const xform *x, const double p[3], double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = x->r[i * 3] * p[0] + x->r[i * 3 + 1] * p[1] + x->r[i * 3 + 2] * p[2] + x->t[i];
}

static void apply_dir(const xform *x, const double d[3], double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = x->r[i * 3] * d[0] + x->r[i * 3 + 1] * d[1] + x->r[i * 3 + 2] * d[2];
}

/* ------------------------------------------------------------------------- */
/* Storage                                                                   */
/* ------------------------------------------------------------------------- */

void mesh_free(mesh *m)
{
    if (!m)
        return;
    free(m->pos);
    free(m->nrm);
    free(m->uv);
    free(m->idx);
    *m = (mesh){0};
}

uint32_t mesh_triangles(const mesh *m)
{
    return m->icount / 3;
}

static bool grow(void **p, uint32_t *cap, uint32_t need, size_t elem)
{
    if (need <= *cap)
        return true;
    uint32_t c = *cap ? *cap : 256;
    while (c < need)
        c *= 2;
    void *q = realloc(*p, (size_t)c * elem);
    if (!q)
        return false;
    *p = q;
    *cap = c;
    return true;
}

static bool reserve(mesh *m, uint32_t verts, uint32_t indices)
{
    if (m->failed)
        return false;
    uint32_t vcap = m->vcap;
    bool ok = grow((void **)&m->pos, &vcap, m->vcount + verts, 3 * sizeof(float));
    vcap = m->vcap;
    ok = ok && grow((void **)&m->nrm, &vcap, m->vcount + verts, 3 * sizeof(float));
    vcap = m->vcap;
    ok = ok && grow((void **)&m->uv, &vcap, m->vcount + verts, 2 * sizeof(float));
    if (ok)
        m->vcap = vcap;
    ok = ok && grow((void **)&m->idx, &m->icap, m->icount + indices, sizeof(uint32_t));
    if (!ok)
        m->failed = true;
    return ok;
}

/* Appends one vertex (already transformed); the normal is normalised here so
 * every primitive can hand over an unnormalised one. */
static uint32_t vertex(mesh *m, const double p[3], const double n[3], double u, double v)
{
    double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    uint32_t i = m->vcount++;
    for (int k = 0; k < 3; k++) {
        m->pos[i * 3 + k] = (float)p[k];
        m->nrm[i * 3 + k] = (float)(len > 0 ? n[k] / len : (k == 1));
    }
    m->uv[i * 2] = (float)u;
    m->uv[i * 2 + 1] = (float)v;
    return i;
}

static uint32_t vertex_x(mesh *m, const xform *x, const double p[3], const double n[3])
{
    double wp[3], wn[3];
    apply_point(x, p, wp);
    apply_dir(x, n, wn);
    return vertex(m, wp, wn, 0, 0);
}

static void tri(mesh *m, uint32_t a, uint32_t b, uint32_t c)
{
    m->idx[m->icount++] = a;
    m->idx[m->icount++] = b;
    m->idx[m->icount++] = c;
}

/* ------------------------------------------------------------------------- */
/* Flat-faced solids                                                         */
/* ------------------------------------------------------------------------- */

void mesh_prism(mesh *m, xform x, const double (*poly)[2], int n, double depth)
{
    if (n < 3 || !reserve(m, (uint32_t)(2 * n + 4 * n), (uint32_t)(6 * (n - 2) + 6 * n)))
        return;
    double h = depth / 2;
    /* Caps: a fan, front (+Z) counter-clockwise, back reversed. */
    for (int side = 0; side < 2; side++) {
        double z = side == 0 ? h : -h, nz[3] = {0, 0, side == 0 ? 1 : -1};
        uint32_t first = m->vcount;
        for (int i = 0; i < n; i++)
            vertex_x(m, &x, (double[3]){poly[i][0], poly[i][1], z}, nz);
        for (int i = 1; i + 1 < n; i++) {
            if (side == 0)
                tri(m, first, first + (uint32_t)i, first + (uint32_t)i + 1);
            else
                tri(m, first, first + (uint32_t)i + 1, first + (uint32_t)i);
        }
    }
    /* Sides: the outward normal of edge (dx, dy) of a counter-clockwise polygon is (dy, -dx). */
    for (int i = 0; i < n; i++) {
        const double *a = poly[i], *b = poly[(i + 1) % n];
        double nrm[3] = {b[1] - a[1], -(b[0] - a[0]), 0};
        uint32_t v0 = vertex_x(m, &x, (double[3]){a[0], a[1], h}, nrm);
        uint32_t v1 = vertex_x(m, &x, (double[3]){a[0], a[1], -h}, nrm);
        uint32_t v2 = vertex_x(m, &x, (double[3]){b[0], b[1], -h}, nrm);
        uint32_t v3 = vertex_x(m, &x, (double[3]){b[0], b[1], h}, nrm);
        tri(m, v0, v1, v2);
        tri(m, v0, v2, v3);
    }
}

void mesh_box(mesh *m, xform x, double sx, double sy, double sz)
{
    double hx = sx / 2, hy = sy / 2;
    const double rect[4][2] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
    mesh_prism(m, x, rect, 4, sz);
}

/* ------------------------------------------------------------------------- */
/* Surfaces of revolution                                                    */
/* ------------------------------------------------------------------------- */

void profile_auto_normals(profile_pt *p, int n)
{
    for (int i = 0; i < n; i++) {
        const profile_pt *a = &p[i > 0 ? i - 1 : i], *b = &p[i + 1 < n ? i + 1 : i];
        double dr = b->r - a->r, dy = b->y - a->y;
        /* Tangent (dr, dy) going up the profile; outward normal (dy, -dr). */
        p[i].nr = dy;
        p[i].ny = -dr;
        /* A pole's normal is the axis itself, whatever the neighbours say. */
        if (p[i].r == 0 && (i == 0 || i == n - 1)) {
            p[i].nr = 0;
            p[i].ny = i == 0 ? -1 : 1;
        }
    }
}

/* Position and normal of profile point p at angle a; angle 0 faces +Z and
 * grows towards +X, which with bottom-to-top profiles gives CCW triangles. */
static uint32_t ring_vertex(mesh *m, const xform *x, const profile_pt *p, double a)
{
    double s = sin(a), c = cos(a);
    double pos[3] = {p->r * s, p->y, p->r * c}, nrm[3] = {p->nr * s, p->ny, p->nr * c};
    return vertex_x(m, x, pos, nrm);
}

void mesh_revolve(mesh *m, xform x, const profile_pt *p, int n, int segments)
{
    if (n < 2 || segments < 3)
        return;
    uint32_t seg = (uint32_t)segments;
    if (!reserve(m, (uint32_t)n * seg, 6 * (uint32_t)(n - 1) * seg))
        return;
    /* Ring i has `seg` vertices (no seam copy: these meshes carry no texture);
     * a pole has one vertex per segment at the segment's middle angle, so a
     * cone's tip keeps the normal of its own facet and no triangle is degenerate. */
    uint32_t *ring = malloc(sizeof(uint32_t) * (size_t)n);
    if (!ring) {
        m->failed = true;
        return;
    }
    for (int i = 0; i < n; i++) {
        bool pole = p[i].r == 0 && (i == 0 || i == n - 1);
        ring[i] = m->vcount;
        for (uint32_t j = 0; j < seg; j++)
            ring_vertex(m, &x, &p[i], 2 * PI * ((double)j + (pole ? 0.5 : 0)) / segments);
    }
    for (int i = 0; i + 1 < n; i++) {
        bool pole_lo = p[i].r == 0 && i == 0, pole_hi = p[i + 1].r == 0 && i + 1 == n - 1;
        for (uint32_t j = 0; j < seg; j++) {
            uint32_t j1 = (j + 1) % seg;
            uint32_t a = ring[i] + j, b = ring[i] + j1, c = ring[i + 1] + j1, d = ring[i + 1] + j;
            if (pole_lo && pole_hi)
                continue;
            if (pole_lo)
                tri(m, a, c, d); /* a is the pole vertex between d and c */
            else if (pole_hi)
                tri(m, a, b, d); /* d is the pole vertex between a and b */
            else {
                tri(m, a, b, c);
                tri(m, a, c, d);
            }
        }
    }
    free(ring);
}

void mesh_sphere(mesh *m, xform x, double rx, double ry, int segments, int rings)
{
    profile_pt *p = malloc(sizeof(profile_pt) * (size_t)(rings + 1));
    if (!p) {
        m->failed = true;
        return;
    }
    for (int i = 0; i <= rings; i++) {
        double phi = PI * i / rings; /* 0 at the bottom pole */
        double s = i == rings ? 0 : sin(phi), c = -cos(phi);
        /* Ellipsoid normal: gradient of (r/rx)^2 + (y/ry)^2. */
        p[i] = (profile_pt){.r = rx * s, .y = ry * c, .nr = s / rx, .ny = c / ry};
    }
    p[0].r = 0;
    mesh_revolve(m, x, p, rings + 1, segments);
    free(p);
}

void mesh_disc(mesh *m, xform x, double r, int segments)
{
    /* Profile from the rim inward to the pole at the centre: tangent (-r, 0), normal (0, r) = up. */
    const profile_pt p[2] = {{r, 0, 0, 1}, {0, 0, 0, 1}};
    mesh_revolve(m, x, p, 2, segments);
}

void mesh_cylinder(mesh *m, xform x, double r_bottom, double r_top, double h, int segments, bool caps)
{
    double nr = h, ny = r_bottom - r_top; /* slanted side of a frustum */
    const profile_pt side[2] = {{r_bottom, 0, nr, ny}, {r_top, h, nr, ny}};
    mesh_revolve(m, x, side, 2, segments);
    if (caps) {
        const profile_pt bottom[2] = {{0, 0, 0, -1}, {r_bottom, 0, 0, -1}};
        mesh_revolve(m, x, bottom, 2, segments);
        if (r_top > 0)
            mesh_disc(m, xform_mul(x, xform_translate(0, h, 0)), r_top, segments);
    }
}

void mesh_cone(mesh *m, xform x, double r, double h, int segments)
{
    const profile_pt side[2] = {{r, 0, h, r}, {0, h, h, r}};
    mesh_revolve(m, x, side, 2, segments);
    const profile_pt bottom[2] = {{0, 0, 0, -1}, {r, 0, 0, -1}};
    mesh_revolve(m, x, bottom, 2, segments);
}

/* ------------------------------------------------------------------------- */
/* Tubes and ground                                                          */
/* ------------------------------------------------------------------------- */

static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        v[0] /= l, v[1] /= l, v[2] /= l;
}

void mesh_tube(mesh *m, const double (*pts)[3], int n, double r, int segments)
{
    if (n < 2 || segments < 3)
        return;
    uint32_t seg = (uint32_t)segments, first = m->vcount;
    if (!reserve(m, (uint32_t)n * seg, 6 * (uint32_t)(n - 1) * seg))
        return;
    for (int i = 0; i < n; i++) {
        const double *a = pts[i > 0 ? i - 1 : i], *b = pts[i + 1 < n ? i + 1 : i];
        double t[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        normalize3(t);
        /* Frame from a fixed reference axis: fine for the gently curved
         * strings and rails made here, which never run along +X. */
        double u[3], v[3], ref[3] = {1, 0, 0};
        cross3(t, ref, u);
        normalize3(u);
        cross3(t, u, v);
        for (uint32_t j = 0; j < seg; j++) {
            double ang = 2 * PI * j / segments, c = cos(ang), s = sin(ang);
            double nrm[3], p[3];
            for (int k = 0; k < 3; k++) {
                nrm[k] = c * u[k] + s * v[k];
                p[k] = pts[i][k] + r * nrm[k];
            }
            vertex(m, p, nrm, 0, 0);
        }
    }
    for (uint32_t i = 0; i + 1 < (uint32_t)n; i++)
        for (uint32_t j = 0; j < seg; j++) {
            uint32_t j1 = (j + 1) % seg;
            uint32_t a = first + i * seg + j, b = first + i * seg + j1;
            uint32_t c = first + (i + 1) * seg + j1, d = first + (i + 1) * seg + j;
            /* (u, v, t) is right-handed, so angle then length winds outward. */
            tri(m, a, b, c);
            tri(m, a, c, d);
        }
}

void mesh_grid(mesh *m, double x0, double z0, double x1, double z1, int nx, int nz, double tile)
{
    if (nx < 1 || nz < 1)
        return;
    uint32_t cols = (uint32_t)nx + 1, first = m->vcount;
    if (!reserve(m, cols * (uint32_t)(nz + 1), 6 * (uint32_t)nx * (uint32_t)nz))
        return;
    const double up[3] = {0, 1, 0};
    for (int k = 0; k <= nz; k++)
        for (int i = 0; i <= nx; i++) {
            double p[3] = {x0 + (x1 - x0) * i / nx, 0, z0 + (z1 - z0) * k / nz};
            vertex(m, p, up, p[0] / tile, p[2] / tile);
        }
    for (uint32_t k = 0; k < (uint32_t)nz; k++)
        for (uint32_t i = 0; i < (uint32_t)nx; i++) {
            uint32_t a = first + k * cols + i, b = a + cols, c = b + 1, d = a + 1;
            /* With z growing along k, (a, b, c) is counter-clockwise seen from +Y. */
            tri(m, a, b, c);
            tri(m, a, c, d);
        }
}
