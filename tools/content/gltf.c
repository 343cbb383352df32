#include "gltf.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/io.h"
#include "core/json.h"
#include "core/log.h"
#include "gltf_internal.h"

/* ------------------------------------------------------------------------- */
/* Building                                                                  */
/* ------------------------------------------------------------------------- */

void gltf_fail(gltf *g, const char *what)
{
    if (!g->failed)
        vg_error("%s: %s", g->scene_name, what);
    g->failed = true;
}

static void copy_name(char *dst, const char *src)
{
    snprintf(dst, NAME_MAX_LEN, "%s", src ? src : "");
}

gltf *gltf_create(const char *scene_name, const char *description)
{
    gltf *g = calloc(1, sizeof *g);
    if (!g)
        return NULL;
    copy_name(g->scene_name, scene_name);
    snprintf(g->description, sizeof g->description, "%s", description ? description : "");
    return g;
}

void gltf_destroy(gltf *g)
{
    if (!g)
        return;
    free(g->bin);
    free(g);
}

/* Appends bytes to the binary buffer at a 4-byte boundary; returns a view index. */
int gltf_view_add(gltf *g, const void *data, size_t size, int target)
{
    if (g->failed)
        return -1;
    if (g->view_count >= MAX_VIEWS) {
        gltf_fail(g, "too many buffer views");
        return -1;
    }
    size_t offset = (g->bin_len + 3) & ~(size_t)3, end = offset + size;
    if (end > g->bin_cap) {
        size_t cap = g->bin_cap ? g->bin_cap : 65536;
        while (cap < end)
            cap *= 2;
        uint8_t *p = realloc(g->bin, cap);
        if (!p) {
            gltf_fail(g, "out of memory for the binary buffer");
            return -1;
        }
        g->bin = p;
        g->bin_cap = cap;
    }
    memset(g->bin + g->bin_len, 0, offset - g->bin_len); /* padding is zero, not garbage */
    memcpy(g->bin + offset, data, size);
    g->bin_len = end;
    g->views[g->view_count] = (view){.offset = offset, .length = size, .target = target};
    return g->view_count++;
}

/* A float accessor of count elements of comps components, with min/max
 * (glTF requires them for POSITION and animation inputs). */
int gltf_accessor_add_float(gltf *g, const float *data, int count, int comps, int target, bool minmax)
{
    int v = gltf_view_add(g, data, sizeof(float) * (size_t)count * (size_t)comps, target);
    if (v < 0)
        return -1;
    if (g->accessor_count >= MAX_ACCESSORS) {
        gltf_fail(g, "too many accessors");
        return -1;
    }
    accessor *a = &g->accessors[g->accessor_count];
    *a = (accessor){.view = v, .component = GL_FLOAT, .count = count, .comps = comps, .minmax = minmax};
    for (int c = 0; c < comps && minmax; c++) {
        a->min[c] = a->max[c] = data[c];
        for (int i = 1; i < count; i++) {
            float x = data[(size_t)i * (size_t)comps + (size_t)c];
            a->min[c] = fminf(a->min[c], x);
            a->max[c] = fmaxf(a->max[c], x);
        }
    }
    return g->accessor_count++;
}

/* Indices as unsigned short when they fit (65535 is the restart value, so
 * it must stay unused), else unsigned int. */
static int add_index_accessor(gltf *g, const uint32_t *idx, uint32_t count, uint32_t vertex_count)
{
    int v;
    bool shorts = vertex_count < 65535;
    if (shorts) {
        uint16_t *s = malloc(sizeof(uint16_t) * count);
        if (!s) {
            gltf_fail(g, "out of memory for indices");
            return -1;
        }
        for (uint32_t i = 0; i < count; i++)
            s[i] = (uint16_t)idx[i];
        v = gltf_view_add(g, s, sizeof(uint16_t) * count, GL_ELEMENT_ARRAY_BUFFER);
        free(s);
    } else {
        v = gltf_view_add(g, idx, sizeof(uint32_t) * count, GL_ELEMENT_ARRAY_BUFFER);
    }
    if (v < 0)
        return -1;
    if (g->accessor_count >= MAX_ACCESSORS) {
        gltf_fail(g, "too many accessors");
        return -1;
    }
    g->accessors[g->accessor_count] = (accessor){
        .view = v, .component = shorts ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT, .count = (int)count, .comps = 1};
    return g->accessor_count++;
}

int gltf_texture_add_png(gltf *g, const char *name, const uint8_t *png, size_t size)
{
    if (g->image_count >= MAX_TEXTURES) {
        gltf_fail(g, "too many textures");
        return 0;
    }
    int v = gltf_view_add(g, png, size, 0);
    if (v < 0)
        return 0;
    image *im = &g->images[g->image_count];
    copy_name(im->name, name);
    im->view = v;
    return ++g->image_count;
}

static float srgb_to_linear(uint8_t c)
{
    double x = c / 255.0;
    return (float)(x <= 0.04045 ? x / 12.92 : pow((x + 0.055) / 1.055, 2.4));
}

int gltf_material_add(gltf *g, const gltf_material_desc *d)
{
    if (g->material_count >= MAX_MATERIALS) {
        gltf_fail(g, "too many materials");
        return 0;
    }
    if (d->texture < 0 || d->texture > g->image_count) {
        gltf_fail(g, "material refers to an unknown texture");
        return 0;
    }
    material *m = &g->materials[g->material_count];
    copy_name(m->name, d->name);
    m->texture = d->texture - 1;
    for (int c = 0; c < 3; c++)
        m->color[c] = d->texture ? 1.0f : srgb_to_linear(d->srgb[c]);
    m->color[3] = 1.0f;
    m->roughness = d->roughness > 0 ? d->roughness : 0.9;
    return ++g->material_count;
}

int gltf_mesh_add(gltf *g, const char *name)
{
    if (g->mesh_count >= MAX_MESHES) {
        gltf_fail(g, "too many meshes");
        return 0;
    }
    copy_name(g->meshes[g->mesh_count].name, name);
    return ++g->mesh_count;
}

void gltf_mesh_primitive(gltf *g, int mesh_h, const mesh *geo, int material_h)
{
    if (mesh_h < 1 || mesh_h > g->mesh_count || material_h < 1 || material_h > g->material_count) {
        gltf_fail(g, "primitive refers to an unknown mesh or material");
        return;
    }
    if (geo->failed || geo->icount == 0) {
        gltf_fail(g, geo->failed ? "out of memory building a mesh" : "empty mesh primitive");
        return;
    }
    gmesh *m = &g->meshes[mesh_h - 1];
    if (m->prim_count >= MAX_PRIMS) {
        gltf_fail(g, "too many primitives in one mesh");
        return;
    }
    const material *mat = &g->materials[material_h - 1];
    int n = (int)geo->vcount;
    prim p = {
        .position = gltf_accessor_add_float(g, geo->pos, n, 3, GL_ARRAY_BUFFER, true),
        .normal = gltf_accessor_add_float(g, geo->nrm, n, 3, GL_ARRAY_BUFFER, false),
        .texcoord = mat->texture >= 0 ? gltf_accessor_add_float(g, geo->uv, n, 2, GL_ARRAY_BUFFER, false) : -1,
        .indices = add_index_accessor(g, geo->idx, geo->icount, geo->vcount),
        .material = material_h - 1,
    };
    m->prims[m->prim_count++] = p;
    g->triangles += geo->icount / 3;
}

int gltf_camera_add(gltf *g, const char *name, double yfov, double znear, double zfar)
{
    if (g->camera_count >= MAX_CAMERAS) {
        gltf_fail(g, "too many cameras");
        return 0;
    }
    camera *c = &g->cameras[g->camera_count];
    copy_name(c->name, name);
    c->yfov = yfov;
    c->znear = znear;
    c->zfar = zfar;
    return ++g->camera_count;
}

int gltf_node_add(gltf *g, const gltf_node_desc *d)
{
    if (g->node_count >= MAX_NODES) {
        gltf_fail(g, "too many nodes");
        return 0;
    }
    if (d->mesh < 0 || d->mesh > g->mesh_count || d->camera < 0 || d->camera > g->camera_count ||
        d->parent < 0 || d->parent > g->node_count || d->skin < 0 || d->skin > g->skin_count) {
        gltf_fail(g, "node refers to an unknown mesh or camera");
        return 0;
    }
    node *n = &g->nodes[g->node_count];
    copy_name(n->name, d->name);
    n->mesh = d->mesh - 1;
    n->camera = d->camera - 1;
    n->parent = d->parent - 1;
    n->skin = d->skin - 1;
    memcpy(n->t, d->translation, sizeof n->t);
    memcpy(n->r, d->rotation, sizeof n->r);
    if (!n->r[0] && !n->r[1] && !n->r[2] && !n->r[3])
        n->r[3] = 1;
    n->saliency = d->saliency;
    return ++g->node_count;
}

int gltf_animation_add(gltf *g, const char *name)
{
    if (g->animation_count >= MAX_ANIMATIONS) {
        gltf_fail(g, "too many animations");
        return 0;
    }
    copy_name(g->animations[g->animation_count].name, name);
    return ++g->animation_count;
}

void gltf_animation_channel(gltf *g, int anim_h, int node_h, gltf_path path, gltf_interp interp,
                            const float *times, int n, const float *values)
{
    if (anim_h < 1 || anim_h > g->animation_count || node_h < 1 || node_h > g->node_count || n < 2) {
        gltf_fail(g, "animation channel refers to an unknown animation or node, or has < 2 keys");
        return;
    }
    animation *a = &g->animations[anim_h - 1];
    if (a->channel_count >= MAX_CHANNELS) {
        gltf_fail(g, "too many channels in one animation");
        return;
    }
    for (int i = 1; i < n; i++)
        if (!(times[i] > times[i - 1])) {
            gltf_fail(g, "animation key times are not strictly increasing");
            return;
        }
    int comps = path == GLTF_PATH_ROTATION ? 4 : 3, per_key = interp == GLTF_INTERP_CUBIC ? 3 : 1;
    channel c = {
        .node = node_h - 1,
        .input = gltf_accessor_add_float(g, times, n, 1, 0, true),
        .output = gltf_accessor_add_float(g, values, n * per_key, comps, 0, false),
        .path = path,
        .interp = interp,
    };
    a->channels[a->channel_count++] = c;
}

uint32_t gltf_triangles(const gltf *g)
{
    return g->triangles;
}
