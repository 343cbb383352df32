/* Animation, morph targets, skins and the hierarchy against values computed
 * independently from the raw bytes of the sample files. */
#include <stdlib.h>
#include <string.h>

#include "unit.h"

/* ------------------------------------------------------------------------- */
/* InterpolationTest: STEP / LINEAR / CUBICSPLINE on T, R, S                 */
/* ------------------------------------------------------------------------- */

/* From InterpolationTest.gltf: animation -> (node, path, mode, byte offsets
 * of the input and output accessors in interpolation.bin), 5 keys each. */
static const struct {
    const char *name;
    int node, comps, mode;
    size_t in, out;
} k_channels[] = {
    {"Step Scale", 0, 3, UNIT_STEP, 7372, 7392},
    {"Linear Scale", 3, 3, UNIT_LINEAR, 7372, 7392},
    {"CubicSpline Scale", 4, 3, UNIT_CUBIC, 7652, 7672},
    {"Step Rotation", 5, 4, UNIT_STEP, 7852, 7872},
    {"CubicSpline Rotation", 6, 4, UNIT_CUBIC, 7952, 7972},
    {"Linear Rotation", 7, 4, UNIT_LINEAR, 8212, 8232},
    {"Step Translation", 8, 3, UNIT_STEP, 8312, 8332},
    {"CubicSpline Translation", 9, 3, UNIT_CUBIC, 8392, 8412},
    {"Linear Translation", 10, 3, UNIT_LINEAR, 8592, 8612},
};

void test_interpolation(void)
{
    scene *s = unit_load(unit_asset("InterpolationTest/glTF/InterpolationTest.gltf"));
    size_t size = 0;
    uint8_t *bin = unit_read(unit_asset("InterpolationTest/glTF/interpolation.bin"), &size);
    if (!s || !bin)
        return;
    EXPECT(s->animation_count == 9 && s->channel_count == 9, "%d animations, %d channels", s->animation_count,
          s->channel_count);
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    const double times[] = {-1.0, 0.0, 0.0417, 0.2, 0.4167, 0.5, 0.77, 0.875, 1.0, 1.25, 1.4, 1.6667, 1.7, 3.0};
    for (size_t c = 0; c < sizeof k_channels / sizeof k_channels[0]; c++) {
        int comps = k_channels[c].comps, per = k_channels[c].mode == UNIT_CUBIC ? 3 : 1;
        float keys[5], values[5 * 3 * 4];
        for (int k = 0; k < 5; k++)
            keys[k] = unit_f32(bin, k_channels[c].in + 4 * (size_t)k);
        for (int v = 0; v < 5 * per * comps; v++)
            values[v] = unit_f32(bin, k_channels[c].out + 4 * (size_t)v);
        for (size_t ti = 0; ti < sizeof times / sizeof times[0]; ti++) {
            double want[4];
            unit_sample(keys, 5, values, comps, k_channels[c].mode, comps == 4, times[ti], want);
            scene_evaluate(s, (float)times[ti], &st);
            int n = k_channels[c].node;
            const float *local = st.local + n * 10, *w = st.world + n * 16;
            if (comps == 4) {
                /* q and -q are the same rotation. */
                double d = 0;
                for (int k = 0; k < 4; k++)
                    d += want[k] * local[3 + k];
                EXPECT_NEAR(fabs(d), 1.0, 2e-5, "%s rotation at t=%g", k_channels[c].name, times[ti]);
                /* World x axis = R applied to (1,0,0) (the node has no scale). */
                double x = want[0], y = want[1], z = want[2], qw = want[3];
                double ax[3] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * qw), 2 * (x * z - y * qw)};
                for (int k = 0; k < 3; k++)
                    EXPECT_NEAR(w[k], ax[k], 1e-4, "%s world axis at t=%g", k_channels[c].name, times[ti]);
            } else if (strstr(k_channels[c].name, "Scale")) {
                for (int k = 0; k < 3; k++) {
                    EXPECT_NEAR(local[7 + k], want[k], 1e-5, "%s at t=%g", k_channels[c].name, times[ti]);
                    double len = sqrt(w[k * 4] * w[k * 4] + w[k * 4 + 1] * w[k * 4 + 1] + w[k * 4 + 2] * w[k * 4 + 2]);
                    EXPECT_NEAR(len, fabs(want[k]), 1e-4, "%s world column at t=%g", k_channels[c].name, times[ti]);
                }
            } else {
                for (int k = 0; k < 3; k++) {
                    EXPECT_NEAR(local[k], want[k], 1e-4, "%s at t=%g", k_channels[c].name, times[ti]);
                    EXPECT_NEAR(w[12 + k], want[k], 1e-4, "%s world at t=%g", k_channels[c].name, times[ti]);
                }
            }
        }
    }
    scene_state_free(&st);
    free(bin);
    scene_destroy(s);
}

/* ------------------------------------------------------------------------- */
/* CUBICSPLINE tangents are scaled by the key interval                       */
/* ------------------------------------------------------------------------- */

void test_cubic_tangents(void)
{
    /* Keys at t = 1 and 3 (interval 2); translation and rotation splines
     * with non-zero tangents, laid out (in-tangent, value, out-tangent). */
    float data[2 + 18 + 24] = {
        1, 3,
        0, 0, 0, 0, 0, 0, 1, 2, 3, /* key 0: a, v, b */
        4, 5, 6, 10, 0, -10, 0, 0, 0, /* key 1 */
        0, 0, 0, 0, 0, 0, 0, 1, 0.3f, 0, 0, 0, /* key 0 rotation: a, v = identity, b */
        0, 0, -0.2f, 0, 0, 0, 0.7071068f, 0.7071068f, 0, 0, 0, 0, /* key 1: 90 deg about z */
    };
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{}],"
        "\"buffers\":[{\"byteLength\":176,\"uri\":\"@BUF@\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":8},{\"buffer\":0,\"byteOffset\":8,\"byteLength\":72},"
        "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":96}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\",\"min\":[1],\"max\":[3]},"
        "{\"bufferView\":1,\"componentType\":5126,\"count\":6,\"type\":\"VEC3\"},"
        "{\"bufferView\":2,\"componentType\":5126,\"count\":6,\"type\":\"VEC4\"}],"
        "\"animations\":[{\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":\"translation\"}},"
        "{\"sampler\":1,\"target\":{\"node\":0,\"path\":\"rotation\"}}],"
        "\"samplers\":[{\"input\":0,\"output\":1,\"interpolation\":\"CUBICSPLINE\"},"
        "{\"input\":0,\"output\":2,\"interpolation\":\"CUBICSPLINE\"}]}]}";
    scene *s = unit_load(unit_write_gltf("cubic.gltf", json, data, sizeof data));
    if (!s)
        return;
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    /* Hand value at the middle (u = 0.5, dt = 2): 0.5 v0 + 0.25 b0 + 0.5 v1 - 0.25 a1. */
    scene_evaluate(s, 2.0f, &st);
    EXPECT_NEAR(st.local[0], 4.25, 1e-5, "x at t=2");
    EXPECT_NEAR(st.local[1], -0.75, 1e-5, "y at t=2");
    EXPECT_NEAR(st.local[2], -5.75, 1e-5, "z at t=2");
    const double times[] = {0.0, 1.0, 1.3, 2.0, 2.6, 2.99, 3.0, 9.0};
    for (size_t i = 0; i < sizeof times / sizeof times[0]; i++) {
        double t[3], q[4];
        unit_sample(data, 2, data + 2, 3, UNIT_CUBIC, false, times[i], t);
        unit_sample(data, 2, data + 20, 4, UNIT_CUBIC, true, times[i], q);
        scene_evaluate(s, (float)times[i], &st);
        for (int k = 0; k < 3; k++)
            EXPECT_NEAR(st.local[k], t[k], 1e-4, "translation[%d] at t=%g", k, times[i]);
        double len = 0;
        for (int k = 0; k < 4; k++) {
            EXPECT_NEAR(st.local[3 + k], q[k], 1e-4, "rotation[%d] at t=%g", k, times[i]);
            len += st.local[3 + k] * st.local[3 + k];
        }
        EXPECT_NEAR(len, 1.0, 1e-5, "rotation is normalised after the spline at t=%g", times[i]);
    }
    scene_state_free(&st);
    scene_destroy(s);
}

/* ------------------------------------------------------------------------- */
/* Morph targets                                                             */
/* ------------------------------------------------------------------------- */

void test_morph(void)
{
    scene *s = unit_load(unit_asset("SimpleMorph/glTF/SimpleMorph.gltf"));
    size_t gn = 0, an = 0;
    uint8_t *geo = unit_read(unit_asset("SimpleMorph/glTF/simpleMorphGeometry.bin"), &gn);
    uint8_t *anim = unit_read(unit_asset("SimpleMorph/glTF/simpleMorphAnimation.bin"), &an);
    if (!s || !geo || !anim)
        return;
    /* bufferView 1 starts at byte 8: base, target 0, target 1 (3 x vec3 each). */
    float base[9], t0[9], t1[9], keys[5], weights[10];
    for (int i = 0; i < 9; i++) {
        base[i] = unit_f32(geo, 8 + 4 * (size_t)i);
        t0[i] = unit_f32(geo, 44 + 4 * (size_t)i);
        t1[i] = unit_f32(geo, 80 + 4 * (size_t)i);
    }
    for (int i = 0; i < 5; i++)
        keys[i] = unit_f32(anim, 4 * (size_t)i);
    for (int i = 0; i < 10; i++)
        weights[i] = unit_f32(anim, 20 + 4 * (size_t)i);
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    /* SimpleMorph has no normals: vertices are unwelded through the indices 0 1 2. */
    const double times[] = {0.0, 0.5, 1.3, 2.0, 3.7, 4.0, 6.0};
    for (size_t ti = 0; ti < sizeof times / sizeof times[0]; ti++) {
        double w[2];
        unit_sample(keys, 5, weights, 2, UNIT_LINEAR, false, times[ti], w);
        scene_evaluate(s, (float)times[ti], &st);
        for (int i = 0; i < 9; i++)
            EXPECT_NEAR(st.positions[i], base[i] + w[0] * t0[i] + w[1] * t1[i], 1e-5, "component %d at t=%g", i,
                       times[ti]);
    }
    /* Without the animation the mesh's default weights (0.5, 0.5) apply. */
    scene still = *s;
    still.channel_count = 0;
    scene_evaluate(&still, 1.0f, &st);
    for (int i = 0; i < 9; i++)
        EXPECT_NEAR(st.positions[i], base[i] + 0.5 * t0[i] + 0.5 * t1[i], 1e-5, "default weights, component %d", i);
    scene_state_free(&st);
    free(geo);
    free(anim);
    scene_destroy(s);
}

void test_morph_override(void)
{
    /* One triangle, one target moving every vertex by +1 in z; mesh weight
     * 0.25; node 0 overrides it with 0.75, node 1 keeps the mesh's. */
    float data[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0,\"weights\":[0.75]},{\"mesh\":0,\"translation\":[5,0,0]}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"targets\":[{\"POSITION\":1}]}],"
        "\"weights\":[0.25]}],"
        "\"buffers\":[{\"byteLength\":72,\"uri\":\"@BUF@\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":36}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
        "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}]}";
    scene *s = unit_load(unit_write_gltf("override.gltf", json, data, sizeof data));
    if (!s)
        return;
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    scene_evaluate(s, 0.0f, &st);
    EXPECT(s->instance_count == 2, "%d instances", s->instance_count);
    for (int v = 0; v < 3; v++) {
        EXPECT_NEAR(st.positions[v * 3 + 2], 0.75, 1e-6, "node weights override, vertex %d", v);
        EXPECT_NEAR(st.positions[(3 + v) * 3 + 2], 0.25, 1e-6, "mesh weights, vertex %d", v);
        EXPECT_NEAR(st.positions[(3 + v) * 3 + 0], data[v * 3] + 5.0, 1e-6, "second instance moved, vertex %d", v);
    }
    EXPECT(s->animated, "non-zero morph weights count as animated");
    scene_state_free(&st);
    scene_destroy(s);
}

/* ------------------------------------------------------------------------- */
/* Skins                                                                     */
/* ------------------------------------------------------------------------- */

/* SimpleSkin.gltf keeps its four buffers as data URIs: decode them here. */
static uint8_t *simple_skin_buffer(const char *text, int index, size_t *size)
{
    const char *p = text;
    for (int i = 0; i <= index && p; i++)
        if ((p = strstr(p, "base64,")))
            p += 7;
    return p ? unit_base64(p - 7, size) : NULL;
}

void test_skin(void)
{
    const char *path = unit_asset("SimpleSkin/glTF/SimpleSkin.gltf");
    size_t n = 0, sz[4] = {0};
    char *text = (char *)unit_read(path, &n);
    scene *s = unit_load(path);
    if (!text || !s)
        return;
    uint8_t *b[4];
    for (int i = 0; i < 4; i++)
        b[i] = simple_skin_buffer(text, i, &sz[i]);
    EXPECT(sz[0] == 168 && sz[1] == 320 && sz[2] == 128 && sz[3] == 240, "buffer sizes %zu %zu %zu %zu", sz[0], sz[1],
          sz[2], sz[3]);
    float keys[12], rot[48];
    for (int i = 0; i < 12; i++)
        keys[i] = unit_f32(b[3], 4 * (size_t)i);
    for (int i = 0; i < 48; i++)
        rot[i] = unit_f32(b[3], 48 + 4 * (size_t)i);
    double ibm[2][16];
    for (int j = 0; j < 2; j++)
        for (int k = 0; k < 16; k++)
            ibm[j][k] = unit_f32(b[2], (size_t)(j * 16 + k) * 4);
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    const double times[] = {0.0, 0.75, 2.0, 3.3, 5.5, 7.0};
    for (size_t ti = 0; ti < sizeof times / sizeof times[0]; ti++) {
        /* Joints are nodes 1 (translation 0 1 0) and 2 (its child, animated
         * rotation); the mesh node 0 is the identity. */
        double q[4], j0[16], j1[16], r[16], t1[3] = {0, 1, 0}, t0[3] = {0, 0, 0}, one[3] = {1, 1, 1},
                                                 q0[4] = {0, 0, 0, 1};
        unit_sample(keys, 12, rot, 4, UNIT_LINEAR, true, times[ti], q);
        unit_mat_trs(j0, t1, q0, one);
        unit_mat_trs(r, t0, q, one);
        unit_mat_mul(j1, j0, r);
        double m[2][16];
        unit_mat_mul(m[0], j0, ibm[0]);
        unit_mat_mul(m[1], j1, ibm[1]);
        scene_evaluate(s, (float)times[ti], &st);
        /* No normals in the file: vertex i of the state is index i of the mesh. */
        for (int i = 0; i < 24; i++) {
            int v = unit_u16(b[0], 2 * (size_t)i);
            double p[3] = {unit_f32(b[0], 48 + 12 * (size_t)v), unit_f32(b[0], 52 + 12 * (size_t)v),
                           unit_f32(b[0], 56 + 12 * (size_t)v)};
            double want[3] = {0, 0, 0};
            for (int k = 0; k < 4; k++) {
                int joint = unit_u16(b[1], 16 * (size_t)v + 2 * (size_t)k);
                double w = unit_f32(b[1], 160 + 16 * (size_t)v + 4 * (size_t)k), o[3];
                if (w == 0.0)
                    continue;
                unit_mat_point(m[joint], p, o);
                for (int c = 0; c < 3; c++)
                    want[c] += w * o[c];
            }
            for (int c = 0; c < 3; c++)
                EXPECT_NEAR(st.positions[i * 3 + c], want[c], 1e-5, "vertex %d (mesh vertex %d)[%d] at t=%g", i, v, c,
                           times[ti]);
            double len = sqrt(st.normals[i * 3] * st.normals[i * 3] + st.normals[i * 3 + 1] * st.normals[i * 3 + 1] +
                              st.normals[i * 3 + 2] * st.normals[i * 3 + 2]);
            EXPECT_NEAR(len, 1.0, 1e-5, "normal %d is unit length at t=%g", i, times[ti]);
        }
    }
    scene_state_free(&st);
    for (int i = 0; i < 4; i++)
        free(b[i]);
    free(text);
    scene_destroy(s);
}

/* With every channel off, RiggedSimple's joints sit at their rest TRS,
 * which is its bind pose: skinned vertices equal the rigid mesh. */
void test_skin_bind_pose(void)
{
    scene *s = unit_load(unit_asset("RiggedSimple/glTF/RiggedSimple.gltf"));
    if (!s)
        return;
    scene rest = *s;
    rest.channel_count = 0;
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    scene_evaluate(&rest, 0.0f, &st);
    const scene_instance *in = &s->instances[0];
    const scene_primitive *p = &s->primitives[in->primitive];
    EXPECT(s->nodes[in->node].skin >= 0 && p->joints, "the instance is skinned");
    double w[16], err = 0;
    unit_mat_from_f(w, st.world + in->node * 16);
    for (uint32_t v = 0; v < p->vertex_count; v++) {
        double q[3] = {p->positions[v * 3], p->positions[v * 3 + 1], p->positions[v * 3 + 2]}, o[3];
        unit_mat_point(w, q, o);
        for (int c = 0; c < 3; c++)
            err = fmax(err, fabs(st.positions[(in->first_vertex + v) * 3 + c] - o[c]));
    }
    EXPECT_NEAR(err, 0.0, 1e-4, "largest distance to the bind pose");
    /* And the animation really bends it away from the rest pose. */
    size_t n3 = (size_t)s->vertex_count * 3;
    float *at_rest = malloc(n3 * sizeof *at_rest);
    memcpy(at_rest, st.positions, n3 * sizeof *at_rest);
    scene_evaluate(s, s->duration * 0.5f, &st);
    double moved = 0;
    for (size_t v = 0; v < n3; v++)
        moved = fmax(moved, fabs(st.positions[v] - at_rest[v]));
    EXPECT(moved > 1e-2, "the animation moves vertices (%g)", moved);
    free(at_rest);
    scene_state_free(&st);
    scene_destroy(s);
}

/* CesiumMan (19 joints under a matrix root): every skinned vertex against a
 * from-scratch evaluation in double precision of the loaded nodes and
 * samplers (reference sampling, recursive hierarchy, weighted joints). */
static void reference_world(const scene *s, const double *local, int node, double out[16])
{
    double m[16];
    memcpy(m, local + node * 16, sizeof m);
    if (s->nodes[node].parent >= 0) {
        double p[16];
        reference_world(s, local, s->nodes[node].parent, p);
        unit_mat_mul(out, p, m);
    } else {
        memcpy(out, m, sizeof m);
    }
}

void test_skin_reference(void)
{
    scene *s = unit_load(unit_asset("CesiumMan/glTF-Binary/CesiumMan.glb"));
    if (!s)
        return;
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    double *local = malloc(sizeof(double) * 16 * (size_t)s->node_count);
    const double times[] = {0.0, 0.37, 1.0, 1.61, 2.5};
    for (size_t ti = 0; ti < sizeof times / sizeof times[0]; ti++) {
        for (int i = 0; i < s->node_count; i++) {
            const scene_node *n = &s->nodes[i];
            double t[3] = {n->translation[0], n->translation[1], n->translation[2]};
            double q[4] = {n->rotation[0], n->rotation[1], n->rotation[2], n->rotation[3]};
            double sc[3] = {n->scale[0], n->scale[1], n->scale[2]};
            for (int c = 0; c < s->channel_count; c++) {
                const scene_channel *ch = &s->channels[c];
                const scene_sampler *sm = &s->samplers[ch->sampler];
                int mode = sm->interp == SCENE_INTERP_STEP ? UNIT_STEP
                           : sm->interp == SCENE_INTERP_CUBIC ? UNIT_CUBIC : UNIT_LINEAR;
                if (ch->node != i)
                    continue;
                double *dst = ch->path == SCENE_PATH_TRANSLATION ? t : ch->path == SCENE_PATH_ROTATION ? q : sc;
                unit_sample(sm->times, sm->key_count, sm->values, sm->components, mode,
                            ch->path == SCENE_PATH_ROTATION, times[ti], dst);
            }
            if (n->has_matrix)
                unit_mat_from_f(local + i * 16, n->matrix);
            else
                unit_mat_trs(local + i * 16, t, q, sc);
        }
        scene_evaluate(s, (float)times[ti], &st);
        const scene_instance *in = &s->instances[0];
        const scene_primitive *p = &s->primitives[in->primitive];
        const scene_skin *sk = &s->skins[s->nodes[in->node].skin];
        double (*jm)[16] = malloc(sizeof *jm * (size_t)sk->joint_count), err = 0;
        for (int j = 0; j < sk->joint_count; j++) {
            double w[16], ibm[16];
            reference_world(s, local, sk->joints[j], w);
            unit_mat_from_f(ibm, sk->inverse_bind + j * 16);
            unit_mat_mul(jm[j], w, ibm);
        }
        for (uint32_t v = 0; v < p->vertex_count; v++) {
            double pos[3] = {p->positions[v * 3], p->positions[v * 3 + 1], p->positions[v * 3 + 2]}, want[3] = {0};
            for (int k = 0; k < 4; k++) {
                double o[3], wk = p->weights[v * 4 + k];
                unit_mat_point(jm[p->joints[v * 4 + k]], pos, o);
                for (int c = 0; c < 3; c++)
                    want[c] += wk * o[c];
            }
            for (int c = 0; c < 3; c++)
                err = fmax(err, fabs(st.positions[(in->first_vertex + v) * 3 + c] - want[c]));
        }
        EXPECT_NEAR(err, 0.0, 1e-4, "largest skinned vertex error at t=%g", times[ti]);
        free(jm);
    }
    free(local);
    scene_state_free(&st);
    scene_destroy(s);
}

/* ------------------------------------------------------------------------- */
/* Hierarchy                                                                 */
/* ------------------------------------------------------------------------- */

void test_hierarchy(void)
{
    scene *s = unit_load(unit_asset("BoxAnimated/glTF/BoxAnimated.gltf"));
    size_t n = 0;
    uint8_t *bin = unit_read(unit_asset("BoxAnimated/glTF/BoxAnimated0.bin"), &n);
    if (!s || !bin)
        return;
    /* Scene roots [3, 0]; 0 -> 1 -> 2. Depth-first: node 3 first, then 2. */
    EXPECT(s->instance_count == 2, "%d instances", s->instance_count);
    EXPECT(s->instances[0].node == 3 && s->instances[0].id == 1, "instance 0: node %d id %u", s->instances[0].node,
          s->instances[0].id);
    EXPECT(s->instances[1].node == 2 && s->instances[1].id == 2, "instance 1: node %d id %u", s->instances[1].node,
          s->instances[1].id);
    EXPECT(s->instances[1].first_vertex == 224 && s->instances[1].first_index == 576, "instance 1 at %u/%u",
          s->instances[1].first_vertex, s->instances[1].first_index);
    float rkeys[2], rvals[8], tkeys[4], tvals[12];
    for (int i = 0; i < 2; i++)
        rkeys[i] = unit_f32(bin, 7760 + 4 * (size_t)i);
    for (int i = 0; i < 8; i++)
        rvals[i] = unit_f32(bin, 4 * (size_t)i);
    for (int i = 0; i < 4; i++)
        tkeys[i] = unit_f32(bin, 7768 + 4 * (size_t)i);
    for (int i = 0; i < 12; i++)
        tvals[i] = unit_f32(bin, 32 + 4 * (size_t)i);
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    const double times[] = {0.0, 1.0, 1.5, 2.0, 3.0, 4.0};
    for (size_t ti = 0; ti < sizeof times / sizeof times[0]; ti++) {
        double t[3], q[4], zero[3] = {0, 0, 0}, one[3] = {1, 1, 1}, q0[4] = {-0.0, -0.0, -0.0, -1.0};
        unit_sample(tkeys, 4, tvals, 3, UNIT_LINEAR, false, times[ti], t);
        unit_sample(rkeys, 2, rvals, 4, UNIT_LINEAR, true, times[ti], q);
        double m0[16], m2[16], w[16];
        unit_mat_trs(m0, t, q0, one);
        unit_mat_trs(m2, zero, q, one);
        unit_mat_mul(w, m0, m2); /* node 1 is the identity */
        scene_evaluate(s, (float)times[ti], &st);
        for (int k = 0; k < 16; k++)
            EXPECT_NEAR(st.world[2 * 16 + k], w[k], 1e-5, "world(node 2)[%d] at t=%g", k, times[ti]);
        /* Mesh 0 positions: accessor 2, bufferView 1 at 80 + 1152, stride 12. */
        for (int v = 0; v < 96; v += 7) {
            double p[3], o[3];
            for (int c = 0; c < 3; c++)
                p[c] = unit_f32(bin, 80 + 1152 + 12 * (size_t)v + 4 * (size_t)c);
            unit_mat_point(w, p, o);
            for (int c = 0; c < 3; c++)
                EXPECT_NEAR(st.positions[(224 + v) * 3 + c], o[c], 1e-5, "vertex %d at t=%g", v, times[ti]);
        }
    }
    scene_state_free(&st);
    free(bin);
    scene_destroy(s);
}

/* scene_evaluate_known (the causal look-ahead): up to now it is the scene;
 * after it, every vertex and node origin goes on at its last velocity.
 * BoxAnimated: node 0 rises linearly over [0, 1.25] s and then stops; node 2
 * turns over [1.25, 2.5] s. */
void test_predict(void)
{
    scene *s = unit_load(unit_asset("BoxAnimated/glTF/BoxAnimated.gltf"));
    if (!s)
        return;
    scene_state now, before, pred, truth;
    EXPECT(scene_state_init(s, &now) == VG_OK && scene_state_init(s, &before) == VG_OK &&
               scene_state_init(s, &pred) == VG_OK && scene_state_init(s, &truth) == VG_OK,
           "states");
    const float step = 1.0f / 60.0f;
    const float nows[2] = {0.5f, 1.5f};
    for (int c = 0; c < 2; c++) {
        float t0 = nows[c];
        scene_evaluate(s, t0, &now);
        scene_evaluate(s, t0 - step, &before);
        scene_past past = {.now = &now, .before = &before};
        /* Up to now (and without a past) it is scene_evaluate. */
        const float known[3] = {t0 - 0.3f, t0, t0 + 0.4f};
        for (int i = 0; i < 3; i++) {
            scene_evaluate_known(s, i < 2 ? &past : NULL, known[i], &pred);
            scene_evaluate(s, known[i], &truth);
            EXPECT(memcmp(pred.positions, truth.positions, 3 * sizeof(float) * s->vertex_count) == 0,
                   "t %.3f (now %.3f%s): not the scene's own state", known[i], t0, i < 2 ? "" : ", no past");
        }
        /* After now: p_now + (t - now) / step (p_now - p_before), rotations held. */
        float t = t0 + 0.5f, u = (t - t0) / step;
        scene_evaluate_known(s, &past, t, &pred);
        for (uint32_t v = 0; v < 3 * s->vertex_count; v += 5)
            EXPECT_NEAR(pred.positions[v], now.positions[v] + u * (now.positions[v] - before.positions[v]), 1e-4,
                        "vertex float %u at %.2f from %.2f", v, t, t0);
        for (int k = 0; k < 12; k++)
            EXPECT(pred.world[2 * 16 + k] == now.world[2 * 16 + k], "node 2's rotation is not held ([%d])", k);
        EXPECT(pred.t == t, "t %g", pred.t);
    }
    /* A constant velocity is foreseen exactly: node 0 from 0.5 s to 1.0 s. */
    scene_evaluate(s, 0.5f, &now);
    scene_evaluate(s, 0.5f - step, &before);
    scene_past past = {.now = &now, .before = &before};
    scene_evaluate_known(s, &past, 1.0f, &pred);
    scene_evaluate(s, 1.0f, &truth);
    EXPECT_NEAR(pred.world[13], truth.world[13], 1e-3, "node 0 at 1.0 s predicted from 0.5 s");
    /* ... and a change of motion is not: it stops at 1.25 s (y 2.52 m). */
    scene_evaluate_known(s, &past, 2.0f, &pred);
    scene_evaluate(s, 2.0f, &truth);
    EXPECT(fabsf(pred.world[13] - truth.world[13]) > 1.0f, "node 0 at 2.0 s: predicted %.3f, truth %.3f",
           pred.world[13], truth.world[13]);
    scene_state_free(&now);
    scene_state_free(&before);
    scene_state_free(&pred);
    scene_state_free(&truth);
    scene_destroy(s);
}

/* A state evaluated again and again keeps the vertices of a rigid instance
 * that did not move (scene_state.placed); every evaluation must still give
 * the bits a fresh state gives: positions, normals, bounds. Times forwards,
 * repeated, backwards and across a clip's end, a prediction in between
 * (scene_evaluate_known writes vertices no placement made), and a pose hook
 * that moves one node at some times only. Rigid, hierarchical, morphed and
 * skinned scenes, and the game's and the demo's. */
static void hook_nudge(void *user, const scene *s, float t, float *local)
{
    (void)s;
    if (t > 0.55f && t < 0.95f)
        local[10 * *(const int *)user + 1] += 0.25f; /* the node's translation y */
}

void test_placement_cache(void)
{
    const char *paths[] = {unit_asset("BoxAnimated/glTF/BoxAnimated.gltf"),
                           unit_asset("AnimatedMorphCube/glTF/AnimatedMorphCube.gltf"),
                           unit_asset("CesiumMan/glTF/CesiumMan.gltf"), "content/arena.gltf", "content/balloon.gltf"};
    const float times[] = {0.0f, 0.0f, 0.1f, 0.6f, 0.6f, 0.2f, 0.7f, 0.7f, 5.0f, 40.0f, 0.0f};
    for (size_t p = 0; p < sizeof paths / sizeof paths[0]; p++) {
        scene *s = unit_load(paths[p]);
        if (!s)
            continue;
        int node = s->node_count - 1;
        if (p == 0)
            scene_set_pose_hook(s, hook_nudge, &node);
        scene_state kept, now, before, fresh;
        EXPECT(scene_state_init(s, &kept) == VG_OK && scene_state_init(s, &now) == VG_OK &&
                   scene_state_init(s, &before) == VG_OK,
               "states");
        size_t bytes = 3 * sizeof(float) * s->vertex_count;
        int placements = 0;
        for (size_t i = 0; i < sizeof times / sizeof times[0]; i++) {
            if (i == 7) { /* a prediction into the kept state, then the time it was last evaluated at */
                scene_evaluate(s, times[i] - 0.1f, &now);
                scene_evaluate(s, times[i] - 0.2f, &before);
                scene_past past = {.now = &now, .before = &before};
                scene_evaluate_known(s, &past, times[i] + 0.3f, &kept);
            }
            scene_evaluate(s, times[i], &kept);
            EXPECT(scene_state_init(s, &fresh) == VG_OK, "state");
            scene_evaluate(s, times[i], &fresh);
            EXPECT(!memcmp(kept.positions, fresh.positions, bytes) && !memcmp(kept.normals, fresh.normals, bytes),
                   "%s at %.2f s (step %zu): the kept state's vertices differ from a fresh one's", paths[p],
                   times[i], i);
            EXPECT(!memcmp(kept.bounds_min, fresh.bounds_min, sizeof kept.bounds_min) &&
                       !memcmp(kept.bounds_max, fresh.bounds_max, sizeof kept.bounds_max),
                   "%s at %.2f s: bounds differ", paths[p], times[i]);
            for (int k = 0; k < s->instance_count; k++)
                placements += !isnan(kept.placed[16 * k]);
            scene_state_free(&fresh);
        }
        EXPECT(placements > 0, "%s: the state recorded no placement to keep", paths[p]);
        scene_state_free(&kept);
        scene_state_free(&now);
        scene_state_free(&before);
        scene_destroy(s);
    }
}
