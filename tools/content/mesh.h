/* vergence content — triangle meshes built from a few primitives.
 *
 * A mesh is an indexed triangle list with positions, normals and texture
 * coordinates, built by appending primitives (boxes, prisms, surfaces of
 * revolution, tubes, ground grids) under a rigid transform. All maths is done
 * in double and rounded to float once, so the output is the same on every run.
 * Triangles are counter-clockwise seen from outside (glTF front faces). */
#pragma once
#include <stdbool.h>
#include <stdint.h>

typedef struct mesh {
    float *pos, *nrm, *uv;     /* 3, 3 and 2 floats per vertex */
    uint32_t *idx;             /* triangle list */
    uint32_t vcount, icount;   /* vertices, indices */
    uint32_t vcap, icap;
    bool failed;               /* an allocation failed: the mesh is unusable */
} mesh;

/* Rigid transform p' = R p + t (R a rotation; scale lives in the primitive sizes). */
typedef struct xform {
    double r[9]; /* row-major 3x3 */
    double t[3];
} xform;

xform xform_identity(void);
xform xform_translate(double x, double y, double z);
/* Rotation about the axis (ax, ay, az) by angle (radians), then translation. */
xform xform_axis_angle(double ax, double ay, double az, double angle);
/* a after b: (a * b) p = a(b(p)). */
xform xform_mul(xform a, xform b);
/* Translation followed by a yaw about +Y (the common "place an object" case). */
xform xform_at(double x, double y, double z, double yaw);

void mesh_free(mesh *m);
uint32_t mesh_triangles(const mesh *m);

/* Box of size (sx, sy, sz) centred at the origin, flat faces. */
void mesh_box(mesh *m, xform x, double sx, double sy, double sz);
/* Convex polygon in the XY plane (counter-clockwise seen from +Z), extruded
 * along Z from -depth/2 to +depth/2, flat faces (gables, roof slabs). */
void mesh_prism(mesh *m, xform x, const double (*poly)[2], int n, double depth);

/* One point of a profile revolved about +Y: radius, height and the outward
 * normal (nr, ny) of the surface in the profile plane. */
typedef struct profile_pt {
    double r, y, nr, ny;
} profile_pt;

/* Surface of revolution of a profile listed from bottom to top. A point with
 * r == 0 at either end is a pole (closed with a triangle fan). */
void mesh_revolve(mesh *m, xform x, const profile_pt *p, int n, int segments);
/* Fills nr, ny of a smooth profile from central differences of (r, y). */
void profile_auto_normals(profile_pt *p, int n);

/* Ready-made revolved shapes; all stand on y = 0 unless noted. */
void mesh_sphere(mesh *m, xform x, double rx, double ry, int segments, int rings); /* centred */
void mesh_cylinder(mesh *m, xform x, double r_bottom, double r_top, double h, int segments, bool caps);
void mesh_cone(mesh *m, xform x, double r, double h, int segments); /* with a bottom cap */
void mesh_disc(mesh *m, xform x, double r, int segments);          /* facing +Y */

/* Tube of radius r along a polyline (strings, thin rails); open ends. */
void mesh_tube(mesh *m, const double (*pts)[3], int n, double r, int segments);

/* Flat ground at y = 0 over [x0, x1] x [z0, z1] in nx x nz cells, facing +Y,
 * with texture coordinates in units of tile metres (u = x / tile, v = z / tile). */
void mesh_grid(mesh *m, double x0, double z0, double x1, double z1, int nx, int nz, double tile);
