/* vergence-content — a glTF document written to DIR/NAME.gltf + .bin: the
 * builder's arrays (gltf.c) and the skins (gltf_deform.c) as glTF 2.0 JSON. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/io.h"
#include "core/json.h"
#include "core/log.h"
#include "gltf_internal.h"

static const char *type_name(int comps)
{
    static const char *const names[] = {"", "SCALAR", "VEC2", "VEC3", "VEC4"};
    return comps == 16 ? "MAT4" : names[comps];
}

static void write_nodes(const gltf *g, vg_json *j)
{
    vg_json_array_begin(j, "nodes");
    for (int i = 0; i < g->node_count; i++) {
        const node *n = &g->nodes[i];
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", n->name);
        if (n->mesh >= 0)
            vg_json_int(j, "mesh", n->mesh);
        if (n->camera >= 0)
            vg_json_int(j, "camera", n->camera);
        if (n->skin >= 0)
            vg_json_int(j, "skin", n->skin);
        bool parent = false;
        for (int c = i + 1; c < g->node_count && !parent; c++)
            parent = g->nodes[c].parent == i;
        if (parent) {
            vg_json_array_begin(j, "children");
            for (int c = i + 1; c < g->node_count; c++)
                if (g->nodes[c].parent == i)
                    vg_json_int(j, NULL, c);
            vg_json_array_end(j);
        }
        if (n->t[0] || n->t[1] || n->t[2])
            vg_json_nums(j, "translation", n->t, 3);
        if (n->r[0] || n->r[1] || n->r[2] || n->r[3] != 1)
            vg_json_nums(j, "rotation", n->r, 4);
        if (n->mesh >= 0) {
            vg_json_object_begin(j, "extras");
            vg_json_num(j, "saliency", n->saliency);
            vg_json_object_end(j);
        }
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
}

static void write_meshes(const gltf *g, vg_json *j)
{
    vg_json_array_begin(j, "meshes");
    for (int i = 0; i < g->mesh_count; i++) {
        const gmesh *m = &g->meshes[i];
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", m->name);
        vg_json_array_begin(j, "primitives");
        for (int k = 0; k < m->prim_count; k++) {
            const prim *p = &m->prims[k];
            vg_json_object_begin(j, NULL);
            vg_json_object_begin(j, "attributes");
            vg_json_int(j, "POSITION", p->position);
            vg_json_int(j, "NORMAL", p->normal);
            if (p->texcoord >= 0)
                vg_json_int(j, "TEXCOORD_0", p->texcoord);
            if (p->joints) {
                vg_json_int(j, "JOINTS_0", p->joints);
                vg_json_int(j, "WEIGHTS_0", p->weights);
            }
            vg_json_object_end(j);
            vg_json_int(j, "indices", p->indices);
            vg_json_int(j, "material", p->material);
            if (p->target_count) {
                vg_json_array_begin(j, "targets");
                for (int t = 0; t < p->target_count; t++) {
                    vg_json_object_begin(j, NULL);
                    vg_json_int(j, "POSITION", p->targets[t][0]);
                    vg_json_int(j, "NORMAL", p->targets[t][1]);
                    vg_json_object_end(j);
                }
                vg_json_array_end(j);
            }
            vg_json_object_end(j);
        }
        vg_json_array_end(j);
        if (m->weight_count)
            vg_json_nums(j, "weights", m->weights, m->weight_count);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
}

static void write_materials(const gltf *g, vg_json *j)
{
    vg_json_array_begin(j, "materials");
    for (int i = 0; i < g->material_count; i++) {
        const material *m = &g->materials[i];
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", m->name);
        vg_json_object_begin(j, "pbrMetallicRoughness");
        vg_json_nums(j, "baseColorFactor", m->color, 4);
        if (m->texture >= 0) {
            vg_json_object_begin(j, "baseColorTexture");
            vg_json_int(j, "index", m->texture);
            vg_json_object_end(j);
        }
        vg_json_num(j, "metallicFactor", 0);
        vg_json_num(j, "roughnessFactor", m->roughness);
        vg_json_object_end(j);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
}

/* One texture per image, all sharing one trilinear repeating sampler. */
static void write_textures(const gltf *g, vg_json *j)
{
    if (!g->image_count)
        return;
    vg_json_array_begin(j, "textures");
    for (int i = 0; i < g->image_count; i++) {
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", g->images[i].name);
        vg_json_int(j, "sampler", 0);
        vg_json_int(j, "source", i);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
    vg_json_array_begin(j, "images");
    for (int i = 0; i < g->image_count; i++) {
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", g->images[i].name);
        vg_json_int(j, "bufferView", g->images[i].view);
        vg_json_str(j, "mimeType", "image/png");
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
    vg_json_array_begin(j, "samplers");
    vg_json_object_begin(j, NULL);
    vg_json_int(j, "magFilter", GL_LINEAR);
    vg_json_int(j, "minFilter", GL_LINEAR_MIPMAP_LINEAR);
    vg_json_int(j, "wrapS", GL_REPEAT);
    vg_json_int(j, "wrapT", GL_REPEAT);
    vg_json_object_end(j);
    vg_json_array_end(j);
}

static void write_cameras(const gltf *g, vg_json *j)
{
    vg_json_array_begin(j, "cameras");
    for (int i = 0; i < g->camera_count; i++) {
        const camera *c = &g->cameras[i];
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", c->name);
        vg_json_str(j, "type", "perspective");
        vg_json_object_begin(j, "perspective");
        vg_json_num(j, "yfov", c->yfov);
        vg_json_num(j, "znear", c->znear);
        vg_json_num(j, "zfar", c->zfar);
        vg_json_object_end(j);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
}

static void write_animations(const gltf *g, vg_json *j)
{
    if (!g->animation_count)
        return;
    static const char *const paths[] = {"translation", "translation", "rotation", "scale", "weights"};
    vg_json_array_begin(j, "animations");
    for (int i = 0; i < g->animation_count; i++) {
        const animation *a = &g->animations[i];
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", a->name);
        vg_json_array_begin(j, "channels");
        for (int k = 0; k < a->channel_count; k++) {
            vg_json_object_begin(j, NULL);
            vg_json_int(j, "sampler", k);
            vg_json_object_begin(j, "target");
            vg_json_int(j, "node", a->channels[k].node);
            vg_json_str(j, "path", paths[a->channels[k].path]);
            vg_json_object_end(j);
            vg_json_object_end(j);
        }
        vg_json_array_end(j);
        vg_json_array_begin(j, "samplers");
        for (int k = 0; k < a->channel_count; k++) {
            vg_json_object_begin(j, NULL);
            vg_json_int(j, "input", a->channels[k].input);
            vg_json_str(j, "interpolation", a->channels[k].interp == GLTF_INTERP_CUBIC ? "CUBICSPLINE" : "LINEAR");
            vg_json_int(j, "output", a->channels[k].output);
            vg_json_object_end(j);
        }
        vg_json_array_end(j);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
}

static void write_buffers(const gltf *g, vg_json *j, const char *bin_name)
{
    vg_json_array_begin(j, "accessors");
    for (int i = 0; i < g->accessor_count; i++) {
        const accessor *a = &g->accessors[i];
        vg_json_object_begin(j, NULL);
        vg_json_int(j, "bufferView", a->view);
        vg_json_int(j, "componentType", a->component);
        vg_json_int(j, "count", a->count);
        vg_json_str(j, "type", type_name(a->comps));
        if (a->minmax) {
            vg_json_nums(j, "min", a->min, a->comps);
            vg_json_nums(j, "max", a->max, a->comps);
        }
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
    vg_json_array_begin(j, "bufferViews");
    for (int i = 0; i < g->view_count; i++) {
        const view *v = &g->views[i];
        vg_json_object_begin(j, NULL);
        vg_json_int(j, "buffer", 0);
        vg_json_int(j, "byteOffset", (long long)v->offset);
        vg_json_int(j, "byteLength", (long long)v->length);
        if (v->target)
            vg_json_int(j, "target", v->target);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
    vg_json_array_begin(j, "buffers");
    vg_json_object_begin(j, NULL);
    vg_json_str(j, "uri", bin_name);
    vg_json_int(j, "byteLength", (long long)g->bin_len);
    vg_json_object_end(j);
    vg_json_array_end(j);
}

vg_status gltf_write(gltf *g, const char *dir, size_t *gltf_bytes, size_t *bin_bytes)
{
    if (g->failed)
        return VG_ERR_NOMEM;
    if (g->camera_count == 0 || g->node_count == 0) {
        gltf_fail(g, "a scene needs a camera and at least one node");
        return VG_ERR_ARG;
    }
    char bin_name[NAME_MAX_LEN + 8], gltf_name[NAME_MAX_LEN + 8], path[4096];
    snprintf(bin_name, sizeof bin_name, "%s.bin", g->scene_name);
    snprintf(gltf_name, sizeof gltf_name, "%s.gltf", g->scene_name);

    vg_json j = {0};
    vg_json_object_begin(&j, NULL);
    vg_json_object_begin(&j, "asset");
    vg_json_str(&j, "version", "2.0");
    vg_json_str(&j, "generator", "vergence-content");
    vg_json_object_end(&j);
    vg_json_int(&j, "scene", 0);
    vg_json_array_begin(&j, "scenes");
    vg_json_object_begin(&j, NULL);
    vg_json_str(&j, "name", g->scene_name);
    vg_json_array_begin(&j, "nodes");
    for (int i = 0; i < g->node_count; i++)
        if (g->nodes[i].parent < 0)
            vg_json_int(&j, NULL, i);
    vg_json_array_end(&j);
    vg_json_object_begin(&j, "extras");
    vg_json_str(&j, "description", g->description);
    vg_json_object_end(&j);
    vg_json_object_end(&j);
    vg_json_array_end(&j);
    write_nodes(g, &j);
    write_cameras(g, &j);
    write_meshes(g, &j);
    gltf_write_skins(g, &j);
    write_materials(g, &j);
    write_textures(g, &j);
    write_animations(g, &j);
    write_buffers(g, &j, bin_name);
    vg_json_object_end(&j);

    vg_status st = vg_path_join(path, sizeof path, dir, bin_name);
    if (st == VG_OK)
        st = vg_file_write_atomic(path, g->bin, g->bin_len);
    if (st == VG_OK)
        st = vg_path_join(path, sizeof path, dir, gltf_name);
    if (st == VG_OK)
        st = vg_json_write_file(&j, path);
    *gltf_bytes = j.len;
    *bin_bytes = g->bin_len;
    vg_json_free(&j);
    return st;
}
