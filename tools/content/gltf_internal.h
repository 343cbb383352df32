/* vergence content — the glTF writer's tables, shared by gltf.c (the
 * document, rigid scenes) and gltf_deform.c (skins, morph targets). Not for
 * the scenes: they use gltf.h. */
#pragma once
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/json.h"
#include "gltf.h"

/* Table sizes: generous for the handful of objects a sample scene has. */
#define MAX_VIEWS 512
#define MAX_ACCESSORS 512
#define MAX_MESHES 64
#define MAX_PRIMS 8
#define MAX_MATERIALS 64
#define MAX_TEXTURES 8
#define MAX_NODES 128
#define MAX_CAMERAS 4
#define MAX_ANIMATIONS 8
#define MAX_CHANNELS 8
#define MAX_SKINS 4
#define MAX_JOINTS 16
#define MAX_TARGETS 4
#define NAME_MAX_LEN 64

/* glTF enumerations. */
enum {
    GL_UNSIGNED_BYTE = 5121,
    GL_FLOAT = 5126,
    GL_UNSIGNED_SHORT = 5123,
    GL_UNSIGNED_INT = 5125,
    GL_ARRAY_BUFFER = 34962,
    GL_ELEMENT_ARRAY_BUFFER = 34963,
    GL_LINEAR = 9729,
    GL_LINEAR_MIPMAP_LINEAR = 9987,
    GL_REPEAT = 10497,
};

typedef struct view {
    size_t offset, length;
    int target; /* 0: none */
} view;

typedef struct accessor {
    int view, component, count, comps;
    bool minmax;
    float min[4], max[4];
} accessor;

typedef struct prim {
    int position, normal, texcoord, indices; /* accessor indices, texcoord -1 when absent */
    int material;                            /* material index */
    int joints, weights;                     /* JOINTS_0 / WEIGHTS_0 accessors, 0 when not skinned */
    int target_count;                        /* morph targets: POSITION and NORMAL accessors */
    int targets[MAX_TARGETS][2];
} prim;

typedef struct gmesh {
    char name[NAME_MAX_LEN];
    prim prims[MAX_PRIMS];
    int prim_count;
    float weights[MAX_TARGETS]; /* default morph weights */
    int weight_count;
} gmesh;

typedef struct material {
    char name[NAME_MAX_LEN];
    float color[4];
    int texture; /* index, -1 none */
    double roughness;
} material;

typedef struct image {
    char name[NAME_MAX_LEN];
    int view;
} image;

typedef struct node {
    char name[NAME_MAX_LEN];
    int mesh, camera; /* indices, -1 none */
    int parent, skin; /* indices, -1 none */
    float t[3], r[4];
    float saliency;
} node;

typedef struct camera {
    char name[NAME_MAX_LEN];
    double yfov, znear, zfar;
} camera;

typedef struct skin {
    char name[NAME_MAX_LEN];
    int joints[MAX_JOINTS]; /* node indices */
    int joint_count;
    int inverse_bind;       /* accessor (MAT4) */
} skin;

typedef struct channel {
    int node, input, output;
    gltf_path path;
    gltf_interp interp;
} channel;

typedef struct animation {
    char name[NAME_MAX_LEN];
    channel channels[MAX_CHANNELS];
    int channel_count;
} animation;

struct gltf {
    char scene_name[NAME_MAX_LEN];
    char description[512];
    uint8_t *bin;
    size_t bin_len, bin_cap;
    view views[MAX_VIEWS];
    accessor accessors[MAX_ACCESSORS];
    gmesh meshes[MAX_MESHES];
    material materials[MAX_MATERIALS];
    image images[MAX_TEXTURES];
    node nodes[MAX_NODES];
    camera cameras[MAX_CAMERAS];
    animation animations[MAX_ANIMATIONS];
    skin skins[MAX_SKINS];
    int skin_count;
    int view_count, accessor_count, mesh_count, material_count, image_count;
    int node_count, camera_count, animation_count;
    uint32_t triangles;
    bool failed;
};

/* A buffer view over a copy of data (4-byte aligned); its index, -1 on failure. */
int gltf_view_add(gltf *g, const void *data, size_t size, int target);
/* A float accessor of count elements of comps components (min/max on request). */
int gltf_accessor_add_float(gltf *g, const float *data, int count, int comps, int target, bool minmax);
/* The skins array (gltf_deform.c); nothing when the document has none. */
void gltf_write_skins(const gltf *g, vg_json *j);
