/* vergence content — building blocks shared by the scenes: objects made of
 * per-material parts, the camera, the textured ground, trees and hills. */
#pragma once
#include "gltf.h"
#include "mesh.h"
#include "texture.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

/* Content frame rate and length (DESIGN.md: 60 Hz; 4 s clips). */
#define CONTENT_FPS 60
#define CONTENT_SECONDS 4

#define OBJECT_MAX_PARTS 8

/* An object under construction: one mesh per material, emitted as one glTF
 * node whose mesh has a primitive per material. */
typedef struct object_part {
    int material;
    mesh geo;
} object_part;

typedef struct object {
    object_part parts[OBJECT_MAX_PARTS];
    int part_count;
    bool failed;
} object;

/* The mesh collecting the triangles of one material (NULL when full). */
mesh *object_part_for(object *o, int material);
/* Adds the object as a node (mesh named like the node) and frees its meshes.
 * Returns the node handle, 0 on failure (already logged by the writer). */
int object_emit(gltf *g, object *o, const gltf_node_desc *d);
void object_free(object *o);

/* Perspective camera node at pos, pitched by `pitch` radians (negative looks
 * down), looking down -Z. Added first so it is the scene's camera 0. */
int scene_camera(gltf *g, const double pos[3], double pitch, double yfov_deg);

/* Material with a procedural ground texture of the given kind. */
int ground_material(gltf *g, texture_kind kind);
/* Flat rectangle [x0, x1] x [z0, z1] in cells of `cell` metres, the texture
 * repeating every `tile` metres. */
void ground_rect(object *o, int material, double x0, double z0, double x1, double z1, double cell, double tile);
/* A node "ground" made of one textured rectangle. */
int scene_ground(gltf *g, texture_kind kind, double x0, double z0, double x1, double z1,
                 double cell, double tile, float saliency);

/* Conifer: trunk and three stacked cones, `height` metres tall. */
void prop_fir(object *o, int bark, int needles, xform at, double height);
/* Broadleaf tree: tapered trunk and a crown of three stacked spheroids
 * (the "layered crown" of paper Fig. 1), each in its own shade. */
void prop_broadleaf(object *o, int bark, const int leaves[3], xform at, double height);
/* Smooth hill of base radius r and height h (a revolved bell curve), sunk a
 * little into the ground so no gap shows at its foot. */
void prop_hill(object *o, int material, xform at, double r, double h);

/* Rotation quaternion (x, y, z, w) about an axis, as floats. */
void quat_axis_angle(double ax, double ay, double az, double angle, float q[4]);
/* Quaternion product a * b (apply b, then a), renormalised. */
void quat_mul(const float a[4], const float b[4], float out[4]);
/* Deterministic jitter in [-1, 1] for placing the i-th of a set of props. */
double jitter(int i, int salt);

/* ------------------------------------------------------------------------- */
/* Animation from analytic paths                                             */
/* ------------------------------------------------------------------------- */

typedef void (*path_fn)(double t, double out[3]);
typedef void (*orient_fn)(double t, float q[4]);

/* Translation channel sampled from f at intervals + 1 evenly spaced keys over
 * [0, duration]. Cubic keys carry f's derivative as both tangents (units per
 * second, as glTF's CUBICSPLINE wants), so any path of degree <= 3 between
 * keys (a ballistic arc, a straight line) is reproduced exactly. */
void anim_translation(gltf *g, int anim, int node, path_fn f, double duration, int intervals, gltf_interp interp);
/* Rotation channel, LINEAR (glTF slerps between keys). */
void anim_rotation(gltf *g, int anim, int node, orient_fn f, double duration, int intervals);
