/* vergence — scene evaluation at time t: animation, hierarchy, morph
 * targets, skins, world-space vertices.
 *
 * Order (glTF 2.0 spec 3.5 "Nodes and hierarchy", 3.7.2.2 "Morph targets",
 * 3.7.3 "Skins", 3.11 "Animations"):
 *   1. every node's local TRS and morph weights at rest (node weights
 *      override mesh weights);
 *   2. every animation channel overwrites its node's T, R, S or weights,
 *      then the pose hook (run-time motion, scene_set_pose_hook) may;
 *   3. world matrices in parent-before-child order;
 *   4. joint matrices world(joint) * inverseBind per skin;
 *   5. per instance: base + sum of weighted target deltas (object space),
 *      then the skin blend or the node's world matrix; normals by the
 *      cofactor matrix (the inverse transpose up to a positive factor);
 *   6. bounds.
 * Nothing is allocated here: the state holds all scratch memory. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/srgb.h"
#include "scene_internal.h"

/* ------------------------------------------------------------------------- */
/* State                                                                     */
/* ------------------------------------------------------------------------- */

static void *zalloc(size_t count, size_t size)
{
    return calloc(count ? count : 1, size);
}

/* Forgets where the instances were placed: the next evaluation places all. */
static void unplace(const scene *s, scene_state *st)
{
    for (size_t i = 0; i < (size_t)s->instance_count * 16; i++)
        st->placed[i] = NAN;
}

vg_status scene_state_init(const scene *s, scene_state *st)
{
    memset(st, 0, sizeof *st);
    size_t nc = (size_t)s->node_count, vc = s->vertex_count, joints = 0;
    for (int i = 0; i < s->skin_count; i++)
        joints += (size_t)s->skins[i].joint_count;
    st->world = zalloc(nc * 16, sizeof(float));
    st->local = zalloc(nc * 10, sizeof(float));
    st->positions = zalloc(vc * 3, sizeof(float));
    st->normals = zalloc(vc * 3, sizeof(float));
    st->morph_offset = zalloc(nc + 1, sizeof(int));
    st->joint_matrices = zalloc(joints * 16, sizeof(float));
    st->placed = zalloc((size_t)s->instance_count * 16, sizeof(float));
    st->instance_bounds = zalloc((size_t)s->instance_count * 6, sizeof(float));
    if (!st->world || !st->local || !st->positions || !st->normals || !st->morph_offset || !st->joint_matrices ||
        !st->placed || !st->instance_bounds) {
        scene_state_free(st);
        return VG_ERR_NOMEM;
    }
    int total = 0;
    for (int i = 0; i < s->node_count; i++) {
        st->morph_offset[i] = total;
        if (s->nodes[i].mesh >= 0)
            total += s->meshes[s->nodes[i].mesh].weight_count;
    }
    st->morph_offset[nc] = total;
    if (!(st->morph_weights = zalloc((size_t)total, sizeof(float)))) {
        scene_state_free(st);
        return VG_ERR_NOMEM;
    }
    unplace(s, st);
    return VG_OK;
}

void scene_state_free(scene_state *st)
{
    if (!st)
        return;
    free(st->world), free(st->local), free(st->positions), free(st->normals);
    free(st->morph_weights), free(st->morph_offset), free(st->joint_matrices);
    free(st->placed), free(st->instance_bounds);
    memset(st, 0, sizeof *st);
}

/* ------------------------------------------------------------------------- */
/* Steps 1-4: nodes                                                          */
/* ------------------------------------------------------------------------- */

static void pose_rest(const scene *s, scene_state *st)
{
    for (int i = 0; i < s->node_count; i++) {
        const scene_node *n = &s->nodes[i];
        float *l = st->local + (size_t)i * 10;
        memcpy(l, n->translation, 3 * sizeof(float));
        memcpy(l + 3, n->rotation, 4 * sizeof(float));
        memcpy(l + 7, n->scale, 3 * sizeof(float));
        int count = st->morph_offset[i + 1] - st->morph_offset[i];
        if (count > 0) {
            const float *w = n->weights ? n->weights : s->meshes[n->mesh].weights;
            memcpy(st->morph_weights + st->morph_offset[i], w, (size_t)count * sizeof(float));
        }
    }
}

static void pose_animate(const scene *s, float t, scene_state *st)
{
    for (int c = 0; c < s->channel_count; c++) {
        const scene_channel *ch = &s->channels[c];
        const scene_sampler *smp = &s->samplers[ch->sampler];
        float *l = st->local + (size_t)ch->node * 10;
        switch (ch->path) {
        case SCENE_PATH_TRANSLATION: scene_sampler_sample(smp, t, false, l); break;
        case SCENE_PATH_ROTATION:
            scene_sampler_sample(smp, t, true, l + 3);
            scene_quat_normalize(l + 3); /* STEP keys are taken as stored */
            break;
        case SCENE_PATH_SCALE: scene_sampler_sample(smp, t, false, l + 7); break;
        case SCENE_PATH_WEIGHTS:
            /* gltf.cpp checked components == the node's weight count. */
            scene_sampler_sample(smp, t, false, st->morph_weights + st->morph_offset[ch->node]);
            break;
        default: break;
        }
    }
}

static void pose_world(const scene *s, scene_state *st)
{
    for (int k = 0; k < s->node_count; k++) {
        int i = s->node_order[k];
        const scene_node *n = &s->nodes[i];
        float local[16], *w = st->world + (size_t)i * 16;
        const float *l = st->local + (size_t)i * 10;
        /* Matrix nodes are never animated: gltf.cpp drops such channels. */
        if (n->has_matrix)
            memcpy(local, n->matrix, sizeof local);
        else
            scene_mat4_from_trs(local, l, l + 3, l + 7);
        if (n->parent >= 0)
            scene_mat4_mul(w, st->world + (size_t)n->parent * 16, local);
        else
            memcpy(w, local, sizeof local);
    }
}

/* Spec 3.7.3.2: jointMatrix = inverse(world(mesh node)) * world(joint) *
 * inverseBind, then the mesh node's world transform is applied; the two
 * mesh-node factors cancel, so the world-space skin matrix is
 * world(joint) * inverseBind (and no inverse is needed). */
static void pose_joints(const scene *s, scene_state *st)
{
    float *out = st->joint_matrices;
    for (int i = 0; i < s->skin_count; i++) {
        const scene_skin *sk = &s->skins[i];
        for (int j = 0; j < sk->joint_count; j++, out += 16)
            scene_mat4_mul(out, st->world + (size_t)sk->joints[j] * 16, sk->inverse_bind + (size_t)j * 16);
    }
}

/* ------------------------------------------------------------------------- */
/* Step 5: vertices                                                          */
/* ------------------------------------------------------------------------- */

/* Normal matrix of an affine 3x3 part (columns a, b, c; m is column-major
 * with a stride of 4 per column): the cofactor matrix equals
 * det * inverse-transpose, so multiplying by sign(det) gives the direction
 * of the inverse transpose without a division (and survives det = 0). */
static inline void normal_matrix(const float *a, const float *b, const float *c, float out[9])
{
    float bc0 = b[1] * c[2] - b[2] * c[1], bc1 = b[2] * c[0] - b[0] * c[2], bc2 = b[0] * c[1] - b[1] * c[0];
    float sign = a[0] * bc0 + a[1] * bc1 + a[2] * bc2 < 0.0f ? -1.0f : 1.0f;
    out[0] = bc0 * sign, out[1] = bc1 * sign, out[2] = bc2 * sign;
    out[3] = (c[1] * a[2] - c[2] * a[1]) * sign;
    out[4] = (c[2] * a[0] - c[0] * a[2]) * sign;
    out[5] = (c[0] * a[1] - c[1] * a[0]) * sign;
    out[6] = (a[1] * b[2] - a[2] * b[1]) * sign;
    out[7] = (a[2] * b[0] - a[0] * b[2]) * sign;
    out[8] = (a[0] * b[1] - a[1] * b[0]) * sign;
}

/* In place: p = M p (affine: 3 columns + translation, 4 floats apart) and
 * n = normalize(nm n). */
static inline void transform(const float *m, const float nm[9], float *p, float *n)
{
    float x = p[0], y = p[1], z = p[2];
    p[0] = m[0] * x + m[4] * y + m[8] * z + m[12];
    p[1] = m[1] * x + m[5] * y + m[9] * z + m[13];
    p[2] = m[2] * x + m[6] * y + m[10] * z + m[14];
    float a = n[0], b = n[1], c = n[2];
    float nx = nm[0] * a + nm[3] * b + nm[6] * c;
    float ny = nm[1] * a + nm[4] * b + nm[7] * c;
    float nz = nm[2] * a + nm[5] * b + nm[8] * c;
    float len2 = nx * nx + ny * ny + nz * nz;
    if (len2 > 1e-30f && len2 < INFINITY) {
        float inv = 1.0f / sqrtf(len2);
        n[0] = nx * inv, n[1] = ny * inv, n[2] = nz * inv;
    } else {
        n[0] = 0.0f, n[1] = 0.0f, n[2] = 1.0f; /* promised unit length */
    }
}

/* Object-space vertices with morph targets applied (spec 3.7.2.2). */
static void morph(const scene_primitive *p, const float *w, int wc, float *pos, float *nrm)
{
    size_t n3 = (size_t)p->vertex_count * 3;
    memcpy(pos, p->positions, n3 * sizeof(float));
    memcpy(nrm, p->normals, n3 * sizeof(float));
    int tc = p->target_count < wc ? p->target_count : wc;
    for (int k = 0; k < tc; k++) {
        float wk = w[k];
        if (wk == 0.0f)
            continue;
        const float *tp = p->target_positions + (size_t)k * n3;
        for (size_t i = 0; i < n3; i++)
            pos[i] += wk * tp[i];
        if (p->target_normals) {
            const float *tn = p->target_normals + (size_t)k * n3;
            for (size_t i = 0; i < n3; i++)
                nrm[i] += wk * tn[i];
        }
    }
}

static void skin_vertices(const scene_primitive *p, const float *joints, const float *world, float *pos, float *nrm)
{
    float rigid_nm[9];
    normal_matrix(world, world + 4, world + 8, rigid_nm);
    for (uint32_t v = 0; v < p->vertex_count; v++) {
        const uint16_t *j = p->joints + (size_t)v * 4;
        const float *w = p->weights + (size_t)v * 4;
        float *vp = pos + (size_t)v * 3, *vn = nrm + (size_t)v * 3;
        if (!(w[0] + w[1] + w[2] + w[3] > 0.0f)) {
            /* No influence at all (invalid, but seen in exports): keep the
             * vertex rigidly on its node instead of collapsing it to 0. */
            transform(world, rigid_nm, vp, vn);
            continue;
        }
        /* Blend only the affine 3x4 part: the bottom rows are 0 0 0 1. */
        float m[16] = {0}, nm[9];
        for (int k = 0; k < 4; k++) {
            float wk = w[k];
            if (wk == 0.0f)
                continue;
            const float *jm = joints + (size_t)j[k] * 16;
            for (int col = 0; col < 4; col++)
                for (int r = 0; r < 3; r++)
                    m[col * 4 + r] += wk * jm[col * 4 + r];
        }
        normal_matrix(m, m + 4, m + 8, nm);
        transform(m, nm, vp, vn);
    }
}

/* The bounds of n positions (xyz); +-infinity when n is 0. */
static void bounds_of(const float *pos, size_t n, float lo[3], float hi[3])
{
    for (int k = 0; k < 3; k++)
        lo[k] = INFINITY, hi[k] = -INFINITY;
    for (size_t i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            float v = pos[i * 3 + (size_t)k];
            lo[k] = fminf(lo[k], v);
            hi[k] = fmaxf(hi[k], v);
        }
}

static bool instance_skinned(const scene *s, const scene_instance *in)
{
    const scene_primitive *p = &s->primitives[in->primitive];
    return s->nodes[in->node].skin >= 0 && p->joints && p->weights;
}

bool scene_instance_rigid(const scene *s, const scene_state *st, int i)
{
    const scene_instance *in = &s->instances[i];
    return st->morph_offset[in->node + 1] == st->morph_offset[in->node] && !instance_skinned(s, in);
}

/* An instance's vertices in world space. A rigid one whose world matrix is
 * the one it was last placed with keeps its vertices: the same inputs, the
 * same bits (most of a scene stands still). */
static void place_instances(const scene *s, scene_state *st)
{
    for (int i = 0; i < s->instance_count; i++) {
        const scene_instance *in = &s->instances[i];
        const scene_node *n = &s->nodes[in->node];
        const scene_primitive *p = &s->primitives[in->primitive];
        const float *world = st->world + (size_t)in->node * 16;
        float *pos = st->positions + (size_t)in->first_vertex * 3;
        float *nrm = st->normals + (size_t)in->first_vertex * 3;
        float *placed = st->placed + (size_t)i * 16;
        if (scene_instance_rigid(s, st, i) && !isnan(placed[0]) && !memcmp(placed, world, 16 * sizeof(float)))
            continue;
        memcpy(placed, world, 16 * sizeof(float));
        int wc = st->morph_offset[in->node + 1] - st->morph_offset[in->node];
        morph(p, st->morph_weights + st->morph_offset[in->node], wc, pos, nrm);
        if (instance_skinned(s, in)) {
            size_t first = 0;
            for (int k = 0; k < n->skin; k++)
                first += (size_t)s->skins[k].joint_count;
            skin_vertices(p, st->joint_matrices + first * 16, world, pos, nrm);
        } else {
            float nm[9];
            normal_matrix(world, world + 4, world + 8, nm);
            for (uint32_t v = 0; v < p->vertex_count; v++)
                transform(world, nm, pos + (size_t)v * 3, nrm + (size_t)v * 3);
        }
        bounds_of(pos, p->vertex_count, st->instance_bounds + (size_t)i * 6, st->instance_bounds + (size_t)i * 6 + 3);
    }
}

/* ------------------------------------------------------------------------- */
/* Evaluate                                                                  */
/* ------------------------------------------------------------------------- */

static void state_bounds(const scene *s, scene_state *st);
static void state_bounds_of_instances(const scene *s, scene_state *st);

void scene_evaluate(const scene *s, float t, scene_state *st)
{
    if (!isfinite(t))
        t = 0.0f;
    st->t = t;
    pose_rest(s, st);
    pose_animate(s, t, st);
    if (s->pose_hook)
        s->pose_hook(s->pose_user, s, t, st->local);
    pose_world(s, st);
    pose_joints(s, st);
    place_instances(s, st);
    state_bounds_of_instances(s, st);
}

void scene_evaluate_known(const scene *s, const scene_past *past, float t, scene_state *st)
{
    if (!past || !isfinite(t) || t <= past->now->t) {
        scene_evaluate(s, t, st);
        return;
    }
    const scene_state *a = past->before, *b = past->now;
    float span = b->t - a->t, u = span > 0.0f ? (t - b->t) / span : 0.0f;
    st->t = t;
    /* Nodes: the translation goes on, the rotation and scale are held (a
     * linear step of a rotation matrix is no rotation). */
    size_t nn = (size_t)s->node_count * 16;
    memcpy(st->world, b->world, nn * sizeof(float));
    for (int n = 0; n < s->node_count; n++)
        for (int k = 12; k < 15; k++)
            st->world[16 * n + k] += u * (b->world[16 * n + k] - a->world[16 * n + k]);
    size_t nv = (size_t)s->vertex_count * 3;
    for (size_t i = 0; i < nv; i++)
        st->positions[i] = b->positions[i] + u * (b->positions[i] - a->positions[i]);
    memcpy(st->normals, b->normals, nv * sizeof(float));
    unplace(s, st); /* its vertices are no instance's placement */
    state_bounds(s, st);
}

/* The bounds of all positions (0 for a scene without vertices). */
static void state_bounds(const scene *s, scene_state *st)
{
    bounds_of(st->positions, s->vertex_count, st->bounds_min, st->bounds_max);
    if (!s->vertex_count)
        for (int k = 0; k < 3; k++)
            st->bounds_min[k] = st->bounds_max[k] = 0.0f;
}

/* The same from the instances' bounds (their vertices are all the scene's,
 * and a minimum of minima is the minimum). */
static void state_bounds_of_instances(const scene *s, scene_state *st)
{
    for (int k = 0; k < 3; k++)
        st->bounds_min[k] = INFINITY, st->bounds_max[k] = -INFINITY;
    for (int i = 0; i < s->instance_count; i++)
        for (int k = 0; k < 3; k++) {
            st->bounds_min[k] = fminf(st->bounds_min[k], st->instance_bounds[(size_t)i * 6 + (size_t)k]);
            st->bounds_max[k] = fmaxf(st->bounds_max[k], st->instance_bounds[(size_t)i * 6 + 3 + (size_t)k]);
        }
    if (!s->vertex_count)
        for (int k = 0; k < 3; k++)
            st->bounds_min[k] = st->bounds_max[k] = 0.0f;
}

bool scene_has_saliency(const scene *s)
{
    for (int i = 0; i < s->node_count; i++)
        if (s->nodes[i].has_saliency)
            return true;
    return false;
}

void scene_mean_base_color(const scene *s, float rgb[3])
{
    double sum[3] = {0, 0, 0}, weight = 0;
    for (int i = 0; i < s->instance_count; i++) {
        const scene_instance *in = &s->instances[i];
        const scene_primitive *p = &s->primitives[in->primitive];
        const scene_material *m = p->material >= 0 ? &s->materials[p->material] : NULL;
        double c[3] = {1, 1, 1};
        if (m) {
            for (int k = 0; k < 3; k++)
                c[k] = m->base_color[k];
            if (m->base_color_texture >= 0 && m->base_color_texture < s->texture_count) {
                const scene_texture *t = &s->textures[m->base_color_texture];
                size_t n = (size_t)t->width * t->height, step = n / 4096 + 1, count = 0;
                double tm[3] = {0, 0, 0};
                for (size_t q = 0; q < n; q += step, count++)
                    for (int k = 0; k < 3; k++)
                        tm[k] += vg_srgb_to_linear(t->rgba[4 * q + (size_t)k] / 255.0f);
                for (int k = 0; k < 3 && count; k++)
                    c[k] *= tm[k] / (double)count;
            }
        }
        double vm[3] = {0, 0, 0};
        for (uint32_t v = 0; v < p->vertex_count; v++)
            for (int k = 0; k < 3; k++)
                vm[k] += p->colors[4 * (size_t)v + (size_t)k];
        double w = (double)p->index_count / 3.0;
        for (int k = 0; k < 3; k++)
            sum[k] += w * c[k] * (p->vertex_count ? vm[k] / p->vertex_count : 1.0);
        weight += w;
    }
    for (int k = 0; k < 3; k++)
        rgb[k] = weight > 0 ? (float)(sum[k] / weight) : 0.5f;
}

void scene_set_pose_hook(scene *s, scene_pose_fn fn, void *user)
{
    s->pose_hook = fn;
    s->pose_user = fn ? user : NULL;
}

int scene_find_node(const scene *s, const char *name)
{
    for (int i = 0; i < s->node_count; i++)
        if (!strcmp(s->nodes[i].name, name))
            return i;
    return -1;
}

int scene_node_instance_ids(const scene *s, int node, uint32_t *ids, int cap)
{
    int n = 0;
    for (int k = 0; k < s->instance_count; k++)
        if (s->instances[k].node == node) {
            if (n < cap)
                ids[n] = s->instances[k].id;
            n++;
        }
    return n;
}
