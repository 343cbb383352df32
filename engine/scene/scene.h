/* vergence — scenes: glTF 2.0 loading and evaluation at any time t.
 *
 * scene_load() reads .gltf or .glb through tinygltf (wrapped in gltf.cpp, the
 * module's only C++ file) and converts everything into the plain C
 * arrays below: every accessor is decoded to float or uint32 (normalised
 * integers, byte strides, sparse accessors applied), missing attributes are
 * filled (flat normals, zero texcoords, white colours), and non-indexed
 * primitives get indices 0..n-1. After loading, nothing refers to tinygltf.
 *
 * scene_evaluate() samples every animation at time t (times past the end hold
 * the last key), composes the node hierarchy, applies morph targets and skins,
 * and writes world-space positions and normals of every drawn vertex into a
 * scene_state. Later passes evaluate at other times to look ahead (motion
 * vectors, predicted keyframes).
 *
 * Conventions: right-handed, +Y up, metres (glTF). Matrices are column-major
 * float[16] (glTF and GLSL order). Quaternions are (x, y, z, w). */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "core/camera.h"
#include "core/status.h"

#define SCENE_NAME_MAX 64
/* Base-colour textures a scene may use (one descriptor array on the GPU). */
#define SCENE_MAX_TEXTURES 16

typedef enum scene_interp {
    SCENE_INTERP_DEFAULT = 0, /* = linear */
    SCENE_INTERP_LINEAR,
    SCENE_INTERP_STEP,
    SCENE_INTERP_CUBIC,
} scene_interp;

typedef enum scene_path {
    SCENE_PATH_DEFAULT = 0,
    SCENE_PATH_TRANSLATION,
    SCENE_PATH_ROTATION,
    SCENE_PATH_SCALE,
    SCENE_PATH_WEIGHTS,
} scene_path;

typedef struct scene_texture {
    char name[SCENE_NAME_MAX];
    int width, height;
    uint8_t *rgba;         /* width * height * 4, top row first */
    bool wrap_repeat_s, wrap_repeat_t; /* false: clamp to edge */
    bool mirror_s, mirror_t; /* MIRRORED_REPEAT (wrap_repeat_* is also true then) */
    bool nearest;          /* magnification filter NEAREST */
} scene_texture;

typedef struct scene_material {
    char name[SCENE_NAME_MAX];
    float base_color[4];   /* linear RGBA factor */
    int base_color_texture; /* index into textures, -1 for none */
    int texcoord;           /* TEXCOORD_n set used by the texture (0 or 1; only 0 is kept) */
    bool double_sided;
} scene_material;

typedef struct scene_primitive {
    int mesh;
    uint32_t vertex_count, index_count;
    float *positions;       /* 3 * vertex_count */
    float *normals;         /* 3 * vertex_count (generated when absent) */
    float *texcoords;       /* 2 * vertex_count (zero when absent) */
    float *colors;          /* 4 * vertex_count (one when absent) */
    uint16_t *joints;       /* 4 * vertex_count, NULL when not skinned */
    float *weights;         /* 4 * vertex_count, NULL when not skinned */
    uint32_t *indices;      /* index_count triangle-list indices */
    int target_count;       /* morph targets */
    float *target_positions; /* target_count * 3 * vertex_count, or NULL */
    float *target_normals;   /* target_count * 3 * vertex_count, or NULL */
    int material;           /* -1: default white material */
    float bounds_min[3], bounds_max[3]; /* of positions, before deformation */
} scene_primitive;

typedef struct scene_mesh {
    char name[SCENE_NAME_MAX];
    int first_primitive, primitive_count;
    int weight_count;        /* morph targets of this mesh */
    float *weights;          /* default morph weights, weight_count */
} scene_mesh;

typedef struct scene_node {
    char name[SCENE_NAME_MAX];
    int parent;              /* -1 for roots */
    int mesh, camera, skin;  /* -1 when absent */
    float translation[3], rotation[4], scale[3];
    float matrix[16];        /* used instead of TRS when has_matrix */
    bool has_matrix;
    float saliency;          /* extras.saliency in [0, 1]; inherited from the parent when absent, 0 at roots */
    bool has_saliency;
    float *weights;          /* node morph weights override (mesh weight_count) or NULL */
} scene_node;

typedef struct scene_camera {
    char name[SCENE_NAME_MAX];
    bool orthographic;
    float yfov;              /* radians (perspective) */
    float aspect;            /* 0: use the viewport's */
    float znear, zfar;       /* zfar 0: infinite */
    float xmag, ymag;        /* orthographic half extents */
} scene_camera;

typedef struct scene_skin {
    char name[SCENE_NAME_MAX];
    int joint_count;
    int *joints;             /* node indices */
    float *inverse_bind;     /* joint_count * 16 (identity when absent) */
    int skeleton;            /* -1 when absent */
} scene_skin;

typedef struct scene_sampler {
    scene_interp interp;
    int key_count;
    float *times;            /* key_count, finite, non-decreasing (equal neighbours tolerated) */
    int components;          /* 3 (T, S), 4 (R) or the morph weight count */
    float *values;           /* key_count * components, x3 for cubic (in-tangent, value, out-tangent) */
} scene_sampler;

typedef struct scene_channel {
    int node;
    scene_path path;
    int sampler;             /* index into the scene's samplers */
} scene_channel;

typedef struct scene_animation {
    char name[SCENE_NAME_MAX];
    int first_channel, channel_count;
    float start, end;        /* time range of its keys, seconds */
} scene_animation;

/* One draw: a node that references a mesh, times one primitive of it. */
typedef struct scene_instance {
    int node, primitive;
    uint32_t id;             /* 1-based instance id written by the G-buffer (0 = background) */
    float saliency;          /* the node's effective saliency */
    uint32_t first_vertex;   /* into scene_state positions/normals */
    uint32_t first_index;    /* into scene.indices (global index buffer) */
} scene_instance;

/* A pose hook (scene_set_pose_hook): moves nodes at run time. */
struct scene;
typedef void (*scene_pose_fn)(void *user, const struct scene *s, float t, float *local);

typedef struct scene {
    char path[512];
    char (*files)[512];      /* every file the scene was read from: path, then its buffers and images */
    int file_count;
    int node_count, mesh_count, primitive_count, material_count, texture_count;
    int camera_count, skin_count, animation_count, channel_count, sampler_count;
    int root_count;
    scene_node *nodes;
    scene_mesh *meshes;
    scene_primitive *primitives;
    scene_material *materials;
    scene_texture *textures;
    scene_camera *cameras;
    scene_skin *skins;
    scene_animation *animations;
    scene_channel *channels;
    scene_sampler *samplers;
    int *roots;              /* root nodes of the default scene */
    int *node_order;         /* node_count: every node after its parent (evaluation order);
                              * added by the scene module */

    int instance_count;
    scene_instance *instances;
    uint32_t vertex_count;   /* sum of instance vertex counts */
    uint32_t index_count;    /* sum of instance index counts */
    uint32_t *indices;       /* all instances' indices, each relative to its own first_vertex */

    float bounds_min[3], bounds_max[3]; /* world-space bounds of all vertices at t = 0 */
    float duration;          /* end of the longest animation, 0 when static */
    bool animated;           /* has animation channels, skinned instances or non-zero morph weights */
    scene_pose_fn pose_hook; /* added for run-time motion: see scene_set_pose_hook (NULL = none) */
    void *pose_user;
} scene;

/* Evaluated scene at one time. Arrays are owned by the state. */
typedef struct scene_state {
    float t;
    float *world;            /* node_count * 16: world matrix of each node */
    float *positions;        /* 3 * scene.vertex_count, world space */
    float *normals;          /* 3 * scene.vertex_count, world space, unit length */
    float bounds_min[3], bounds_max[3]; /* of all positions */

    /* Added by the scene module: what scene_evaluate computes on the way,
     * kept so it never allocates. Read-only for callers. */
    float *local;            /* node_count * 10: local T (3), R (4, x y z w), S (3) at t */
    float *morph_weights;    /* morph weights of node n at morph_weights + morph_offset[n] */
    int *morph_offset;       /* node_count + 1 offsets; node n has morph_offset[n+1] - morph_offset[n] weights */
    float *joint_matrices;   /* per skin, in skin order: joint_count * 16, world(joint) * inverseBind */
    float *placed;           /* instance_count * 16: the world matrix an instance's vertices were last placed
                              * with (NaN: not placed), so a rigid instance that did not move is not placed again
                              * (morphed and skinned ones are placed every time) */
    float *instance_bounds;  /* instance_count * 6: min xyz, max xyz of each instance's placed vertices */
} scene_state;

/* Loads a .gltf or .glb. On failure logs one line naming the file and the
 * problem, returns VG_ERR_IO / VG_ERR_FORMAT / VG_ERR_UNSUPPORTED, *out NULL. */
vg_status scene_load(const char *path, scene **out);
void scene_destroy(scene *s);

vg_status scene_state_init(const scene *s, scene_state *st);
void scene_state_free(scene_state *st);
/* Never allocates; t outside [0, duration] holds the first/last keys; a
 * non-finite t is treated as 0. */
void scene_evaluate(const scene *s, float t, scene_state *st);

/* The scene as a host that cannot see ahead knows it (`--look-ahead
 * causal`, docs/method.md "Look-ahead"): evaluated up to now->t, predicted
 * after it. A prediction moves every vertex and every node's origin on at
 * the velocity it had from before->t to now->t (constant velocity, from the
 * last two evaluations only); node rotations, scales and normals are held. */
typedef struct scene_past {
    const scene_state *now, *before; /* evaluated at now->t > before->t (the last frame and one step before) */
} scene_past;
/* scene_evaluate for t <= past->now->t (or past NULL: the scene's own
 * future, perfect foresight), else the prediction at t. */
void scene_evaluate_known(const scene *s, const scene_past *past, float t, scene_state *st);

/* Run-time motion (the game's ball): scene_evaluate calls fn after the
 * animation channels and before the hierarchy is composed, with every node's
 * local T (3), R (4, x y z w), S (3) at t (node i at local + 10 i), and fn
 * may rewrite them. Motion set this way is a function of t like any
 * animation, so evaluations at other times (motion vectors, look-ahead
 * keyframes) see it too; fn must therefore depend on t only. NULL removes
 * the hook. Bounds in the scene (at t = 0, from loading) do not change. */
void scene_set_pose_hook(scene *s, scene_pose_fn fn, void *user);
/* Whether any node authors extras.saliency (else every instance has 0 and
 * the frame may compute saliency: docs/method.md section 3). */
bool scene_has_saliency(const scene *s);
/* Instance i's vertices are its rest positions under its world matrix alone
 * (no morph weights, no skin): where st->placed is unchanged, so are they. */
bool scene_instance_rigid(const scene *s, const scene_state *st, int i);
/* The scene's mean base colour (linear RGB): each instance's material
 * factor x its texture's mean x its vertex colours' mean, weighted by its
 * triangles (the reference of computed saliency's colour contrast). */
void scene_mean_base_color(const scene *s, float rgb[3]);
/* Index of the first node named `name`, or -1. */
int scene_find_node(const scene *s, const char *name);
/* The instance ids (the G-buffer's) of node's own instances, up to cap of
 * them into ids; returns how many it has. */
int scene_node_instance_ids(const scene *s, int node, uint32_t *ids, int cap);

/* ------------------------------------------------------------------------- */
/* Cameras                                                                   */
/* ------------------------------------------------------------------------- */


/* The view for an evaluated state: the scene's camera node number `index`
 * (in node order, clamped to the cameras there are) when it has cameras,
 * else an automatic camera that frames the scene's bounds at t = 0 from the
 * front (+Z) slightly above. aspect is the viewport's width / height and is
 * used even when the glTF camera has its own (no stretching); aspect <= 0
 * takes the camera's aspectRatio (or 1). An infinite glTF zfar becomes a
 * far plane just beyond the scene bounds. See docs/scene.md. */
void scene_camera_resolve(const scene *s, const scene_state *st, int index, float aspect, vg_camera *cam);
/* Camera nodes of the scene (0: the automatic camera only). */
int scene_camera_count(const scene *s);
/* The node of camera `index` (clamped as scene_camera_resolve does), -1 without cameras. */
int scene_camera_node(const scene *s, int index);
/* Camera `index` is a glTF orthographic camera: it has no stereo rig (a
 * parallel view has no field of view for the eyes to converge within), so
 * the commands that render stereo refuse it (docs/scene.md). */
bool scene_camera_orthographic(const scene *s, int index);
