/* vergence content — a small glTF 2.0 writer (.gltf JSON + one .bin).
 *
 * The document is collected in memory and written at the end with the
 * project's deterministic JSON writer, so the same calls always give the same
 * bytes. Every accessor gets its own buffer view, 4-byte aligned. Handles are
 * 1-based ints, 0 meaning "none" (so zeroed desc structs mean "not set").
 * Colours are given as sRGB bytes, the way an artist picks them, and stored
 * as the linear factors glTF wants. */
#pragma once
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "mesh.h"

typedef struct gltf gltf;

typedef enum gltf_interp {
    GLTF_INTERP_DEFAULT = 0, /* = linear */
    GLTF_INTERP_LINEAR,
    GLTF_INTERP_CUBIC,       /* CUBICSPLINE: values are (in-tangent, value, out-tangent) per key */
} gltf_interp;

typedef enum gltf_path {
    GLTF_PATH_DEFAULT = 0, /* = translation */
    GLTF_PATH_TRANSLATION,
    GLTF_PATH_ROTATION,
    GLTF_PATH_SCALE,
    GLTF_PATH_WEIGHTS,     /* morph weights (gltf_animation_weights) */
} gltf_path;

typedef struct gltf_material_desc {
    const char *name;
    uint8_t srgb[3];    /* base colour as sRGB bytes; ignored (white) with a texture */
    int texture;        /* handle from gltf_texture_add_png, 0 = none */
    double roughness;   /* 0 = default 0.9: everything here is matte */
} gltf_material_desc;

typedef struct gltf_node_desc {
    const char *name;
    int mesh, camera;   /* handles, 0 = none */
    float translation[3];
    float rotation[4];  /* quaternion (x, y, z, w); all zero = identity */
    float saliency;     /* extras.saliency, written on every mesh node */
    int parent;         /* handle of an earlier node, 0 = a scene root */
    int skin;           /* handle from gltf_skin_add, 0 = none (skinned mesh nodes) */
} gltf_node_desc;

gltf *gltf_create(const char *scene_name, const char *description);
void gltf_destroy(gltf *g);

int gltf_texture_add_png(gltf *g, const char *name, const uint8_t *png, size_t size);
int gltf_material_add(gltf *g, const gltf_material_desc *d);
int gltf_mesh_add(gltf *g, const char *name);
/* Adds geometry as a primitive of a mesh; texture coordinates are written
 * only when the material has a texture. */
void gltf_mesh_primitive(gltf *g, int mesh, const struct mesh *geometry, int material);
int gltf_camera_add(gltf *g, const char *name, double yfov, double znear, double zfar);
/* Nodes in the order added (the camera first, by convention of
 * engine/scene: camera index 0 is the first camera node); roots unless
 * they name a parent. */
int gltf_node_add(gltf *g, const gltf_node_desc *d);

int gltf_animation_add(gltf *g, const char *name);
/* One channel: n key times (strictly increasing); values hold n (linear) or
 * 3n (cubic) elements of 3 (translation, scale) or 4 (rotation) floats. */
void gltf_animation_channel(gltf *g, int animation, int node, gltf_path path, gltf_interp interp,
                            const float *times, int n, const float *values);

/* ------------------------------------------------------------------------- */
/* Deforming meshes (gltf_deform.c)                                          */
/* ------------------------------------------------------------------------- */

/* A skin over joint nodes (handles; joints before the skinned mesh node)
 * with their inverse bind matrices (16 floats each, column-major). */
int gltf_skin_add(gltf *g, const char *name, const int *joints, int joint_count, const float *inverse_bind);
/* A skinned primitive: four joint indices (into the skin's joints) and
 * four weights per vertex, weights summing to 1, unused slots joint 0 and
 * weight 0. */
void gltf_mesh_primitive_skinned(gltf *g, int mesh, const struct mesh *geometry, int material,
                                 const uint8_t *joints, const float *weights);
/* A primitive with morph targets: per target, position and normal offsets
 * (3 floats per vertex each). */
void gltf_mesh_primitive_morph(gltf *g, int mesh, const struct mesh *geometry, int material,
                               const float *const *position_offsets, const float *const *normal_offsets,
                               int targets);
/* Default morph weights of a mesh. */
void gltf_mesh_weights(gltf *g, int mesh, const float *weights, int count);
/* A morph-weight channel: n key times, n x targets values (linear). */
void gltf_animation_weights(gltf *g, int animation, int node, const float *times, int n, const float *values,
                            int targets);

/* Records a failure (logged once); gltf_write then refuses to write. */
void gltf_fail(gltf *g, const char *what);

/* Triangle total so far (for the summary line). */
uint32_t gltf_triangles(const gltf *g);

/* Writes DIR/NAME.gltf and DIR/NAME.bin. Logs and returns an error when any
 * earlier call failed (out of memory, a table full, a bad handle). */
vg_status gltf_write(gltf *g, const char *dir, size_t *gltf_bytes, size_t *bin_bytes);
