#include "props.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "core/io.h"

/* ------------------------------------------------------------------------- */
/* Objects                                                                   */
/* ------------------------------------------------------------------------- */

mesh *object_part_for(object *o, int material)
{
    for (int i = 0; i < o->part_count; i++)
        if (o->parts[i].material == material)
            return &o->parts[i].geo;
    if (o->part_count >= OBJECT_MAX_PARTS) {
        o->failed = true;
        return NULL;
    }
    object_part *p = &o->parts[o->part_count++];
    *p = (object_part){.material = material};
    return &p->geo;
}

void object_free(object *o)
{
    for (int i = 0; i < o->part_count; i++)
        mesh_free(&o->parts[i].geo);
    *o = (object){0};
}

int object_emit(gltf *g, object *o, const gltf_node_desc *d)
{
    int node = 0;
    if (o->failed)
        gltf_fail(g, "an object has more materials than OBJECT_MAX_PARTS");
    else {
        int m = gltf_mesh_add(g, d->name);
        for (int i = 0; i < o->part_count; i++)
            gltf_mesh_primitive(g, m, &o->parts[i].geo, o->parts[i].material);
        gltf_node_desc nd = *d;
        nd.mesh = m;
        node = gltf_node_add(g, &nd);
    }
    object_free(o);
    return node;
}

/* ------------------------------------------------------------------------- */
/* Camera and ground                                                         */
/* ------------------------------------------------------------------------- */

void quat_axis_angle(double ax, double ay, double az, double angle, float q[4])
{
    double len = sqrt(ax * ax + ay * ay + az * az), s = sin(angle / 2) / len;
    q[0] = (float)(ax * s);
    q[1] = (float)(ay * s);
    q[2] = (float)(az * s);
    q[3] = (float)cos(angle / 2);
}

void quat_mul(const float a[4], const float b[4], float out[4])
{
    double ax = a[0], ay = a[1], az = a[2], aw = a[3], bx = b[0], by = b[1], bz = b[2], bw = b[3];
    double q[4] = {
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    };
    double len = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; i++)
        out[i] = (float)(q[i] / len);
}

double jitter(int i, int salt)
{
    uint32_t x = (uint32_t)i * 0x9e3779b1U + (uint32_t)salt * 0x85ebca6bU;
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x / 2147483647.5 - 1;
}

int scene_camera(gltf *g, const double pos[3], double pitch, double yfov_deg)
{
    /* znear 0.1 m and zfar 150 m: the scenes span 2-60 m, so depth precision
     * is spent where the content is, with room for the backdrop. */
    int cam = gltf_camera_add(g, "camera", yfov_deg * DEG, 0.1, 150);
    gltf_node_desc d = {
        .name = "camera",
        .camera = cam,
        .translation = {(float)pos[0], (float)pos[1], (float)pos[2]},
    };
    /* Rotating -Z about +X by pitch gives (0, sin pitch, -cos pitch): negative looks down. */
    quat_axis_angle(1, 0, 0, pitch, d.rotation);
    return gltf_node_add(g, &d);
}

int ground_material(gltf *g, texture_kind kind)
{
    static const char *const names[] = {"grass", "grass", "paving", "field"};
    texture tex;
    uint8_t *png = NULL;
    size_t png_size = 0;
    if (texture_make(&tex, kind, 256) != VG_OK)
        return 0;
    vg_status st = vg_png_encode(tex.width, tex.height, 3, tex.rgb, &png, &png_size);
    texture_free(&tex);
    if (st != VG_OK)
        return 0;
    int t = gltf_texture_add_png(g, names[kind], png, png_size);
    free(png);
    return gltf_material_add(g, &(gltf_material_desc){.name = names[kind], .texture = t, .roughness = 1.0});
}

void ground_rect(object *o, int material, double x0, double z0, double x1, double z1, double cell, double tile)
{
    /* Cells of a few metres keep vertices close enough for per-vertex work
     * (shadows, the disparity warp) without costing many triangles. */
    mesh *m = object_part_for(o, material);
    if (m)
        mesh_grid(m, x0, z0, x1, z1, (int)lround((x1 - x0) / cell), (int)lround((z1 - z0) / cell), tile);
}

int scene_ground(gltf *g, texture_kind kind, double x0, double z0, double x1, double z1,
                 double cell, double tile, float saliency)
{
    object o = {0};
    ground_rect(&o, ground_material(g, kind), x0, z0, x1, z1, cell, tile);
    return object_emit(g, &o, &(gltf_node_desc){.name = "ground", .saliency = saliency});
}

/* ------------------------------------------------------------------------- */
/* Trees and hills                                                           */
/* ------------------------------------------------------------------------- */

void prop_fir(object *o, int bark, int needles, xform at, double h)
{
    mesh *trunk = object_part_for(o, bark), *crown = object_part_for(o, needles);
    if (!trunk || !crown)
        return;
    mesh_cylinder(trunk, at, 0.05 * h, 0.035 * h, 0.3 * h, 12, false);
    /* Three tiers, each overlapping the one below, like a drawn fir. */
    static const double tiers[3][3] = {
        /* base height, radius, height (fractions of the tree height) */
        {0.16, 0.30, 0.44},
        {0.38, 0.24, 0.38},
        {0.60, 0.17, 0.40},
    };
    for (int i = 0; i < 3; i++)
        mesh_cone(crown, xform_mul(at, xform_translate(0, tiers[i][0] * h, 0)), tiers[i][1] * h,
                  tiers[i][2] * h, 24);
}

void prop_broadleaf(object *o, int bark, const int leaves[3], xform at, double h)
{
    mesh *trunk = object_part_for(o, bark);
    if (!trunk)
        return;
    mesh_cylinder(trunk, at, 0.05 * h, 0.03 * h, 0.55 * h, 16, false);
    /* Crown layers: centre (x, y, z), radii (horizontal, vertical). Slight
     * offsets keep the silhouette from looking turned on a lathe. */
    static const double layers[3][5] = {
        {0.00, 0.56, 0.00, 0.34, 0.20},
        {0.03, 0.73, -0.02, 0.27, 0.17},
        {-0.02, 0.88, 0.01, 0.17, 0.12},
    };
    for (int i = 0; i < 3; i++) {
        mesh *crown = object_part_for(o, leaves[i]);
        if (!crown)
            return;
        xform c = xform_mul(at, xform_translate(layers[i][0] * h, layers[i][1] * h, layers[i][2] * h));
        mesh_sphere(crown, c, layers[i][3] * h, layers[i][4] * h, 32, 16);
    }
}

void prop_hill(object *o, int material, xform at, double r, double h)
{
    mesh *m = object_part_for(o, material);
    if (!m)
        return;
    enum { N = 14 };
    profile_pt p[N];
    for (int i = 0; i < N; i++) {
        double s = (double)i / (N - 1), rad = r * (1 - s);
        /* Raised cosine: flat foot, round top; 0.3 m below ground at the foot. */
        p[i] = (profile_pt){.r = rad, .y = h * 0.5 * (1 + cos(PI * rad / r)) - 0.3};
    }
    p[N - 1].r = 0;
    profile_auto_normals(p, N);
    mesh_revolve(m, at, p, N, 40);
}

/* ------------------------------------------------------------------------- */
/* Animation                                                                 */
/* ------------------------------------------------------------------------- */

/* Key time i of n intervals; computed from the integers so the last key is
 * exactly the duration. */
static float key_time(int i, int n, double duration)
{
    return (float)(duration * i / n);
}

void anim_translation(gltf *g, int anim, int node, path_fn f, double duration, int intervals, gltf_interp interp)
{
    int keys = intervals + 1, per_key = interp == GLTF_INTERP_CUBIC ? 3 : 1;
    float *times = malloc(sizeof(float) * (size_t)keys);
    float *values = malloc(sizeof(float) * 3 * (size_t)(keys * per_key));
    if (!times || !values) {
        free(times);
        free(values);
        gltf_fail(g, "out of memory for animation keys");
        return;
    }
    for (int i = 0; i < keys; i++) {
        double t = duration * i / intervals, p[3];
        times[i] = key_time(i, intervals, duration);
        f(t, p);
        float *v = values + (size_t)i * 3 * (size_t)per_key;
        if (interp == GLTF_INTERP_CUBIC) {
            /* Central difference; h small enough for the smooth paths used here. */
            const double h = 1e-4;
            double a[3], b[3];
            f(t - h, a);
            f(t + h, b);
            for (int k = 0; k < 3; k++) {
                float d = (float)((b[k] - a[k]) / (2 * h));
                v[k] = d;          /* in-tangent */
                v[3 + k] = (float)p[k];
                v[6 + k] = d;      /* out-tangent */
            }
        } else {
            for (int k = 0; k < 3; k++)
                v[k] = (float)p[k];
        }
    }
    gltf_animation_channel(g, anim, node, GLTF_PATH_TRANSLATION, interp, times, keys, values);
    free(times);
    free(values);
}

void anim_rotation(gltf *g, int anim, int node, orient_fn f, double duration, int intervals)
{
    int keys = intervals + 1;
    float *times = malloc(sizeof(float) * (size_t)keys), *values = malloc(sizeof(float) * 4 * (size_t)keys);
    if (!times || !values) {
        free(times);
        free(values);
        gltf_fail(g, "out of memory for animation keys");
        return;
    }
    for (int i = 0; i < keys; i++) {
        times[i] = key_time(i, intervals, duration);
        f(duration * i / intervals, values + (size_t)i * 4);
    }
    gltf_animation_channel(g, anim, node, GLTF_PATH_ROTATION, GLTF_INTERP_LINEAR, times, keys, values);
    free(times);
    free(values);
}
