/* vergence content — deforming meshes in the glTF writer: skins (joints,
 * inverse bind matrices, JOINTS_0/WEIGHTS_0) and morph targets (offsets and
 * their weights, animated). The document tables are in gltf_internal.h. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gltf_internal.h"

/* The primitive just added to a mesh by gltf_mesh_primitive, or NULL. */
static prim *last_prim(gltf *g, int mesh_h)
{
    if (g->failed || mesh_h < 1 || mesh_h > g->mesh_count || g->meshes[mesh_h - 1].prim_count == 0)
        return NULL;
    gmesh *m = &g->meshes[mesh_h - 1];
    return &m->prims[m->prim_count - 1];
}

int gltf_skin_add(gltf *g, const char *name, const int *joints, int joint_count, const float *inverse_bind)
{
    if (g->skin_count >= MAX_SKINS || joint_count < 1 || joint_count > MAX_JOINTS) {
        gltf_fail(g, "too many skins, or a skin with no or too many joints");
        return 0;
    }
    skin *s = &g->skins[g->skin_count];
    snprintf(s->name, NAME_MAX_LEN, "%s", name ? name : "");
    for (int i = 0; i < joint_count; i++) {
        if (joints[i] < 1 || joints[i] > g->node_count) {
            gltf_fail(g, "a skin joint refers to an unknown node");
            return 0;
        }
        s->joints[i] = joints[i] - 1;
    }
    s->joint_count = joint_count;
    s->inverse_bind = gltf_accessor_add_float(g, inverse_bind, joint_count, 16, 0, false);
    return s->inverse_bind < 0 ? 0 : ++g->skin_count;
}

void gltf_mesh_primitive_skinned(gltf *g, int mesh_h, const mesh *geo, int material, const uint8_t *joints,
                                 const float *weights)
{
    gltf_mesh_primitive(g, mesh_h, geo, material);
    prim *p = last_prim(g, mesh_h);
    if (!p)
        return;
    int n = (int)geo->vcount;
    int v = gltf_view_add(g, joints, (size_t)n * 4, GL_ARRAY_BUFFER);
    if (v < 0 || g->accessor_count >= MAX_ACCESSORS) {
        gltf_fail(g, "too many accessors");
        return;
    }
    g->accessors[g->accessor_count] = (accessor){.view = v, .component = GL_UNSIGNED_BYTE, .count = n, .comps = 4};
    p->joints = g->accessor_count++;
    p->weights = gltf_accessor_add_float(g, weights, n, 4, GL_ARRAY_BUFFER, false);
}

void gltf_mesh_primitive_morph(gltf *g, int mesh_h, const mesh *geo, int material,
                               const float *const *position_offsets, const float *const *normal_offsets,
                               int targets)
{
    gltf_mesh_primitive(g, mesh_h, geo, material);
    prim *p = last_prim(g, mesh_h);
    if (!p)
        return;
    if (targets < 1 || targets > MAX_TARGETS) {
        gltf_fail(g, "a primitive needs 1 to MAX_TARGETS morph targets");
        return;
    }
    int n = (int)geo->vcount;
    for (int t = 0; t < targets; t++) {
        /* POSITION targets need bounds (glTF 2.0, 3.7.2.2). */
        p->targets[t][0] = gltf_accessor_add_float(g, position_offsets[t], n, 3, GL_ARRAY_BUFFER, true);
        p->targets[t][1] = gltf_accessor_add_float(g, normal_offsets[t], n, 3, GL_ARRAY_BUFFER, false);
    }
    p->target_count = targets;
}

void gltf_mesh_weights(gltf *g, int mesh_h, const float *weights, int count)
{
    if (mesh_h < 1 || mesh_h > g->mesh_count || count < 1 || count > MAX_TARGETS) {
        gltf_fail(g, "mesh weights refer to an unknown mesh or have a bad count");
        return;
    }
    gmesh *m = &g->meshes[mesh_h - 1];
    memcpy(m->weights, weights, sizeof(float) * (size_t)count);
    m->weight_count = count;
}

void gltf_animation_weights(gltf *g, int anim_h, int node_h, const float *times, int n, const float *values,
                            int targets)
{
    if (anim_h < 1 || anim_h > g->animation_count || node_h < 1 || node_h > g->node_count || n < 2 ||
        targets < 1) {
        gltf_fail(g, "weights channel refers to an unknown animation or node, or has < 2 keys");
        return;
    }
    animation *a = &g->animations[anim_h - 1];
    if (a->channel_count >= MAX_CHANNELS) {
        gltf_fail(g, "too many channels in one animation");
        return;
    }
    /* One scalar per target and key (glTF 2.0, 3.11: weights outputs). */
    channel c = {
        .node = node_h - 1,
        .input = gltf_accessor_add_float(g, times, n, 1, 0, true),
        .output = gltf_accessor_add_float(g, values, n * targets, 1, 0, false),
        .path = GLTF_PATH_WEIGHTS,
        .interp = GLTF_INTERP_LINEAR,
    };
    a->channels[a->channel_count++] = c;
}

void gltf_write_skins(const gltf *g, vg_json *j)
{
    if (!g->skin_count)
        return;
    vg_json_array_begin(j, "skins");
    for (int i = 0; i < g->skin_count; i++) {
        const skin *s = &g->skins[i];
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", s->name);
        vg_json_int(j, "inverseBindMatrices", s->inverse_bind);
        vg_json_array_begin(j, "joints");
        for (int k = 0; k < s->joint_count; k++)
            vg_json_int(j, NULL, s->joints[k]);
        vg_json_array_end(j);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
}
