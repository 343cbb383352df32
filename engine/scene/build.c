/* vergence — scene building: primitives into triangle lists, the node
 * hierarchy into an evaluation order, the default scene into instances.
 *
 * Everything here works on the plain structs of scene.h; gltf.cpp has
 * already checked every index it copied from the file. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "scene_internal.h"

/* ------------------------------------------------------------------------- */
/* Errors                                                                    */
/* ------------------------------------------------------------------------- */

bool scene_fail(scene_err *e, vg_status status, const char *fmt, ...)
{
    if (e->status != VG_OK)
        return false; /* one line per load: the first cause is the useful one */
    char msg[768];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    e->status = status;
    vg_error("%s: %s", e->path, msg);
    return false;
}

/* ------------------------------------------------------------------------- */
/* Primitives                                                                */
/* ------------------------------------------------------------------------- */

/* calloc that never returns NULL for a zero count (so NULL means failure). */
static void *zalloc(size_t count, size_t size)
{
    return calloc(count ? count : 1, size);
}

/* Replaces a per-vertex array (elements of `bytes` bytes; NULL: none) by
 * its elements gathered through idx. `field` is the address of the array's
 * pointer, of any element type: it is read and written through memcpy. */
static bool remap(void *field, size_t bytes, const uint32_t *idx, size_t n)
{
    const uint8_t *in;
    memcpy(&in, field, sizeof in);
    if (!in)
        return true;
    uint8_t *out = zalloc(n, bytes);
    if (!out)
        return false;
    for (size_t i = 0; i < n; i++)
        memcpy(out + i * bytes, in + (size_t)idx[i] * bytes, bytes);
    free((void *)in);
    memcpy(field, &out, sizeof out);
    return true;
}

/* Topology to a triangle list (glTF 2.0 spec 3.7.2.1, "Topology types"):
 * strip triangle i = {v_i, v_{i+(1+i%2)}, v_{i+(2-i%2)}} keeps the winding,
 * fan triangle i = {v_{i+1}, v_{i+2}, v_0}. */
static uint32_t *to_triangle_list(const uint32_t *in, uint32_t n, int mode, uint32_t *out_count)
{
    uint32_t tris = mode == 4 ? n / 3 : (n >= 3 ? n - 2 : 0);
    uint32_t *out = zalloc((size_t)tris * 3, sizeof *out);
    if (!out)
        return NULL;
    for (uint32_t i = 0; i < tris; i++) {
        uint32_t *t = out + (size_t)i * 3;
        if (mode == 4) {
            t[0] = in[3 * i], t[1] = in[3 * i + 1], t[2] = in[3 * i + 2];
        } else if (mode == 5) {
            t[0] = in[i], t[1] = in[i + 1 + i % 2], t[2] = in[i + 2 - i % 2];
        } else {
            t[0] = in[i + 1], t[1] = in[i + 2], t[2] = in[0];
        }
    }
    *out_count = tris * 3;
    return out;
}

/* Flat normals (the spec asks for flat normals when NORMAL is absent,
 * 3.7.2.1): each triangle gets its own three vertices. */
static bool unweld_flat(scene_primitive *p)
{
    uint32_t n = p->index_count;
    uint32_t *idx = p->indices;
    size_t vc = p->vertex_count;
    bool ok = remap(&p->positions, 3 * sizeof *p->positions, idx, n) &&
              remap(&p->texcoords, 2 * sizeof *p->texcoords, idx, n) &&
              remap(&p->colors, 4 * sizeof *p->colors, idx, n) && remap(&p->joints, 4 * sizeof *p->joints, idx, n) &&
              remap(&p->weights, 4 * sizeof *p->weights, idx, n);
    /* Targets are stored back to back, target_count slices of vc vertices. */
    if (ok && p->target_count > 0 && p->target_positions) {
        float *tp = zalloc((size_t)p->target_count * n * 3, sizeof *tp);
        ok = tp != NULL;
        for (int k = 0; ok && k < p->target_count; k++)
            for (uint32_t i = 0; i < n; i++)
                memcpy(tp + ((size_t)k * n + i) * 3, p->target_positions + ((size_t)k * vc + idx[i]) * 3,
                       3 * sizeof *tp);
        if (ok) {
            free(p->target_positions);
            p->target_positions = tp;
        }
    }
    /* Target normals without base normals have nothing to displace. */
    free(p->target_normals);
    p->target_normals = NULL;
    if (!ok)
        return false;
    p->normals = zalloc((size_t)n * 3, sizeof *p->normals);
    if (!p->normals)
        return false;
    for (uint32_t t = 0; t + 3 <= n; t += 3) {
        const float *a = p->positions + (size_t)t * 3, *b = a + 3, *c = a + 6;
        float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float nx = u[1] * v[2] - u[2] * v[1], ny = u[2] * v[0] - u[0] * v[2], nz = u[0] * v[1] - u[1] * v[0];
        float len = sqrtf(nx * nx + ny * ny + nz * nz);
        if (len > 1e-30f && isfinite(len))
            nx /= len, ny /= len, nz /= len;
        else
            nx = 0, ny = 0, nz = 1; /* degenerate triangle: any unit vector */
        for (int k = 0; k < 3; k++) {
            float *o = p->normals + ((size_t)t + (size_t)k) * 3;
            o[0] = nx, o[1] = ny, o[2] = nz;
        }
    }
    for (uint32_t i = 0; i < n; i++)
        idx[i] = i;
    p->vertex_count = n;
    return true;
}

bool scene_primitive_finish(scene_primitive *p, int mode, bool has_indices, scene_err *e, int mesh,
                            int prim)
{
    /* Non-indexed primitives draw vertices in order (spec 3.7.2.1). */
    if (!has_indices) {
        free(p->indices);
        p->indices = zalloc(p->vertex_count, sizeof *p->indices);
        if (!p->indices)
            return scene_fail(e, VG_ERR_NOMEM, "out of memory (mesh %d primitive %d)", mesh, prim);
        for (uint32_t i = 0; i < p->vertex_count; i++)
            p->indices[i] = i;
        p->index_count = p->vertex_count;
    }
    for (uint32_t i = 0; i < p->index_count; i++)
        if (p->indices[i] >= p->vertex_count)
            return scene_fail(e, VG_ERR_FORMAT,
                              "index %u is not below the vertex count %u (mesh %d primitive %d)",
                              p->indices[i], p->vertex_count, mesh, prim);
    uint32_t count = 0;
    uint32_t *list = to_triangle_list(p->indices, p->index_count, mode, &count);
    if (!list)
        return scene_fail(e, VG_ERR_NOMEM, "out of memory (mesh %d primitive %d)", mesh, prim);
    free(p->indices);
    p->indices = list;
    p->index_count = count;

    if (!p->normals && !unweld_flat(p))
        return scene_fail(e, VG_ERR_NOMEM, "out of memory (mesh %d primitive %d)", mesh, prim);
    size_t vc = p->vertex_count;
    if (!p->texcoords && !(p->texcoords = zalloc(vc * 2, sizeof(float))))
        return scene_fail(e, VG_ERR_NOMEM, "out of memory (mesh %d primitive %d)", mesh, prim);
    if (!p->colors) {
        if (!(p->colors = zalloc(vc * 4, sizeof(float))))
            return scene_fail(e, VG_ERR_NOMEM, "out of memory (mesh %d primitive %d)", mesh, prim);
        for (size_t i = 0; i < vc * 4; i++)
            p->colors[i] = 1.0f;
    }
    for (int k = 0; k < 3; k++) {
        p->bounds_min[k] = vc ? INFINITY : 0.0f;
        p->bounds_max[k] = vc ? -INFINITY : 0.0f;
    }
    for (size_t i = 0; i < vc; i++)
        for (int k = 0; k < 3; k++) {
            float v = p->positions[i * 3 + (size_t)k];
            p->bounds_min[k] = fminf(p->bounds_min[k], v);
            p->bounds_max[k] = fmaxf(p->bounds_max[k], v);
        }
    return true;
}

/* ------------------------------------------------------------------------- */
/* Hierarchy                                                                 */
/* ------------------------------------------------------------------------- */

/* Depth-first pre-order from the given roots, children in file order, with
 * an explicit stack (a chain of 100k nodes must not overflow the C stack).
 * gltf.cpp guarantees one parent per node, so each node is pushed once. */
static int walk(const scene *s, const scene_children *c, const int *roots, int root_count, int *out,
                int *stack, unsigned char *seen)
{
    int n = 0;
    for (int r = 0; r < root_count; r++) {
        if (seen[roots[r]])
            continue; /* a root listed twice in a scene */
        int top = 0;
        stack[top++] = roots[r];
        seen[roots[r]] = 1;
        while (top > 0) {
            int node = stack[--top];
            out[n++] = node;
            for (int k = c->child_start[node + 1] - 1; k >= c->child_start[node]; k--) {
                int child = c->child_list[k];
                if (!seen[child] && top < s->node_count) {
                    seen[child] = 1;
                    stack[top++] = child;
                }
            }
        }
    }
    return n;
}

static bool order_nodes(scene *s, const scene_children *c, scene_err *e)
{
    size_t nc = (size_t)s->node_count;
    int *roots = zalloc(nc, sizeof *roots), *stack = zalloc(nc, sizeof *stack);
    unsigned char *seen = zalloc(nc, 1);
    s->node_order = zalloc(nc, sizeof *s->node_order);
    if (!roots || !stack || !seen || !s->node_order) {
        free(roots), free(stack), free(seen);
        return scene_fail(e, VG_ERR_NOMEM, "out of memory ordering %d nodes", s->node_count);
    }
    int root_count = 0;
    for (int i = 0; i < s->node_count; i++)
        if (s->nodes[i].parent < 0)
            roots[root_count++] = i;
    int n = walk(s, c, roots, root_count, s->node_order, stack, seen);
    bool ok = true;
    if (n != s->node_count) {
        /* Every node has one parent, so the unreached ones hang off a cycle. */
        int bad = 0;
        while (bad < s->node_count && seen[bad])
            bad++;
        ok = scene_fail(e, VG_ERR_FORMAT, "node %d is part of a cycle in the node hierarchy", bad);
    }
    free(roots), free(stack), free(seen);
    if (!ok)
        return false;
    /* extras.saliency: inherited from the parent when absent, 0 at roots. */
    for (int k = 0; k < s->node_count; k++) {
        scene_node *nd = &s->nodes[s->node_order[k]];
        if (!nd->has_saliency)
            nd->saliency = nd->parent >= 0 ? s->nodes[nd->parent].saliency : 0.0f;
    }
    return true;
}

/* ------------------------------------------------------------------------- */
/* Instances                                                                 */
/* ------------------------------------------------------------------------- */

static bool check_skin(const scene *s, const scene_node *nd, int node, const scene_primitive *p, scene_err *e)
{
    if (nd->skin < 0 || !p->joints || !p->weights)
        return true;
    const scene_skin *sk = &s->skins[nd->skin];
    for (size_t i = 0; i < (size_t)p->vertex_count * 4; i++)
        if (p->joints[i] >= sk->joint_count)
            return scene_fail(e, VG_ERR_FORMAT,
                              "joint index %u is not below the %d joints of skin %d (node %d mesh %d)",
                              p->joints[i], sk->joint_count, nd->skin, node, nd->mesh);
    return true;
}

static bool layout_instances(scene *s, const scene_children *c, scene_err *e)
{
    size_t nc = (size_t)s->node_count;
    int *order = zalloc(nc, sizeof *order), *stack = zalloc(nc, sizeof *stack);
    unsigned char *seen = zalloc(nc, 1);
    if (!order || !stack || !seen) {
        free(order), free(stack), free(seen);
        return scene_fail(e, VG_ERR_NOMEM, "out of memory laying out instances");
    }
    int n = walk(s, c, s->roots, s->root_count, order, stack, seen);
    free(stack), free(seen);

    /* Pass 1: count and check against the caps. */
    size_t count = 0, vertices = 0, indices = 0;
    for (int k = 0; k < n; k++) {
        const scene_node *nd = &s->nodes[order[k]];
        if (nd->mesh < 0)
            continue;
        const scene_mesh *m = &s->meshes[nd->mesh];
        for (int j = 0; j < m->primitive_count; j++) {
            const scene_primitive *p = &s->primitives[m->first_primitive + j];
            if (!check_skin(s, nd, order[k], p, e)) {
                free(order);
                return false;
            }
            count++;
            vertices += p->vertex_count;
            indices += p->index_count;
            if (vertices > SCENE_MAX_INSTANCE_VERTICES || indices > SCENE_MAX_INSTANCE_INDICES) {
                free(order);
                return scene_fail(e, VG_ERR_UNSUPPORTED,
                                  "the default scene instances more than %u vertices or %u indices",
                                  SCENE_MAX_INSTANCE_VERTICES, SCENE_MAX_INSTANCE_INDICES);
            }
        }
    }
    s->instances = zalloc(count, sizeof *s->instances);
    s->indices = zalloc(indices, sizeof *s->indices);
    if (!s->instances || !s->indices) {
        free(order);
        return scene_fail(e, VG_ERR_NOMEM, "out of memory for %zu instances", count);
    }
    /* Pass 2: ids 1..N in depth-first order, vertices and indices back to back. */
    uint32_t v = 0, ix = 0;
    for (int k = 0; k < n; k++) {
        const scene_node *nd = &s->nodes[order[k]];
        if (nd->mesh < 0)
            continue;
        const scene_mesh *m = &s->meshes[nd->mesh];
        for (int j = 0; j < m->primitive_count; j++) {
            const scene_primitive *p = &s->primitives[m->first_primitive + j];
            scene_instance *in = &s->instances[s->instance_count++];
            *in = (scene_instance){.node = order[k], .primitive = m->first_primitive + j,
                                   .id = (uint32_t)s->instance_count, .saliency = nd->saliency,
                                   .first_vertex = v, .first_index = ix};
            memcpy(s->indices + ix, p->indices, (size_t)p->index_count * sizeof *s->indices);
            v += p->vertex_count;
            ix += p->index_count;
        }
    }
    s->vertex_count = v;
    s->index_count = ix;
    free(order);
    return true;
}

/* ------------------------------------------------------------------------- */
/* Build                                                                     */
/* ------------------------------------------------------------------------- */

bool scene_build(scene *s, const scene_children *c, scene_err *e)
{
    if (!order_nodes(s, c, e))
        return false;
    for (int r = 0; r < s->root_count; r++)
        if (s->nodes[s->roots[r]].parent >= 0)
            return scene_fail(e, VG_ERR_FORMAT, "scene node %d is not a root node (it has parent %d)",
                              s->roots[r], s->nodes[s->roots[r]].parent);
    if (!layout_instances(s, c, e))
        return false;

    s->duration = 0.0f;
    for (int a = 0; a < s->animation_count; a++)
        s->duration = fmaxf(s->duration, s->animations[a].end);
    /* "animated": evaluation at some t differs from the raw vertices. */
    s->animated = s->channel_count > 0;
    for (int i = 0; i < s->instance_count && !s->animated; i++) {
        const scene_node *nd = &s->nodes[s->instances[i].node];
        const scene_primitive *p = &s->primitives[s->instances[i].primitive];
        if (nd->skin >= 0 && p->joints)
            s->animated = true;
        const float *w = nd->weights ? nd->weights : s->meshes[nd->mesh].weights;
        for (int k = 0; w && k < p->target_count && k < s->meshes[nd->mesh].weight_count; k++)
            if (w[k] != 0.0f)
                s->animated = true;
    }

    scene_state st;
    vg_status status = scene_state_init(s, &st);
    if (status != VG_OK)
        return scene_fail(e, status, "out of memory for the evaluation state");
    scene_evaluate(s, 0.0f, &st);
    memcpy(s->bounds_min, st.bounds_min, sizeof s->bounds_min);
    memcpy(s->bounds_max, st.bounds_max, sizeof s->bounds_max);
    scene_state_free(&st);
    return true;
}

void scene_destroy(scene *s)
{
    if (!s)
        return;
    for (int i = 0; i < s->primitive_count; i++) {
        scene_primitive *p = &s->primitives[i];
        free(p->positions), free(p->normals), free(p->texcoords), free(p->colors);
        free(p->joints), free(p->weights), free(p->indices);
        free(p->target_positions), free(p->target_normals);
    }
    for (int i = 0; i < s->mesh_count; i++)
        free(s->meshes[i].weights);
    for (int i = 0; i < s->node_count; i++)
        free(s->nodes[i].weights);
    for (int i = 0; i < s->texture_count; i++)
        free(s->textures[i].rgba);
    for (int i = 0; i < s->skin_count; i++)
        free(s->skins[i].joints), free(s->skins[i].inverse_bind);
    for (int i = 0; i < s->sampler_count; i++)
        free(s->samplers[i].times), free(s->samplers[i].values);
    free(s->nodes), free(s->meshes), free(s->primitives), free(s->materials), free(s->textures);
    free(s->cameras), free(s->skins), free(s->animations), free(s->channels), free(s->samplers);
    free(s->roots), free(s->node_order), free(s->instances), free(s->indices), free(s->files);
    memset(s, 0, sizeof *s);
    free(s);
}
