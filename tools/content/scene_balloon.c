/* balloon — paper Fig. 1: a red balloon flies from far behind, between a
 * house and a tree, up to the viewer. Disparity compression of the empty
 * depth between those landmarks makes the balloon speed up and slow down in
 * depth; the optimisation restores the smooth approach. */
#include <math.h>

#include "props.h"
#include "scenes.h"

/* House footprint and shape (metres, house-local: front faces +Z). */
#define HOUSE_W 5.0    /* along x */
#define HOUSE_D 4.0    /* along z */
#define HOUSE_H 3.0    /* wall height */
#define ROOF_PITCH (38 * DEG)
#define ROOF_T 0.16    /* slab thickness */

#define BALLOON_R 0.40

typedef struct balloon_materials {
    int walls, roof, door, window, chimney, bark, leaves[3];
} balloon_materials;

/* ------------------------------------------------------------------------- */
/* House                                                                     */
/* ------------------------------------------------------------------------- */

/* One roof slab resting on the gable edge; side +1 is the front (+Z) slope. */
static void roof_slab(mesh *m, xform at, int side)
{
    double rise = HOUSE_D / 2 * tan(ROOF_PITCH), s = hypot(HOUSE_D / 2, rise);
    /* Rotating about X by the pitch maps local +Z onto the slope (down to the
     * eave) and local +Y onto its outward normal. */
    double c = HOUSE_D / 2 / s, sn = rise / s;
    double eave = 0.35, past_ridge = 0.06, len = s + eave + past_ridge, shift = (eave - past_ridge) / 2;
    double mid[3] = {0, HOUSE_H + rise / 2, side * HOUSE_D / 4};
    double nrm[3] = {0, c, side * sn}, down[3] = {0, -sn, side * c};
    xform x = xform_axis_angle(1, 0, 0, side * ROOF_PITCH);
    for (int k = 0; k < 3; k++)
        x.t[k] = mid[k] + nrm[k] * ROOF_T / 2 + down[k] * shift;
    mesh_box(m, xform_mul(at, x), HOUSE_W + 0.6, ROOF_T, len);
}

/* Thin box on a wall: doors and windows stand 4 cm proud of the facade. */
static void facade_box(mesh *m, xform at, double x, double y, double z, double yaw, double w, double h)
{
    mesh_box(m, xform_mul(at, xform_at(x, y, z, yaw)), w, h, 0.08);
}

static void build_house(object *o, const balloon_materials *mt, xform at)
{
    mesh *walls = object_part_for(o, mt->walls), *roof = object_part_for(o, mt->roof);
    mesh *door = object_part_for(o, mt->door), *win = object_part_for(o, mt->window);
    mesh *chimney = object_part_for(o, mt->chimney);
    if (!walls || !roof || !door || !win || !chimney)
        return;
    double rise = HOUSE_D / 2 * tan(ROOF_PITCH);
    mesh_box(walls, xform_mul(at, xform_translate(0, HOUSE_H / 2, 0)), HOUSE_W, HOUSE_H, HOUSE_D);
    /* Gable: a triangle in the house's YZ plane, extruded along x. */
    const double gable[3][2] = {{-HOUSE_D / 2, 0}, {HOUSE_D / 2, 0}, {0, rise}};
    mesh_prism(walls, xform_mul(at, xform_at(0, HOUSE_H, 0, PI / 2)), gable, 3, HOUSE_W - 0.02);
    roof_slab(roof, at, 1);
    roof_slab(roof, at, -1);
    mesh_box(chimney, xform_mul(at, xform_translate(1.3, HOUSE_H + rise * 0.75, -0.7)), 0.55, rise * 1.2, 0.55);

    double front = HOUSE_D / 2, side = HOUSE_W / 2;
    facade_box(door, at, 0.55, 1.0, front, 0, 0.95, 2.0);
    facade_box(win, at, -1.45, 1.75, front, 0, 1.0, 0.95);
    facade_box(win, at, 1.85, 1.75, front, 0, 0.8, 0.95);
    /* The gable end facing the balloon's path gets two windows, one up in the gable. */
    facade_box(win, at, side, 1.7, 0.4, PI / 2, 1.1, 0.95);
    facade_box(win, at, side, HOUSE_H + 0.55, 0, PI / 2, 0.6, 0.6);
    facade_box(win, at, -side, 1.7, 0, PI / 2, 1.1, 0.95);
    /* Door step: a low slab in front of the door. */
    mesh_box(chimney, xform_mul(at, xform_translate(0.55, 0.06, front + 0.35)), 1.4, 0.12, 0.7);
}

/* ------------------------------------------------------------------------- */
/* Balloon                                                                   */
/* ------------------------------------------------------------------------- */

/* Body: a sphere stretched upward and tapered at the bottom into a teardrop. */
static void build_balloon(object *o, int rubber, int string)
{
    mesh *body = object_part_for(o, rubber), *cord = object_part_for(o, string);
    if (!body || !cord)
        return;
    enum { RINGS = 20 };
    profile_pt p[RINGS + 1];
    for (int i = 0; i <= RINGS; i++) {
        double phi = PI * i / RINGS, c = -cos(phi), s = sin(phi);
        double taper = c < 0 ? 1 - 0.22 * c * c : 1; /* narrower towards the knot */
        p[i] = (profile_pt){.r = BALLOON_R * s * taper, .y = BALLOON_R * c * (c < 0 ? 1.25 : 1.1)};
    }
    p[0].r = 0;
    p[RINGS].r = 0;
    profile_auto_normals(p, RINGS + 1);
    mesh_revolve(body, xform_identity(), p, RINGS + 1, 32);
    double bottom = -BALLOON_R * 1.25;
    /* Knot: a small flared neck under the body. */
    mesh_cylinder(body, xform_translate(0, bottom - 0.05, 0), 0.035, 0.012, 0.07, 12, true);
    /* String: a gentle S-curve hanging 1.2 m below the knot. */
    enum { N = 16 };
    double pts[N][3];
    for (int i = 0; i < N; i++) {
        double s = (double)i / (N - 1);
        pts[i][0] = 0.05 * sin(PI * s * 1.5);
        pts[i][1] = bottom - 0.04 - 1.2 * s;
        pts[i][2] = 0.03 * sin(PI * s);
    }
    mesh_tube(cord, (const double(*)[3])pts, N, 0.006, 6);
}

/* The flight: 25 m behind the camera plane at t = 0 to 3 m at t = 4 s, at a
 * constant depth speed of 5.5 m/s, so the original disparity changes
 * smoothly (paper Fig. 1); a slow sideways drift and a bob make it float. */
static void balloon_path(double t, double p[3])
{
    p[0] = 1.0 - 0.34 * t + 0.22 * sin(2 * PI * t / 3.2);
    p[1] = 2.7 - 0.2 * t + 0.12 * sin(2 * PI * t / 1.7);
    p[2] = -25.0 + 5.5 * t;
}

/* A gentle sway about the knot's vertical. */
static void balloon_sway(double t, float q[4])
{
    float roll[4], pitch[4];
    quat_axis_angle(0, 0, 1, 7 * DEG * sin(2 * PI * t / 2.1), roll);
    quat_axis_angle(1, 0, 0, 5 * DEG * sin(2 * PI * t / 2.9 + 1.0), pitch);
    quat_mul(roll, pitch, q);
}

/* ------------------------------------------------------------------------- */
/* Scene                                                                     */
/* ------------------------------------------------------------------------- */

static int mat(gltf *g, const char *name, uint8_t r, uint8_t gr, uint8_t b, double roughness)
{
    return gltf_material_add(g, &(gltf_material_desc){.name = name, .srgb = {r, gr, b}, .roughness = roughness});
}

/* Background: firs along the edge of the meadow and low hills behind them. */
static void build_backdrop(gltf *g, int bark, int needles, int hill_a, int hill_b)
{
    object firs = {0};
    for (int i = 0; i < 11; i++) {
        double x = -20 + 4 * i + 1.2 * jitter(i, 1), z = -33 - 3 * fabs(jitter(i, 2));
        if (fabs(x) < 3)
            z -= 4; /* keep the gap behind the balloon's start open a little deeper */
        prop_fir(&firs, bark, needles, xform_at(x, 0, z, jitter(i, 3)), 6.5 + 2 * jitter(i, 4));
    }
    /* Two nearer firs frame the middle ground at the sides. */
    prop_fir(&firs, bark, needles, xform_at(-11, 0, -19, 0.3), 7.5);
    prop_fir(&firs, bark, needles, xform_at(10.5, 0, -21, 1.1), 8.0);
    object_emit(g, &firs, &(gltf_node_desc){.name = "firs", .saliency = 0.1f});

    object hills = {0};
    prop_hill(&hills, hill_a, xform_at(-18, 0, -50, 0), 16, 7);
    prop_hill(&hills, hill_b, xform_at(4, 0, -54, 0), 20, 9);
    prop_hill(&hills, hill_a, xform_at(26, 0, -48, 0), 15, 6);
    object_emit(g, &hills, &(gltf_node_desc){.name = "hills", .saliency = 0.1f});
}

void scene_balloon_build(gltf *g)
{
    scene_camera(g, (const double[3]){0, 1.7, 0}, 4 * DEG, 45);
    scene_ground(g, TEXTURE_GRASS, -40, -60, 40, 6, 2, 4, 0.1f);

    balloon_materials mt = {
        .walls = mat(g, "house_walls", 238, 226, 200, 0.9),
        .roof = mat(g, "roof_tiles", 178, 82, 60, 0.8),
        .door = mat(g, "door", 96, 62, 44, 0.7),
        .window = mat(g, "window", 62, 78, 98, 0.3),
        .chimney = mat(g, "brick", 150, 84, 70, 0.9),
        .bark = mat(g, "bark", 104, 76, 54, 1.0),
        .leaves = {mat(g, "leaves_dark", 72, 128, 60, 0.9), mat(g, "leaves", 92, 150, 70, 0.9),
                   mat(g, "leaves_light", 118, 170, 82, 0.9)},
    };
    int rubber = mat(g, "balloon_red", 214, 36, 56, 0.35);
    int string = mat(g, "string", 236, 230, 218, 0.9);
    int needles = mat(g, "fir_needles", 58, 100, 62, 1.0);
    int hill_a = mat(g, "hill_near", 128, 160, 110, 1.0), hill_b = mat(g, "hill_far", 140, 166, 138, 1.0);

    /* The house stands left of the path, turned 20 degrees so both its front
     * and the gable facing the path are lit and visible. */
    object house = {0};
    build_house(&house, &mt, xform_identity());
    gltf_node_desc hd = {.name = "house", .translation = {-4.3f, 0, -11.5f}, .saliency = 0.3f};
    quat_axis_angle(0, 1, 0, -20 * DEG, hd.rotation);
    object_emit(g, &house, &hd);

    /* The tree stands right of the path, a 3 m gap from the house's corner. */
    object tree = {0};
    prop_broadleaf(&tree, mt.bark, mt.leaves, xform_identity(), 6.5);
    object_emit(g, &tree, &(gltf_node_desc){.name = "tree", .translation = {4.2f, 0, -12.5f}, .saliency = 0.3f});

    build_backdrop(g, mt.bark, needles, hill_a, hill_b);

    object balloon = {0};
    build_balloon(&balloon, rubber, string);
    double p0[3];
    balloon_path(0, p0);
    gltf_node_desc bd = {.name = "balloon", .translation = {(float)p0[0], (float)p0[1], (float)p0[2]}, .saliency = 1.0f};
    balloon_sway(0, bd.rotation);
    int node = object_emit(g, &balloon, &bd);
    int anim = gltf_animation_add(g, "balloon_flight");
    /* Cubic keys every 0.25 s with exact tangents: smooth velocity in depth. */
    anim_translation(g, anim, node, balloon_path, CONTENT_SECONDS, 16, GLTF_INTERP_CUBIC);
    anim_rotation(g, anim, node, balloon_sway, CONTENT_SECONDS, 40);
}
