/* vergence — scene module internals shared by gltf.cpp and the C files.
 *
 * gltf.cpp talks to tinygltf and fills the plain structs of scene.h; the C
 * files do everything that does not need tinygltf: decoding an accessor once
 * its bytes are located (accessor.c), finishing primitives, checking the node
 * hierarchy and laying out instances (build.c), evaluation (scene.c,
 * animation.c) and cameras (camera.c). */
#pragma once
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Limits against lying headers: data-less (zero or sparse-only) accessors
 * allocate without any bytes in the file to back them, and instancing
 * multiplies vertices, so both are capped. */
#define SCENE_MAX_DATALESS_ELEMENTS (1u << 24)   /* per load, summed */
#define SCENE_MAX_INSTANCE_VERTICES (1u << 25)   /* summed over instances */
#define SCENE_MAX_INSTANCE_INDICES  (1u << 27)
#define SCENE_MAX_TEXTURE_PIXELS    (8192 * 8192)
/* Plausibility: a vertex coordinate (metres) the frame can still draw;
 * products of the view with coordinates near FLT_MAX overflow. */
#define SCENE_POSITION_MAX          1e9f

/* ------------------------------------------------------------------------- */
/* Errors: one line per failed load                                          */
/* ------------------------------------------------------------------------- */

typedef struct scene_err {
    const char *path;   /* the file as the caller named it */
    vg_status status;   /* VG_OK until the first failure */
} scene_err;

/* Logs "path: <message>" once (later failures of the same load are dropped)
 * and records the status. Always returns false, so `return scene_fail(...)`. */
bool scene_fail(scene_err *e, vg_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* ------------------------------------------------------------------------- */
/* Raw bytes (container.c)                                                   */
/* ------------------------------------------------------------------------- */

/* Checks a GLB container; on success *length is its declared length and
 * *json its JSON chunk. */
bool scene_glb_check(const uint8_t *b, size_t size, scene_err *e, uint32_t *length, const uint8_t **json,
                     size_t *json_size);
/* Checks the glTF JSON before tinygltf reads it: nesting at most 64 levels
 * deep, and no node with both a matrix and translation/rotation/scale
 * (tinygltf keeps the matrix and drops the rest silently). VG_ERR_FORMAT. */
bool scene_json_check(const uint8_t *s, size_t n, scene_err *e);
/* Decodes an encoded image (PNG, JPEG, ...) into out->rgba/width/height;
 * on failure writes the reason into why. */
bool scene_texture_decode(const uint8_t *bytes, size_t size, scene_texture *out, char *why, size_t cap);

/* ------------------------------------------------------------------------- */
/* Accessors (accessor.c)                                                    */
/* ------------------------------------------------------------------------- */

/* An accessor whose bytes gltf.cpp has located and checked to lie inside
 * their buffers; accessor.c checks everything that is relative to the view. */
typedef struct scene_accessor_desc {
    int component_type;    /* GL enum 5120..5126 */
    int components;        /* per element: 1..4, 16 for MAT4 */
    bool normalized;
    size_t count;          /* elements */
    bool has_view;         /* false: no bufferView, the accessor is all zeros */
    const uint8_t *view;   /* bufferView bytes */
    size_t view_size;
    size_t offset;         /* accessor byteOffset inside the view */
    size_t stride;         /* bufferView byteStride, 0 = tightly packed */
    /* sparse substitution (glTF 2.0 spec 3.6.2.3), sparse_count 0: none */
    size_t sparse_count;
    int sparse_index_type; /* 5121, 5123 or 5125 */
    const uint8_t *sparse_indices;
    size_t sparse_indices_size;
    const uint8_t *sparse_values;
    size_t sparse_values_size;
} scene_accessor_desc;

/* Checks every range without reading data; call before allocating the
 * output (count is only trustworthy after this). */
bool scene_accessor_check(const scene_accessor_desc *d, char *why, size_t why_cap);
/* Checks ranges and decodes to count * components floats (normalised
 * integers: unsigned c / max, signed max(c / max, -1), as in the glTF 2.0
 * spec's table in 3.11). On failure writes the reason into why. */
bool scene_accessor_floats(const scene_accessor_desc *d, float *out, char *why, size_t why_cap);
/* Same for unsigned integer data (indices, joints): u8, u16 or u32 only. */
bool scene_accessor_uints(const scene_accessor_desc *d, uint32_t *out, char *why, size_t why_cap);

/* ------------------------------------------------------------------------- */
/* Building (build.c)                                                        */
/* ------------------------------------------------------------------------- */

/* Turns a primitive's raw decoded arrays into the scene.h form: triangle
 * list indices (mode 4, 5 or 6, or none), flat normals when normals is NULL
 * (vertices are unwelded then), zero texcoords, white colours, bounds. */
bool scene_primitive_finish(scene_primitive *p, int mode, bool has_indices, scene_err *e,
                            int mesh, int prim);

/* Children of every node as given in the file (CSR: children of node n are
 * child_list[child_start[n] .. child_start[n+1]]). */
typedef struct scene_children {
    const int *child_start;
    const int *child_list;
} scene_children;

/* Checks the hierarchy (cycles), orders nodes, inherits saliency, lays out
 * instances of the default scene, checks skins against their primitives,
 * and computes duration, the animated flag and the bounds at t = 0. */
bool scene_build(scene *s, const scene_children *children, scene_err *e);

/* ------------------------------------------------------------------------- */
/* Animation (animation.c)                                                   */
/* ------------------------------------------------------------------------- */

/* Samples a sampler at t into out[components]; rotation: quaternion slerp
 * (linear) or renormalisation (cubic). */
void scene_sampler_sample(const scene_sampler *smp, float t, bool rotation, float *out);

/* ------------------------------------------------------------------------- */
/* Small math (column-major float[16], quaternions x y z w)                  */
/* ------------------------------------------------------------------------- */

void scene_mat4_identity(float m[16]);
void scene_mat4_mul(float out[16], const float a[16], const float b[16]); /* out = a * b */
void scene_mat4_from_trs(float m[16], const float t[3], const float q[4], const float s[3]);
/* General inverse; returns false (and identity) when singular. */
bool scene_mat4_invert(float out[16], const float m[16]);
void scene_quat_normalize(float q[4]);

#ifdef __cplusplus
}
#endif
