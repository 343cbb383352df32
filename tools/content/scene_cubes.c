/* cubes — paper Fig. 2: a small cube flies in depth from 3 m to 25 m, right
 * past a group of static cubes at 8-12 m. A disparity compression that
 * favours the static group squeezes the depth around it, so the flying cube
 * appears to slow down there; the optimisation restores its steady motion. */
#include <math.h>

#include "props.h"
#include "scenes.h"

#define FLYER_SIZE 0.45

static int mat(gltf *g, const char *name, uint8_t r, uint8_t gr, uint8_t b, double roughness)
{
    return gltf_material_add(g, &(gltf_material_desc){.name = name, .srgb = {r, gr, b}, .roughness = roughness});
}

/* Straight flight at a constant 5.5 m/s, drifting a little left so it passes
 * between the static cubes instead of through them. */
static void flyer_path(double t, double p[3])
{
    double s = t / CONTENT_SECONDS;
    p[0] = 0.55 - 0.9 * s;
    p[1] = 1.05 + 0.25 * s;
    p[2] = -3.0 - 22.0 * s;
}

/* A slow tumble: 120 degrees in 4 s about a tilted axis (constant axis, so
 * glTF's slerp between keys is exact). */
static void flyer_spin(double t, float q[4])
{
    quat_axis_angle(0.3, 1, 0.25, 120 * DEG * t / CONTENT_SECONDS, q);
}

typedef struct static_cube {
    const char *name;
    double x, z, size, yaw_deg, lift; /* lift: stacked on another cube */
    uint8_t srgb[3];
} static_cube;

/* The group spans 8-12.5 m, left and right of the flight path, heights
 * chosen so the flyer (at about 1.1-1.2 m there) passes beside their faces. */
static const static_cube group[] = {
    {"cube_blue", -3.3, -9.0, 1.4, 15, 0, {98, 134, 186}},
    {"cube_ochre", -1.9, -12.0, 1.8, -10, 0, {224, 164, 88}},
    {"cube_lavender", -1.9, -12.0, 0.9, 35, 1.8, {156, 137, 184}},
    {"cube_sage", 1.8, -8.3, 1.2, 30, 0, {143, 188, 143}},
    {"cube_rose", 3.3, -11.3, 1.6, 8, 0, {201, 123, 132}},
    {"cube_sand", 1.45, -12.6, 1.0, -25, 0, {214, 196, 150}},
};

static void build_backdrop(gltf *g)
{
    int hedge = mat(g, "hedge", 78, 124, 72, 1.0), bark = mat(g, "bark", 104, 76, 54, 1.0);
    int needles = mat(g, "fir_needles", 58, 100, 62, 1.0), hill = mat(g, "hill", 138, 164, 128, 1.0);
    int stone = mat(g, "wall_stone", 176, 170, 160, 0.9);

    /* A low stone wall closes the paved court at 30 m, hedges in front of it. */
    object wall = {0};
    mesh *m = object_part_for(&wall, stone);
    if (m) {
        mesh_box(m, xform_translate(0, 0.45, -30), 36, 0.9, 0.5);
        mesh_box(m, xform_translate(-18, 0.45, -19), 0.5, 0.9, 22);
        mesh_box(m, xform_translate(18, 0.45, -19), 0.5, 0.9, 22);
    }
    mesh *h = object_part_for(&wall, hedge);
    for (int i = 0; i < 6 && h; i++)
        mesh_box(h, xform_translate(-15 + 6 * i, 0.6, -28.8), 4.2, 1.2, 1.2);
    object_emit(g, &wall, &(gltf_node_desc){.name = "wall", .saliency = 0.1f});

    object trees = {0};
    for (int i = 0; i < 9; i++) {
        double x = -22 + 5.5 * i + jitter(i, 7), z = -35 - 2.5 * fabs(jitter(i, 8));
        prop_fir(&trees, bark, needles, xform_at(x, 0, z, jitter(i, 9)), 7 + 1.5 * jitter(i, 10));
    }
    object_emit(g, &trees, &(gltf_node_desc){.name = "firs", .saliency = 0.1f});

    object hills = {0};
    prop_hill(&hills, hill, xform_at(-12, 0, -52, 0), 18, 8);
    prop_hill(&hills, hill, xform_at(16, 0, -50, 0), 16, 6);
    object_emit(g, &hills, &(gltf_node_desc){.name = "hills", .saliency = 0.1f});
}

void scene_cubes_build(gltf *g)
{
    scene_camera(g, (const double[3]){0, 1.5, 0}, -3 * DEG, 45);
    scene_ground(g, TEXTURE_CHECKER, -20, -46, 20, 6, 2, 2, 0.1f);

    for (size_t i = 0; i < sizeof group / sizeof group[0]; i++) {
        const static_cube *c = &group[i];
        object o = {0};
        mesh *m = object_part_for(&o, mat(g, c->name, c->srgb[0], c->srgb[1], c->srgb[2], 0.8));
        if (m)
            mesh_box(m, xform_identity(), c->size, c->size, c->size);
        gltf_node_desc d = {
            .name = c->name,
            .translation = {(float)c->x, (float)(c->lift + c->size / 2), (float)c->z},
            .saliency = 0.5f,
        };
        quat_axis_angle(0, 1, 0, c->yaw_deg * DEG, d.rotation);
        object_emit(g, &o, &d);
    }

    build_backdrop(g);

    object flyer = {0};
    mesh *m = object_part_for(&flyer, mat(g, "flyer_red", 228, 72, 40, 0.5));
    if (m)
        mesh_box(m, xform_identity(), FLYER_SIZE, FLYER_SIZE, FLYER_SIZE);
    double p0[3];
    flyer_path(0, p0);
    gltf_node_desc d = {.name = "flying_cube", .translation = {(float)p0[0], (float)p0[1], (float)p0[2]}, .saliency = 1.0f};
    flyer_spin(0, d.rotation);
    int node = object_emit(g, &flyer, &d);
    int anim = gltf_animation_add(g, "flight");
    anim_translation(g, anim, node, flyer_path, CONTENT_SECONDS, 16, GLTF_INTERP_LINEAR);
    anim_rotation(g, anim, node, flyer_spin, CONTENT_SECONDS, 16);
}
