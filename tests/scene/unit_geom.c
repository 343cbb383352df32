/* Geometry decoding: sparse accessors, interleaving, generated indices and
 * normals, topology conversion, saliency, textures. */
#include <stdlib.h>
#include <string.h>

#include "unit.h"

static scene_state evaluate(const scene *s, float t)
{
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    scene_evaluate(s, t, &st);
    return st;
}

void test_sparse(void)
{
    scene *s = unit_load(unit_asset("SimpleSparseAccessor/glTF/SimpleSparseAccessor.gltf"));
    size_t n = 0;
    uint8_t *bin = unit_read(unit_asset("SimpleSparseAccessor/glTF/SimpleSparseAccessor.bin"), &n);
    if (!s || !bin)
        return;
    /* Base positions: bufferView 1 (byte 72), 14 x vec3; sparse indices:
     * bufferView 2 (byte 240), 3 x u16; values: bufferView 3 (byte 248). */
    float pos[14 * 3];
    for (int i = 0; i < 14 * 3; i++)
        pos[i] = unit_f32(bin, 72 + 4 * (size_t)i);
    int replaced = 0;
    for (int k = 0; k < 3; k++) {
        int v = unit_u16(bin, 240 + 2 * (size_t)k);
        for (int c = 0; c < 3; c++) {
            float f = unit_f32(bin, 248 + 12 * (size_t)k + 4 * (size_t)c);
            replaced += pos[v * 3 + c] != f;
            pos[v * 3 + c] = f;
        }
    }
    EXPECT(replaced > 0, "the sparse values differ from the base");
    scene_state st = evaluate(s, 0.0f);
    /* No normals: vertex i of the state is mesh vertex indices[i]. */
    EXPECT(s->vertex_count == 36, "%u vertices", s->vertex_count);
    for (int i = 0; i < 36 && s->vertex_count == 36; i++) {
        int v = unit_u16(bin, 2 * (size_t)i);
        for (int c = 0; c < 3; c++)
            EXPECT_NEAR(st.positions[i * 3 + c], pos[v * 3 + c], 0, "vertex %d (mesh vertex %d)", i, v);
    }
    EXPECT_NEAR(s->bounds_max[0], 6.0, 0, "max x from the sparse values");
    EXPECT_NEAR(s->bounds_max[1], 4.0, 0, "max y from the sparse values");
    scene_state_free(&st);
    free(bin);
    scene_destroy(s);
}

void test_interleaved(void)
{
    scene *a = unit_load(unit_asset("Box/glTF/Box.gltf"));
    scene *b = unit_load(unit_asset("BoxInterleaved/glTF/BoxInterleaved.gltf"));
    if (!a || !b)
        return;
    EXPECT(a->vertex_count == b->vertex_count && a->index_count == b->index_count, "%u/%u vs %u/%u",
          a->vertex_count, a->index_count, b->vertex_count, b->index_count);
    scene_state sa = evaluate(a, 0.0f), sb = evaluate(b, 0.0f);
    for (uint32_t i = 0; i < a->vertex_count * 3 && a->vertex_count == b->vertex_count; i++) {
        EXPECT_NEAR(sa.positions[i], sb.positions[i], 0, "position component %u", i);
        EXPECT_NEAR(sa.normals[i], sb.normals[i], 0, "normal component %u", i);
    }
    for (uint32_t i = 0; i < a->index_count && a->index_count == b->index_count; i++)
        EXPECT(a->indices[i] == b->indices[i], "index %u: %u vs %u", i, a->indices[i], b->indices[i]);
    scene_state_free(&sa);
    scene_state_free(&sb);
    scene_destroy(a);
    scene_destroy(b);
}

void test_no_indices(void)
{
    scene *s = unit_load(unit_asset("TriangleWithoutIndices/glTF/TriangleWithoutIndices.gltf"));
    size_t n = 0;
    uint8_t *bin = unit_read(unit_asset("TriangleWithoutIndices/glTF/triangleWithoutIndices.bin"), &n);
    if (!s || !bin)
        return;
    EXPECT(s->index_count == 3 && s->vertex_count == 3, "%u indices, %u vertices", s->index_count, s->vertex_count);
    for (uint32_t i = 0; i < s->index_count; i++)
        EXPECT(s->indices[i] == i, "generated index %u is %u", i, s->indices[i]);
    scene_state st = evaluate(s, 0.0f);
    for (int i = 0; i < 9; i++)
        EXPECT_NEAR(st.positions[i], unit_f32(bin, 4 * (size_t)i), 0, "position component %d", i);
    /* Counter-clockwise (0,0,0) (1,0,0) (0,1,0): the flat normal is +z. */
    for (int v = 0; v < 3; v++) {
        EXPECT_NEAR(st.normals[v * 3 + 0], 0, 1e-6, "normal x of vertex %d", v);
        EXPECT_NEAR(st.normals[v * 3 + 1], 0, 1e-6, "normal y of vertex %d", v);
        EXPECT_NEAR(st.normals[v * 3 + 2], 1, 1e-6, "normal z of vertex %d", v);
    }
    const scene_primitive *p = &s->primitives[0];
    for (int i = 0; i < 3 * 2; i++)
        EXPECT(p->texcoords[i] == 0.0f, "missing texcoords are zero");
    for (int i = 0; i < 3 * 4; i++)
        EXPECT(p->colors[i] == 1.0f, "missing colours are one");
    scene_state_free(&st);
    free(bin);
    scene_destroy(s);
}

void test_topology(void)
{
    /* Five vertices drawn as a strip, a fan, lines (skipped) and a
     * triangle list with a spare index (dropped). */
    struct {
        float pos[15];
        uint16_t idx[8];
    } data = {{0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 1, 0, 2, 0, 0}, {0, 1, 2, 3, 4, 0, 0, 0}};
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":["
        "{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":5},"
        "{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":6},"
        "{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":1},"
        "{\"attributes\":{\"POSITION\":0},\"indices\":2}]}],"
        "\"buffers\":[{\"byteLength\":76,\"uri\":\"@BUF@\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":60},{\"buffer\":0,\"byteOffset\":60,\"byteLength\":16}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":5,\"type\":\"VEC3\"},"
        "{\"bufferView\":1,\"componentType\":5123,\"count\":5,\"type\":\"SCALAR\"},"
        "{\"bufferView\":1,\"componentType\":5123,\"count\":4,\"type\":\"SCALAR\"}]}";
    scene *s = unit_load(unit_write_gltf("topology.gltf", json, &data, 76));
    if (!s)
        return;
    EXPECT(s->primitive_count == 3 && s->instance_count == 3, "%d primitives, %d instances (lines skipped)",
          s->primitive_count, s->instance_count);
    /* Spec 3.7.2.1: strip i = (i, i+1+i%2, i+2-i%2), fan i = (i+1, i+2, 0).
     * Vertices are unwelded (no normals), so compare the positions drawn. */
    const uint32_t strip[9] = {0, 1, 2, 1, 3, 2, 2, 3, 4}, fan[9] = {1, 2, 0, 2, 3, 0, 3, 4, 0}, list[3] = {0, 1, 2};
    const uint32_t *want[3] = {strip, fan, list};
    const uint32_t count[3] = {9, 9, 3};
    for (int k = 0; k < 3 && s->primitive_count == 3; k++) {
        const scene_primitive *p = &s->primitives[k];
        EXPECT(p->index_count == count[k], "primitive %d: %u indices", k, p->index_count);
        for (uint32_t i = 0; i < p->index_count && i < count[k]; i++)
            for (int c = 0; c < 3; c++)
                EXPECT_NEAR(p->positions[p->indices[i] * 3 + c], data.pos[want[k][i] * 3 + c], 0,
                           "primitive %d corner %u", k, i);
        /* All triangles keep the winding: every flat normal points the same way. */
        for (uint32_t v = 0; v < p->vertex_count; v++)
            EXPECT(fabsf(fabsf(p->normals[v * 3 + 2]) - 1.0f) < 1e-6f, "primitive %d normal %u", k, v);
    }
    const scene_primitive *st = &s->primitives[0];
    for (uint32_t v = 0; v < st->vertex_count; v++)
        EXPECT(st->normals[v * 3 + 2] == st->normals[2], "strip winding is consistent at vertex %u", v);
    scene_destroy(s);
}

void test_saliency(void)
{
    float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0,4,5,7]}],\"nodes\":["
        "{\"mesh\":0,\"children\":[1],\"extras\":{\"saliency\":0.8}},"      /* 0 */
        "{\"mesh\":0,\"children\":[2]},"                                     /* 1: inherits 0.8 */
        "{\"children\":[3],\"extras\":{\"saliency\":0.2}},"                 /* 2 */
        "{\"mesh\":0},"                                                      /* 3: inherits 0.2 */
        "{\"mesh\":0},"                                                      /* 4: root, 0 */
        "{\"children\":[6],\"extras\":{\"saliency\":7}},"                   /* 5: clamped to 1 */
        "{\"mesh\":0,\"extras\":{\"saliency\":-2}},"                        /* 6: clamped to 0 */
        "{\"mesh\":0,\"extras\":{\"saliency\":\"high\",\"other\":1}}],"     /* 7: not a number */
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
        "\"buffers\":[{\"byteLength\":36,\"uri\":\"@BUF@\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}]}";
    scene *s = unit_load(unit_write_gltf("saliency.gltf", json, tri, sizeof tri));
    if (!s)
        return;
    const float want[8] = {0.8f, 0.8f, 0.2f, 0.2f, 0.0f, 1.0f, 0.0f, 0.0f};
    const bool has[8] = {true, false, true, false, false, true, true, false};
    for (int i = 0; i < 8 && s->node_count == 8; i++) {
        EXPECT_NEAR(s->nodes[i].saliency, want[i], 1e-6, "node %d saliency", i);
        EXPECT(s->nodes[i].has_saliency == has[i], "node %d has_saliency", i);
    }
    /* Instances in depth-first order: nodes 0, 1, 3, 4, 6, 7. */
    const int nodes[6] = {0, 1, 3, 4, 6, 7};
    EXPECT(s->instance_count == 6, "%d instances", s->instance_count);
    for (int i = 0; i < 6 && s->instance_count == 6; i++) {
        EXPECT(s->instances[i].node == nodes[i] && s->instances[i].id == (uint32_t)i + 1, "instance %d: node %d id %u",
              i, s->instances[i].node, s->instances[i].id);
        EXPECT_NEAR(s->instances[i].saliency, want[nodes[i]], 1e-6, "instance %d saliency", i);
        EXPECT(s->instances[i].first_vertex == (uint32_t)i * 3, "instance %d first vertex %u", i,
              s->instances[i].first_vertex);
    }
    scene_destroy(s);
}

void test_textures(void)
{
    scene *s = unit_load(unit_asset("BoxTextured/glTF-Binary/BoxTextured.glb"));
    scene *t = unit_load(unit_asset("BoxTextured/glTF/BoxTextured.gltf"));
    if (!s || !t)
        return;
    EXPECT(s->texture_count == 1 && t->texture_count == 1, "%d and %d textures", s->texture_count, t->texture_count);
    if (s->texture_count == 1 && t->texture_count == 1) {
        const scene_texture *a = &s->textures[0], *b = &t->textures[0];
        EXPECT(a->width > 0 && a->height > 0 && a->rgba, "%dx%d", a->width, a->height);
        /* The embedded (bufferView) and external (file) images decode alike. */
        EXPECT(a->width == b->width && a->height == b->height &&
                  !memcmp(a->rgba, b->rgba, (size_t)a->width * (size_t)a->height * 4),
              "GLB and .gltf images differ");
        EXPECT(s->materials[0].base_color_texture == 0, "material texture %d", s->materials[0].base_color_texture);
    }
    scene_destroy(s);
    scene_destroy(t);
}

void test_normals(void)
{
    /* One triangle with a slanted normal (1, 0, 1)/sqrt 2 drawn by three
     * nodes: identity, mirrored in x, stretched 2x in x. Normals follow the
     * inverse transpose (spec 3.7.2.1 leaves it to the renderer; it is the
     * only choice that keeps them perpendicular), mirrored ones included. */
    float data[18] = {0, 0, 0, 1, 0, -1, 0, 1, 0, 0.7071068f, 0, 0.7071068f, 0.7071068f, 0, 0.7071068f,
                      0.7071068f, 0, 0.7071068f};
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0,1,2]}],"
        "\"nodes\":[{\"mesh\":0},{\"mesh\":0,\"scale\":[-1,1,1]},{\"mesh\":0,\"scale\":[2,1,1]}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1}}]}],"
        "\"buffers\":[{\"byteLength\":72,\"uri\":\"@BUF@\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":36}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
        "{\"bufferView\":1,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}]}";
    scene *s = unit_load(unit_write_gltf("normals.gltf", json, data, sizeof data));
    if (!s)
        return;
    scene_state st = evaluate(s, 0.0f);
    const double k = 1.0 / sqrt(1.25);
    const double want[3][3] = {{0.7071068, 0, 0.7071068}, {-0.7071068, 0, 0.7071068}, {0.5 * k, 0, k}};
    for (int i = 0; i < 3 && s->vertex_count == 9; i++)
        for (int v = 0; v < 3; v++)
            for (int c = 0; c < 3; c++)
                EXPECT_NEAR(st.normals[(i * 3 + v) * 3 + c], want[i][c], 1e-6, "instance %d vertex %d normal[%d]", i,
                           v, c);
    /* The normal stays perpendicular to the transformed surface. */
    for (int i = 0; i < 3 && s->vertex_count == 9; i++) {
        const float *p = st.positions + i * 9, *n = st.normals + i * 9;
        double e[3] = {p[3] - p[0], p[4] - p[1], p[5] - p[2]};
        EXPECT_NEAR(e[0] * n[0] + e[1] * n[1] + e[2] * n[2], 0, 1e-6, "instance %d: normal perpendicular", i);
    }
    scene_state_free(&st);
    scene_destroy(s);
}

void test_colors(void)
{
    /* COLOR_0 as normalised u8 VEC3 (alpha becomes 1), normalised u16
     * VEC4, and float VEC3; TEXCOORD_0 as normalised u16 (quantised). */
    struct {
        float pos[9];
        uint8_t c8[12];    /* 3 x RGB, each padded to 4 bytes (byteStride 4) */
        uint16_t c16[12];  /* 3 x RGBA */
        float cf[9];       /* 3 x RGB */
        uint16_t uv[6];
        uint16_t pad;
    } d = {{0, 0, 0, 1, 0, 0, 0, 1, 0},
           {255, 0, 51, 0, 0, 255, 0, 0, 102, 102, 102, 0},
           {65535, 0, 0, 32768, 0, 65535, 0, 65535, 0, 0, 65535, 0},
           {0.25f, 0.5f, 0.75f, 1, 1, 1, 0, 0, 0},
           {0, 0, 65535, 0, 0, 32768},
           0};
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
        "\"meshes\":[{\"primitives\":["
        "{\"attributes\":{\"POSITION\":0,\"COLOR_0\":1,\"TEXCOORD_0\":4}},"
        "{\"attributes\":{\"POSITION\":0,\"COLOR_0\":2}},"
        "{\"attributes\":{\"POSITION\":0,\"COLOR_0\":3}}]}],"
        "\"buffers\":[{\"byteLength\":124,\"uri\":\"@BUF@\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},"
        "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":12,\"byteStride\":4},"
        "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":24},"
        "{\"buffer\":0,\"byteOffset\":72,\"byteLength\":36},"
        "{\"buffer\":0,\"byteOffset\":108,\"byteLength\":12}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
        "{\"bufferView\":1,\"componentType\":5121,\"normalized\":true,\"count\":3,\"type\":\"VEC3\"},"
        "{\"bufferView\":2,\"componentType\":5123,\"normalized\":true,\"count\":3,\"type\":\"VEC4\"},"
        "{\"bufferView\":3,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
        "{\"bufferView\":4,\"componentType\":5123,\"normalized\":true,\"count\":3,\"type\":\"VEC2\"}]}";
    scene *s = unit_load(unit_write_gltf("colors.gltf", json, &d, 124));
    if (!s)
        return;
    EXPECT(s->primitive_count == 3, "%d primitives", s->primitive_count);
    if (s->primitive_count != 3) {
        scene_destroy(s);
        return;
    }
    /* No normals: vertices are unwelded in order 0 1 2, so vertex i is i. */
    const scene_primitive *p = s->primitives;
    const float want8[12] = {1, 0, 0.2f, 1, 0, 1, 0, 1, 0.4f, 0.4f, 0.4f, 1};
    for (int i = 0; i < 12; i++)
        EXPECT_NEAR(p[0].colors[i], want8[i], 1e-6, "u8 colour component %d", i);
    const float want16[12] = {1, 0, 0, 32768.0f / 65535.0f, 0, 1, 0, 1, 0, 0, 1, 0};
    for (int i = 0; i < 12; i++)
        EXPECT_NEAR(p[1].colors[i], want16[i], 1e-6, "u16 colour component %d", i);
    const float wantf[12] = {0.25f, 0.5f, 0.75f, 1, 1, 1, 1, 1, 0, 0, 0, 1};
    for (int i = 0; i < 12; i++)
        EXPECT_NEAR(p[2].colors[i], wantf[i], 1e-6, "float colour component %d", i);
    const float wantuv[6] = {0, 0, 1, 0, 0, 32768.0f / 65535.0f};
    for (int i = 0; i < 6; i++)
        EXPECT_NEAR(p[0].texcoords[i], wantuv[i], 1e-6, "normalised u16 texcoord %d", i);
    scene_destroy(s);
}

void test_magic(void)
{
    /* The container is told by its first bytes: a GLB named .gltf and a
     * JSON glTF (embedded buffers) named .glb both load. */
    size_t nb = 0, nt = 0;
    uint8_t *glb = unit_read(unit_asset("Box/glTF-Binary/Box.glb"), &nb);
    uint8_t *txt = unit_read(unit_asset("Box/glTF-Embedded/Box.gltf"), &nt);
    if (!glb || !txt)
        return;
    char a[160], b[160];
    snprintf(a, sizeof a, "%s", unit_write_gltf("really-binary.gltf", "", NULL, 0));
    snprintf(b, sizeof b, "%s", unit_write_gltf("really-text.glb", "", NULL, 0));
    FILE *f = fopen(a, "wb");
    if (f)
        fwrite(glb, 1, nb, f), fclose(f);
    f = fopen(b, "wb");
    if (f)
        fwrite(txt, 1, nt, f), fclose(f);
    scene *s = unit_load(a), *t = unit_load(b);
    EXPECT(s && t && s->vertex_count == 24 && t->vertex_count == 24, "both boxes load with 24 vertices");
    scene_destroy(s);
    scene_destroy(t);
    free(glb);
    free(txt);
}
