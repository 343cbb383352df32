/* bird — deforming objects and camera motion, like the paper's Fig. 8: a
 * bird flaps its skinned wings as it flies from behind a windmill toward
 * the viewer, through the empty depth between the windmill and the tree
 * line that a disparity operator compresses; a flag waves (morph targets),
 * the windmill's sails turn, and the camera dollies forward and pans. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "props.h"
#include "scenes.h"

/* Flap frequency (Hz) and the joints of the skin, in skin order. */
#define FLAP_HZ 2.0
enum { J_ROOT, J_LEFT, J_LEFT_TIP, J_RIGHT, J_RIGHT_TIP, J_COUNT };

/* The bird's bind pose (metres; +Z forward, +X right) is modelled at unit
 * size and scaled by BIRD_SCALE: a large bird, 2.5 m from tip to tip. */
#define BIRD_SCALE 1.3
#define SHOULDER_X (0.09 * BIRD_SCALE)
#define SHOULDER_Y (0.04 * BIRD_SCALE)
#define ELBOW (0.42 * BIRD_SCALE) /* shoulder to the outer joint, along the span */
#define SPAN (0.86 * BIRD_SCALE)  /* shoulder to the wing tip */

static int mat(gltf *g, const char *name, uint8_t r, uint8_t gr, uint8_t b, double roughness)
{
    return gltf_material_add(g, &(gltf_material_desc){.name = name, .srgb = {r, gr, b}, .roughness = roughness});
}

/* ------------------------------------------------------------------------- */
/* Paths                                                                     */
/* ------------------------------------------------------------------------- */

/* 36 m behind the camera's start to 4.5 m in front of its end, 8 m/s in
 * depth, a slow S-curve and a gentle sink. */
static void bird_path(double t, double p[3])
{
    p[0] = 1.4 - 0.45 * t + 0.55 * sin(2 * PI * t / 3.0);
    p[1] = 5.2 - 0.55 * t + 0.1 * sin(2 * PI * t * 0.8);
    p[2] = -36.0 + 8.0 * t;
}

/* Heading along the path, banking into the curve. */
static void bird_heading(double t, float q[4])
{
    const double h = 1e-3;
    double a[3], b[3];
    bird_path(t - h, a);
    bird_path(t + h, b);
    double yaw = atan2(b[0] - a[0], b[2] - a[2]);
    float qy[4], qr[4];
    quat_axis_angle(0, 1, 0, yaw, qy);
    quat_axis_angle(0, 0, 1, -1.4 * yaw, qr);
    quat_mul(qy, qr, q);
}

static double flap(double t, double lag)
{
    return sin(2 * PI * FLAP_HZ * t - lag);
}

/* Shoulders: 40 degrees up and down around a slight dihedral. */
static void wing_left(double t, float q[4])
{
    quat_axis_angle(0, 0, 1, -(8 * DEG + 40 * DEG * flap(t, 0)), q);
}
static void wing_right(double t, float q[4])
{
    quat_axis_angle(0, 0, 1, 8 * DEG + 40 * DEG * flap(t, 0), q);
}
/* The outer wing follows a little later and bends less. */
static void tip_left(double t, float q[4])
{
    quat_axis_angle(0, 0, 1, -(22 * DEG * flap(t, 0.9)), q);
}
static void tip_right(double t, float q[4])
{
    quat_axis_angle(0, 0, 1, 22 * DEG * flap(t, 0.9), q);
}

/* The camera dollies 2.8 m forward and pans slowly after the bird. */
static void camera_path(double t, double p[3])
{
    p[0] = 0.5 - 0.12 * t;
    p[1] = 1.6 - 0.02 * t;
    p[2] = 3.0 - 0.7 * t;
}
static void camera_turn(double t, float q[4])
{
    float yaw[4], pitch[4];
    quat_axis_angle(0, 1, 0, (4.0 - 1.8 * t) * DEG, yaw);
    quat_axis_angle(1, 0, 0, (7.0 + 1.0 * t) * DEG, pitch);
    quat_mul(yaw, pitch, q);
}

/* The sails turn a quarter revolution per second (anticlockwise as seen). */
static void sails_turn(double t, float q[4])
{
    quat_axis_angle(0, 0, 1, 2 * PI * 0.25 * t, q);
}

/* ------------------------------------------------------------------------- */
/* Bird: a skinned mesh                                                      */
/* ------------------------------------------------------------------------- */

/* One wing, span segments from the shoulder out, flat plates 2 cm thick. */
static void build_wing(mesh *m, double side)
{
    enum { SEGMENTS = 8 };
    for (int i = 0; i < SEGMENTS; i++) {
        double s0 = (double)i / SEGMENTS, s1 = (double)(i + 1) / SEGMENTS;
        /* Chord: 0.34 m at the root tapering to a rounded 0.1 m tip, swept back. */
        const double S = BIRD_SCALE;
        double c0 = S * (0.34 - 0.22 * s0 * s0), c1 = S * (0.34 - 0.22 * s1 * s1);
        double x0 = SHOULDER_X + 0.02 + (SPAN - 0.02) * s0, x1 = SHOULDER_X + 0.02 + (SPAN - 0.02) * s1;
        double lead0 = S * (0.16 - 0.12 * s0), lead1 = S * (0.16 - 0.12 * s1);
        /* A convex quad in the XZ plane: the prism's polygon is in XY and is
         * extruded along Z, so rotate it onto the wing's plane. */
        double poly[4][2] = {{x0, lead0}, {x0, lead0 - c0}, {x1, lead1 - c1}, {x1, lead1}};
        if (side < 0)
            for (int k = 0; k < 4; k++)
                poly[k][0] = -poly[k][0];
        double ordered[4][2];
        for (int k = 0; k < 4; k++)
            memcpy(ordered[k], poly[side < 0 ? 3 - k : k], sizeof ordered[k]);
        xform x = xform_axis_angle(1, 0, 0, PI / 2);
        x.t[1] = SHOULDER_Y;
        mesh_prism(m, x, (const double(*)[2])ordered, 4, 0.025 * BIRD_SCALE);
    }
}

static void build_body(mesh *body, mesh *beak)
{
    const double S = BIRD_SCALE;
    /* Body along +Z: a spheroid revolved about Y, turned onto Z. */
    xform along = xform_axis_angle(1, 0, 0, PI / 2);
    mesh_sphere(body, along, 0.13 * S, 0.30 * S, 20, 12);
    mesh_sphere(body, xform_translate(0, 0.09 * S, 0.27 * S), 0.095 * S, 0.095 * S, 16, 10);
    xform tail = xform_axis_angle(1, 0, 0, -PI / 2 + 0.15);
    tail.t[1] = 0.02 * S;
    tail.t[2] = -0.26 * S;
    mesh_cone(body, tail, 0.08 * S, 0.22 * S, 10);
    xform bill = xform_axis_angle(1, 0, 0, PI / 2);
    bill.t[1] = 0.08 * S;
    bill.t[2] = 0.35 * S;
    mesh_cone(beak, bill, 0.03 * S, 0.1 * S, 10);
}

/* Joint weights from the bind-pose position: the body and the inner wing
 * blend over the shoulder, the inner and outer wing over the elbow. */
static void skin_weights(const mesh *m, uint8_t *joints, float *weights)
{
    for (uint32_t v = 0; v < m->vcount; v++) {
        double x = m->pos[3 * v], span = fabs(x) - SHOULDER_X;
        int inner = x < 0 ? J_LEFT : J_RIGHT, outer = x < 0 ? J_LEFT_TIP : J_RIGHT_TIP;
        uint8_t *j = joints + 4 * v;
        float *w = weights + 4 * v;
        memset(j, 0, 4);
        memset(w, 0, 4 * sizeof *w);
        double a = (span + 0.04 * BIRD_SCALE) / (0.08 * BIRD_SCALE); /* 0 -> 1 across the shoulder */
        double b = (span - ELBOW + 0.06 * BIRD_SCALE) / (0.12 * BIRD_SCALE);
        if (a <= 0) {
            j[0] = J_ROOT;
            w[0] = 1;
        } else if (a < 1) {
            j[0] = (uint8_t)inner;
            j[1] = J_ROOT;
            w[0] = (float)a;
            w[1] = 1.0f - w[0];
        } else if (b <= 0) {
            j[0] = (uint8_t)inner;
            w[0] = 1;
        } else if (b < 1) {
            j[0] = (uint8_t)outer;
            j[1] = (uint8_t)inner;
            w[0] = (float)b;
            w[1] = 1.0f - w[0];
        } else {
            j[0] = (uint8_t)outer;
            w[0] = 1;
        }
    }
}

static void emit_skinned(gltf *g, int mesh_h, const mesh *m, int material)
{
    uint8_t *joints = malloc(4 * (size_t)m->vcount);
    float *weights = malloc(4 * sizeof(float) * (size_t)m->vcount);
    if (!joints || !weights || m->failed)
        gltf_fail(g, "out of memory for the bird's skin");
    else {
        skin_weights(m, joints, weights);
        gltf_mesh_primitive_skinned(g, mesh_h, m, material, joints, weights);
    }
    free(joints);
    free(weights);
}

/* Joint nodes, the skin and the skinned mesh node (a root without a
 * transform: glTF skins place it through the joints). */
static void build_bird(gltf *g)
{
    int plumage = mat(g, "plumage", 70, 84, 110, 0.7), wings = mat(g, "wing_feathers", 232, 226, 214, 0.8);
    int beak = mat(g, "beak", 236, 160, 40, 0.5);
    mesh body = {0}, wing = {0}, bill = {0};
    build_body(&body, &bill);
    build_wing(&wing, -1);
    build_wing(&wing, 1);

    double p0[3];
    bird_path(0, p0);
    gltf_node_desc root = {.name = "bird_root", .translation = {(float)p0[0], (float)p0[1], (float)p0[2]}};
    bird_heading(0, root.rotation);
    int j[J_COUNT];
    j[J_ROOT] = gltf_node_add(g, &root);
    const struct {
        const char *name;
        int parent;
        double x, y;
        orient_fn turn;
    } limbs[] = {
        {"wing_left", J_ROOT, -SHOULDER_X, SHOULDER_Y, wing_left},
        {"wing_left_tip", J_LEFT, -ELBOW, 0, tip_left},
        {"wing_right", J_ROOT, SHOULDER_X, SHOULDER_Y, wing_right},
        {"wing_right_tip", J_RIGHT, ELBOW, 0, tip_right},
    };
    /* Inverse bind matrices: each joint's bind-pose frame is a translation. */
    float ibm[J_COUNT][16] = {{0}};
    double bind[J_COUNT][2] = {{0, 0}};
    for (int k = 0; k < J_COUNT; k++)
        ibm[k][0] = ibm[k][5] = ibm[k][10] = ibm[k][15] = 1;
    for (int k = 0; k < 4; k++) {
        gltf_node_desc d = {.name = limbs[k].name, .parent = j[limbs[k].parent],
                            .translation = {(float)limbs[k].x, (float)limbs[k].y, 0}};
        limbs[k].turn(0, d.rotation);
        j[k + 1] = gltf_node_add(g, &d);
        bind[k + 1][0] = bind[limbs[k].parent][0] + limbs[k].x;
        bind[k + 1][1] = bind[limbs[k].parent][1] + limbs[k].y;
        ibm[k + 1][12] = (float)-bind[k + 1][0];
        ibm[k + 1][13] = (float)-bind[k + 1][1];
    }
    int skin = gltf_skin_add(g, "bird_skin", j, J_COUNT, &ibm[0][0]);
    int m = gltf_mesh_add(g, "bird");
    emit_skinned(g, m, &body, plumage);
    emit_skinned(g, m, &wing, wings);
    emit_skinned(g, m, &bill, beak);
    mesh_free(&body);
    mesh_free(&wing);
    mesh_free(&bill);
    gltf_node_add(g, &(gltf_node_desc){.name = "bird", .mesh = m, .skin = skin, .saliency = 1.0f});

    int anim = gltf_animation_add(g, "bird_flight");
    anim_translation(g, anim, j[J_ROOT], bird_path, CONTENT_SECONDS, 24, GLTF_INTERP_CUBIC);
    anim_rotation(g, anim, j[J_ROOT], bird_heading, CONTENT_SECONDS, 40);
    /* Keys every 1/30 s: a 2 Hz flap is smooth under slerp. */
    for (int k = 0; k < 4; k++)
        anim_rotation(g, anim, j[k + 1], limbs[k].turn, CONTENT_SECONDS, 120);
}

/* ------------------------------------------------------------------------- */
/* Flag: morph targets                                                       */
/* ------------------------------------------------------------------------- */

#define FLAG_W 1.5
#define FLAG_H 0.95
#define FLAG_NX 24
#define FLAG_NY 8

/* A wave travelling away from the pole, z = A s sin(k s + phase), is the sum
 * of two fixed shapes weighted by cos(phase) and sin(phase). */
static void build_flag(gltf *g, int cloth)
{
    mesh m = {0};
    mesh_grid(&m, 0, 0, FLAG_W, FLAG_H, FLAG_NX, FLAG_NY, 1.0);
    /* mesh_grid makes an XZ ground facing +Y: turn it upright, facing +Z. */
    size_t n = m.vcount;
    float *dp[2] = {calloc(3 * n, sizeof(float)), calloc(3 * n, sizeof(float))};
    float *dn[2] = {calloc(3 * n, sizeof(float)), calloc(3 * n, sizeof(float))};
    if (!dp[0] || !dp[1] || !dn[0] || !dn[1] || m.failed)
        gltf_fail(g, "out of memory for the flag");
    else {
        const double amp = 0.14, k = 2 * PI * 1.3;
        for (size_t v = 0; v < n; v++) {
            double x = m.pos[3 * v], z = m.pos[3 * v + 2];
            m.pos[3 * v + 1] = (float)(FLAG_H - z);
            m.pos[3 * v + 2] = 0;
            m.nrm[3 * v + 1] = 0;
            m.nrm[3 * v + 2] = 1;
            double s = x / FLAG_W;
            /* Shape 0: A s sin(k s); shape 1: A s cos(k s); slopes along x. */
            double z0 = amp * s * sin(k * s), z1 = amp * s * cos(k * s);
            double d0 = amp / FLAG_W * (sin(k * s) + s * k * cos(k * s));
            double d1 = amp / FLAG_W * (cos(k * s) - s * k * sin(k * s));
            dp[0][3 * v + 2] = (float)z0;
            dp[1][3 * v + 2] = (float)z1;
            dn[0][3 * v] = (float)-d0;
            dn[1][3 * v] = (float)-d1;
        }
        /* The grid's triangles faced +Y; turning y into -z kept them
         * counter-clockwise seen from +Z. */
        int mh = gltf_mesh_add(g, "flag");
        gltf_mesh_primitive_morph(g, mh, &m, cloth, (const float *const *)dp, (const float *const *)dn, 2);
        gltf_mesh_weights(g, mh, (const float[2]){1, 0}, 2);
        /* Turned 35 degrees away from the camera, so the waves show. */
        gltf_node_desc fd = {.name = "flag", .mesh = mh, .translation = {2.64f, 3.0f, -9.0f}, .saliency = 0.5f};
        quat_axis_angle(0, 1, 0, 35 * DEG, fd.rotation);
        int node = gltf_node_add(g, &fd);
        enum { KEYS = 121 };
        float times[KEYS], w[2 * KEYS];
        for (int i = 0; i < KEYS; i++) {
            double t = CONTENT_SECONDS * (double)i / (KEYS - 1), phase = -2 * PI * 1.1 * t;
            times[i] = (float)t;
            w[2 * i] = (float)cos(phase);
            w[2 * i + 1] = (float)sin(phase);
        }
        int anim = gltf_animation_add(g, "flag_wave");
        gltf_animation_weights(g, anim, node, times, KEYS, w, 2);
    }
    for (int t = 0; t < 2; t++) {
        free(dp[t]);
        free(dn[t]);
    }
    mesh_free(&m);
}

/* ------------------------------------------------------------------------- */
/* Landmarks                                                                 */
/* ------------------------------------------------------------------------- */

static void build_windmill(gltf *g)
{
    int plaster = mat(g, "windmill_plaster", 236, 228, 212, 0.9), cap = mat(g, "windmill_cap", 92, 70, 60, 0.8);
    int sail = mat(g, "sail_cloth", 244, 240, 230, 0.9), wood = mat(g, "sail_wood", 120, 88, 62, 0.9);
    object mill = {0};
    mesh *walls = object_part_for(&mill, plaster), *roof = object_part_for(&mill, cap);
    if (walls && roof) {
        mesh_cylinder(walls, xform_identity(), 1.7, 1.1, 7.0, 24, true);
        mesh_cone(roof, xform_translate(0, 7.0, 0), 1.35, 1.5, 24);
        mesh_box(roof, xform_translate(0, 1.0, 1.62), 0.8, 2.0, 0.1); /* door */
    }
    object_emit(g, &mill, &(gltf_node_desc){.name = "windmill", .translation = {-5.6f, 0, -17.0f}, .saliency = 0.3f});

    object sails = {0};
    mesh *cloth = object_part_for(&sails, sail), *spars = object_part_for(&sails, wood);
    if (cloth && spars) {
        mesh_cylinder(spars, xform_axis_angle(1, 0, 0, PI / 2), 0.18, 0.18, 0.4, 12, true);
        for (int b = 0; b < 4; b++) {
            xform arm = xform_axis_angle(0, 0, 1, b * PI / 2);
            mesh_box(spars, xform_mul(arm, xform_translate(0, 1.9, 0.3)), 0.1, 3.8, 0.08);
            mesh_box(cloth, xform_mul(arm, xform_translate(0.3, 2.25, 0.33)), 0.5, 2.9, 0.03);
        }
    }
    gltf_node_desc sd = {.name = "sails", .translation = {-5.6f, 6.3f, -15.3f}, .saliency = 0.3f};
    int node = object_emit(g, &sails, &sd);
    int anim = gltf_animation_add(g, "sails_turn");
    anim_rotation(g, anim, node, sails_turn, CONTENT_SECONDS, 40);
}

static void build_backdrop(gltf *g, int flag_cloth)
{
    int bark = mat(g, "bark", 104, 76, 54, 1.0), needles = mat(g, "fir_needles", 58, 100, 62, 1.0);
    int leaves[3] = {mat(g, "leaves_dark", 72, 128, 60, 0.9), mat(g, "leaves", 92, 150, 70, 0.9),
                     mat(g, "leaves_light", 118, 170, 82, 0.9)};
    int hill_a = mat(g, "hill_near", 128, 160, 110, 1.0), hill_b = mat(g, "hill_far", 140, 166, 138, 1.0);
    int pole = mat(g, "flag_pole", 210, 210, 205, 0.5);

    object tree = {0};
    prop_broadleaf(&tree, bark, leaves, xform_identity(), 7.0);
    object_emit(g, &tree, &(gltf_node_desc){.name = "tree", .translation = {5.2f, 0, -15.0f}, .saliency = 0.3f});

    object mast = {0};
    mesh *pm = object_part_for(&mast, pole);
    if (pm) {
        mesh_cylinder(pm, xform_identity(), 0.05, 0.035, 4.1, 10, true);
        mesh_sphere(pm, xform_translate(0, 4.12, 0), 0.07, 0.07, 10, 6);
    }
    object_emit(g, &mast, &(gltf_node_desc){.name = "flag_pole", .translation = {2.6f, 0, -9.0f}, .saliency = 0.3f});
    build_flag(g, flag_cloth);

    object firs = {0};
    for (int i = 0; i < 12; i++) {
        double x = -24 + 4.3 * i + 1.3 * jitter(i, 7), z = -36 - 4 * fabs(jitter(i, 8));
        prop_fir(&firs, bark, needles, xform_at(x, 0, z, jitter(i, 9)), 7.0 + 2 * jitter(i, 10));
    }
    prop_fir(&firs, bark, needles, xform_at(12, 0, -22, 0.4), 8.5);
    object_emit(g, &firs, &(gltf_node_desc){.name = "firs", .saliency = 0.1f});

    object hills = {0};
    prop_hill(&hills, hill_b, xform_at(-22, 0, -56, 0), 18, 8);
    prop_hill(&hills, hill_a, xform_at(6, 0, -60, 0), 22, 10);
    prop_hill(&hills, hill_b, xform_at(30, 0, -52, 0), 16, 7);
    object_emit(g, &hills, &(gltf_node_desc){.name = "hills", .saliency = 0.1f});
}

/* ------------------------------------------------------------------------- */
/* Scene                                                                     */
/* ------------------------------------------------------------------------- */

void scene_bird_build(gltf *g)
{
    double c0[3];
    camera_path(0, c0);
    int cam = scene_camera(g, c0, 7.0 * DEG, 50);
    scene_ground(g, TEXTURE_GRASS, -44, -66, 44, 10, 2, 4, 0.1f);
    int cloth = mat(g, "flag_cloth", 236, 178, 40, 0.8);
    build_windmill(g);
    build_backdrop(g, cloth);
    build_bird(g);

    int anim = gltf_animation_add(g, "camera_dolly");
    anim_translation(g, anim, cam, camera_path, CONTENT_SECONDS, 8, GLTF_INTERP_CUBIC);
    anim_rotation(g, anim, cam, camera_turn, CONTENT_SECONDS, 20);
}
