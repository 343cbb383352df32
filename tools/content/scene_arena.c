/* arena — paper Fig. 6 and Sec. 5: the hit-prediction game. A ball is
 * thrown from near the player down a walled field; the player sees only the
 * start of the flight and clicks where it will land. The field's 1 m grid
 * and 4 m chalk lines, the marker pillars every 8 m and the walls give the
 * depth cues a player judges distance by. The game moves the node `ball` at
 * run time; the animation here is a default throw for captures and tests. */
#include <math.h>

#include "props.h"
#include "scenes.h"

/* Field (x across, z down the field; the camera stands at z = 0). */
#define FIELD_X 20.0   /* half width: the field is 40 m wide */
#define FIELD_NEAR 18.0 /* the player stands 18 m into the field, */
#define FIELD_FAR -42.0 /* so its far end is 42 m away; 60 m long */
#define WALL_H 0.8
#define WALL_T 0.3

#define BALL_R 0.25
#define GRAVITY 9.81
#define FLIGHT_S 2.0
#define ARENA_YFOV 40 /* degrees: a 0.5 m ball at 22 m is 8 px across in a 270 px high eye */

static int mat(gltf *g, const char *name, uint8_t r, uint8_t gr, uint8_t b, double roughness)
{
    return gltf_material_add(g, &(gltf_material_desc){.name = name, .srgb = {r, gr, b}, .roughness = roughness});
}

/* Default throw: launched 3.5 m in front of the player at 1 m height, lands
 * 30 m away, a little to the left, after 2 s. The apex is 5.5 m high at 16 m
 * and the ball never rises more than 16 degrees above the eye, so it stays in
 * the camera's view (22 degrees up). Pure ballistics: cubic keys with exact
 * tangents reproduce the parabola exactly. */
static void ball_path(double t, double p[3])
{
    static const double from[3] = {0.4, 1.0, -3.5}, to[3] = {-2.5, BALL_R, -30.0};
    double vy = (to[1] - from[1] + 0.5 * GRAVITY * FLIGHT_S * FLIGHT_S) / FLIGHT_S;
    p[0] = from[0] + (to[0] - from[0]) * t / FLIGHT_S;
    p[1] = from[1] + vy * t - 0.5 * GRAVITY * t * t;
    p[2] = from[2] + (to[2] - from[2]) * t / FLIGHT_S;
}

/* Low wall with a coping along the field's edges (not behind the camera). */
static void build_walls(gltf *g)
{
    int concrete = mat(g, "wall_concrete", 190, 184, 172, 0.95), coping = mat(g, "wall_coping", 140, 134, 126, 0.9);
    object o = {0};
    mesh *w = object_part_for(&o, concrete), *c = object_part_for(&o, coping);
    if (!w || !c)
        return;
    double len = FIELD_NEAR - FIELD_FAR, zc = (FIELD_NEAR + FIELD_FAR) / 2;
    for (int side = -1; side <= 1; side += 2) {
        double x = side * (FIELD_X + WALL_T / 2);
        mesh_box(w, xform_translate(x, WALL_H / 2, zc), WALL_T, WALL_H, len);
        mesh_box(c, xform_translate(x, WALL_H + 0.05, zc), WALL_T + 0.14, 0.1, len + 0.14);
    }
    double span = 2 * FIELD_X + 2 * WALL_T;
    mesh_box(w, xform_translate(0, WALL_H / 2, FIELD_FAR - WALL_T / 2), span, WALL_H, WALL_T);
    mesh_box(c, xform_translate(0, WALL_H + 0.05, FIELD_FAR - WALL_T / 2), span + 0.14, 0.1, WALL_T + 0.14);
    object_emit(g, &o, &(gltf_node_desc){.name = "walls", .saliency = 0.2f});
}

/* Marker pillars every 8 m along both sides and across the far end: a ruler
 * in depth, each with a coloured band near the top. */
static void build_pillars(gltf *g)
{
    int white = mat(g, "pillar_white", 236, 232, 222, 0.8), band = mat(g, "pillar_band", 222, 96, 78, 0.7);
    object o = {0};
    mesh *p = object_part_for(&o, white), *b = object_part_for(&o, band);
    if (!p || !b)
        return;
    for (int i = 0; i < 5; i++) {
        double z = -4 - 8 * i;
        for (int side = -1; side <= 1; side += 2) {
            xform at = xform_translate(side * (FIELD_X - 1.5), 0, z);
            mesh_cylinder(p, at, 0.25, 0.25, 2.0, 20, false);
            mesh_cylinder(b, xform_mul(at, xform_translate(0, 2.0, 0)), 0.27, 0.27, 0.4, 20, true);
        }
    }
    for (int i = -1; i <= 1; i++) {
        xform at = xform_translate(12.0 * i, 0, FIELD_FAR + 1.5);
        mesh_cylinder(p, at, 0.25, 0.25, 2.0, 20, false);
        mesh_cylinder(b, xform_mul(at, xform_translate(0, 2.0, 0)), 0.27, 0.27, 0.4, 20, true);
    }
    object_emit(g, &o, &(gltf_node_desc){.name = "pillars", .saliency = 0.2f});
}

/* Gates down the field: a pair of 3.3 m posts with a pennant at 7, 13 and
 * 17 m, each standing 0.6 m inside the edge of a 16:9 view there. Objects
 * at several depths with gaps between them (paper Fig. 1 and 2): the
 * histogram operator gives their depths more of the range and the gaps
 * less, so a ball flying through the gates speeds up and slows down in
 * depth under h (docs/content.md: measured on the ball). Near-to-far
 * flights cross the first gate while the ball is shown, far-to-near ones
 * the other two. */
#define GATE_H 3.3
static void build_gates(gltf *g)
{
    static const double dist[3] = {7.0, 13.0, 17.0};
    static const uint8_t colour[3][3] = {{232, 92, 70}, {38, 166, 154}, {244, 190, 52}};
    static const char *const pennant[3] = {"pennant_coral", "pennant_teal", "pennant_gold"};
    object o = {0};
    mesh *p = object_part_for(&o, mat(g, "gate_post", 240, 238, 230, 0.6));
    for (int i = 0; i < 3; i++) {
        mesh *f = object_part_for(&o, mat(g, pennant[i], colour[i][0], colour[i][1], colour[i][2], 0.8));
        if (!p || !f)
            return;
        double z = dist[i], x = z * tan(0.5 * ARENA_YFOV * DEG) * 16.0 / 9.0 - 0.6;
        for (int side = -1; side <= 1; side += 2) {
            mesh_cylinder(p, xform_translate(side * x, 0, -z), 0.12, 0.09, GATE_H, 16, true);
            mesh_box(f, xform_translate(side * (x - 0.75), GATE_H - 0.5, -z), 1.4, 0.9, 0.05);
        }
    }
    object_emit(g, &o, &(gltf_node_desc){.name = "gates", .saliency = 0.6f});
}

/* Firs outside the walls, a meadow around the field, hills on the horizon. */
static void build_surroundings(gltf *g)
{
    int bark = mat(g, "bark", 104, 76, 54, 1.0), needles = mat(g, "fir_needles", 58, 100, 62, 1.0);
    int hill_a = mat(g, "hill_near", 128, 160, 110, 1.0), hill_b = mat(g, "hill_far", 146, 170, 150, 1.0);

    object meadow = {0};
    int grass = ground_material(g, TEXTURE_GRASS);
    ground_rect(&meadow, grass, -60, -100, -FIELD_X - WALL_T, FIELD_NEAR + 2, 4, 4);
    ground_rect(&meadow, grass, FIELD_X + WALL_T, -100, 60, FIELD_NEAR + 2, 4, 4);
    ground_rect(&meadow, grass, -FIELD_X - WALL_T, -100, FIELD_X + WALL_T, FIELD_FAR - WALL_T, 4, 4);
    object_emit(g, &meadow, &(gltf_node_desc){.name = "meadow", .saliency = 0.05f});

    object firs = {0};
    for (int i = 0; i < 8; i++)
        for (int side = -1; side <= 1; side += 2) {
            int k = i * 2 + (side > 0);
            double x = side * (24 + 2.5 * fabs(jitter(k, 11))), z = 4 - 6.5 * i + 1.5 * jitter(k, 12);
            prop_fir(&firs, bark, needles, xform_at(x, 0, z, jitter(k, 13)), 8 + 2 * jitter(k, 14));
        }
    for (int i = 0; i < 8; i++) {
        double x = -21 + 6 * i + 1.5 * jitter(i, 15), z = FIELD_FAR - 5 - 3 * fabs(jitter(i, 16));
        prop_fir(&firs, bark, needles, xform_at(x, 0, z, jitter(i, 17)), 8.5 + 2 * jitter(i, 18));
    }
    object_emit(g, &firs, &(gltf_node_desc){.name = "firs", .saliency = 0.1f});

    object hills = {0};
    prop_hill(&hills, hill_b, xform_at(-26, 0, -66, 0), 20, 9);
    prop_hill(&hills, hill_a, xform_at(6, 0, -70, 0), 22, 11);
    prop_hill(&hills, hill_b, xform_at(34, 0, -62, 0), 18, 8);
    object_emit(g, &hills, &(gltf_node_desc){.name = "hills", .saliency = 0.05f});
}

void scene_arena_build(gltf *g)
{
    /* Eye height 1.6 m, looking 3 degrees down the field (paper Fig. 6). */
    scene_camera(g, (const double[3]){0, 1.6, 0}, -3 * DEG, ARENA_YFOV);
    scene_ground(g, TEXTURE_FIELD, -FIELD_X, FIELD_FAR, FIELD_X, FIELD_NEAR, 2, 4, 0.1f);
    build_walls(g);
    build_pillars(g);
    build_gates(g);
    build_surroundings(g);

    object ball = {0};
    mesh *m = object_part_for(&ball, mat(g, "ball_orange", 255, 140, 22, 0.45));
    if (m)
        mesh_sphere(m, xform_identity(), BALL_R, BALL_R, 32, 16);
    double p0[3];
    ball_path(0, p0);
    int node = object_emit(g, &ball, &(gltf_node_desc){
        .name = "ball", .translation = {(float)p0[0], (float)p0[1], (float)p0[2]}, .saliency = 1.0f});
    int anim = gltf_animation_add(g, "throw");
    anim_translation(g, anim, node, ball_path, FLIGHT_S, 8, GLTF_INTERP_CUBIC);
}
