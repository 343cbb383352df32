/* Cameras: loading, resolving into Vulkan clip space (y down, depth 0..1). */
#include <stdlib.h>
#include <string.h>

#include "unit.h"

/* Clip-space position of a world point. */
static void project(const vg_camera *c, const double p[3], double clip[4])
{
    for (int r = 0; r < 4; r++)
        clip[r] = c->view_proj[r] * p[0] + c->view_proj[4 + r] * p[1] + c->view_proj[8 + r] * p[2] +
                  c->view_proj[12 + r];
}

static void ahead(const vg_camera *c, double dist, double up, double right, double out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = c->position[k] + c->forward[k] * dist + c->up[k] * up + c->right[k] * right;
}

/* The properties every resolved camera must have. */
static void check_clip_space(const vg_camera *c, const char *what)
{
    double p[3], q[4];
    double mid = 0.5 * (c->znear + c->zfar);
    ahead(c, mid, 0, 0, p);
    project(c, p, q);
    EXPECT_NEAR(q[0] / q[3], 0, 1e-5, "%s: straight ahead projects to the centre (x)", what);
    EXPECT_NEAR(q[1] / q[3], 0, 1e-5, "%s: straight ahead projects to the centre (y)", what);
    ahead(c, c->znear, 0, 0, p);
    project(c, p, q);
    EXPECT_NEAR(q[2] / q[3], 0, 1e-4, "%s: near plane maps to depth 0", what);
    ahead(c, c->zfar, 0, 0, p);
    project(c, p, q);
    EXPECT_NEAR(q[2] / q[3], 1, 1e-4, "%s: far plane maps to depth 1", what);
    ahead(c, mid, 0.01 * mid, 0, p);
    project(c, p, q);
    EXPECT(q[1] / q[3] < 0, "%s: up in the world is up on screen, negative y in Vulkan (%g)", what, q[1] / q[3]);
    ahead(c, mid, 0, 0.01 * mid, p);
    project(c, p, q);
    EXPECT(q[0] / q[3] > 0, "%s: right is +x (%g)", what, q[0] / q[3]);
    EXPECT(c->proj[5] < 0, "%s: proj[1][1] is negative (%g)", what, c->proj[5]);
    double ortho = c->forward[0] * c->up[0] + c->forward[1] * c->up[1] + c->forward[2] * c->up[2];
    EXPECT_NEAR(ortho, 0, 1e-5, "%s: forward and up are orthogonal", what);
}

void test_cameras(void)
{
    scene *s = unit_load(unit_asset("Cameras/glTF/Cameras.gltf"));
    if (!s)
        return;
    EXPECT(s->camera_count == 2, "%d cameras", s->camera_count);
    if (s->camera_count == 2) {
        const scene_camera *p = &s->cameras[0], *o = &s->cameras[1];
        EXPECT(!p->orthographic && fabsf(p->yfov - 0.7f) < 1e-6f && p->aspect == 1.0f, "perspective %g %g", p->yfov,
              p->aspect);
        EXPECT(fabsf(p->znear - 0.01f) < 1e-7f && p->zfar == 100.0f, "perspective near/far %g %g", p->znear, p->zfar);
        EXPECT(o->orthographic && o->xmag == 1.0f && o->ymag == 1.0f && o->zfar == 100.0f, "orthographic %g %g %g",
              o->xmag, o->ymag, o->zfar);
    }
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    scene_evaluate(s, 0.0f, &st);
    vg_camera c;
    scene_camera_resolve(s, &st, 0, 2.0f, &c);
    EXPECT(c.source_node == 1 && !c.orthographic, "camera 0 is node %d", c.source_node);
    EXPECT_NEAR(c.position[0], 0.5, 1e-6, "camera position x");
    EXPECT_NEAR(c.position[1], 0.5, 1e-6, "camera position y");
    EXPECT_NEAR(c.position[2], 3.0, 1e-6, "camera position z");
    EXPECT_NEAR(c.forward[2], -1.0, 1e-6, "glTF cameras look down -Z");
    EXPECT_NEAR(c.yfov, 0.7, 1e-6, "yfov");
    EXPECT_NEAR(c.aspect, 2.0, 1e-6, "the viewport's aspect wins (no stretching)");
    EXPECT_NEAR(c.proj[0], 1.0 / tan(0.35) / 2.0, 1e-4, "proj[0][0]");
    EXPECT_NEAR(c.znear, 0.01, 1e-7, "znear");
    EXPECT_NEAR(c.zfar, 100, 1e-4, "zfar");
    check_clip_space(&c, "perspective camera");
    scene_camera_resolve(s, &st, 0, 0.0f, &c);
    EXPECT_NEAR(c.aspect, 1.0, 1e-6, "aspect 0 falls back to the camera's aspectRatio");
    scene_camera_resolve(s, &st, 1, 1.0f, &c);
    EXPECT(c.source_node == 2 && c.orthographic, "camera 1 is node %d, orthographic %d", c.source_node, c.orthographic);
    EXPECT_NEAR(c.proj[5], -1.0, 1e-6, "orthographic ymag 1, y down");
    check_clip_space(&c, "orthographic camera");
    scene_camera_resolve(s, &st, 7, 1.0f, &c);
    EXPECT(c.source_node == 2, "index past the end clamps to the last camera (%d)", c.source_node);
    scene_camera_resolve(s, &st, -3, 1.0f, &c);
    EXPECT(c.source_node == 1, "negative index clamps to the first camera (%d)", c.source_node);
    scene_state_free(&st);
    scene_destroy(s);
}

void test_camera_resolve(void)
{
    /* No camera in the file: the automatic view frames the bounds. */
    scene *s = unit_load(unit_asset("Duck/glTF-Binary/Duck.glb"));
    scene *b = unit_load(unit_asset("BoxAnimated/glTF/BoxAnimated.gltf"));
    if (!s || !b)
        return;
    scene_state st;
    EXPECT(scene_state_init(b, &st) == VG_OK, "state");
    scene_evaluate(b, 0.0f, &st);
    vg_camera c;
    scene_camera_resolve(b, &st, 0, 16.0f / 9.0f, &c);
    EXPECT(c.source_node == -1, "automatic camera (%d)", c.source_node);
    EXPECT_NEAR(c.yfov, 0.785398, 1e-5, "automatic yfov is 45 degrees");
    check_clip_space(&c, "automatic camera");
    double centre[3], q[4];
    for (int k = 0; k < 3; k++)
        centre[k] = 0.5 * (b->bounds_min[k] + b->bounds_max[k]);
    project(&c, centre, q);
    EXPECT_NEAR(q[0] / q[3], 0, 1e-5, "the bounds centre is at the screen centre (x)");
    EXPECT_NEAR(q[1] / q[3], 0, 1e-5, "the bounds centre is at the screen centre (y)");
    EXPECT(c.position[2] > centre[2] && c.position[1] > centre[1], "seen from +Z, slightly above");
    for (int corner = 0; corner < 8; corner++) {
        double p[3] = {corner & 1 ? b->bounds_max[0] : b->bounds_min[0], corner & 2 ? b->bounds_max[1] : b->bounds_min[1],
                       corner & 4 ? b->bounds_max[2] : b->bounds_min[2]};
        project(&c, p, q);
        EXPECT(fabs(q[0]) <= q[3] && fabs(q[1]) <= q[3] && q[2] >= 0 && q[2] <= q[3],
              "bounds corner %d is inside the view volume (%g %g %g / %g)", corner, q[0], q[1], q[2], q[3]);
    }
    scene_state_free(&st);

    /* Duck has a camera node: index 0 resolves to it. */
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    scene_evaluate(s, 0.0f, &st);
    scene_camera_resolve(s, &st, 0, 1.5f, &c);
    EXPECT(c.source_node >= 0 && s->nodes[c.source_node].camera == 0, "Duck camera node %d", c.source_node);
    check_clip_space(&c, "Duck camera");
    scene_state_free(&st);
    scene_destroy(s);
    scene_destroy(b);
}

void test_camera_infinite(void)
{
    /* A perspective camera without zfar (infinite) at z = 10 looking at a
     * triangle spread along z: the chosen far plane must enclose it. */
    float tri[9] = {0, 0, 0, 1, 0, -20, 0, 1, 5};
    const char *json =
        "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0},{\"camera\":0,\"translation\":[0,0,10],\"scale\":[2,3,4]}],"
        "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":1.0,\"znear\":0.1}}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
        "\"buffers\":[{\"byteLength\":36,\"uri\":\"@BUF@\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"}]}";
    scene *s = unit_load(unit_write_gltf("infinite.gltf", json, tri, sizeof tri));
    if (!s)
        return;
    EXPECT(s->camera_count == 1 && s->cameras[0].zfar == 0.0f, "zfar absent is stored as 0 (infinite)");
    scene_state st;
    EXPECT(scene_state_init(s, &st) == VG_OK, "state");
    scene_evaluate(s, 0.0f, &st);
    vg_camera c;
    scene_camera_resolve(s, &st, 0, 1.0f, &c);
    EXPECT(c.source_node == 1 && isfinite(c.zfar) && c.zfar > c.znear, "finite far %g", c.zfar);
    EXPECT(c.zfar >= 30.0f, "far %g encloses the point 30 units ahead", c.zfar);
    check_clip_space(&c, "infinite camera with a scaled node");
    for (int v = 0; v < 3; v++) {
        double p[3] = {st.positions[v * 3], st.positions[v * 3 + 1], st.positions[v * 3 + 2]}, q[4];
        project(&c, p, q);
        EXPECT(q[2] >= 0 && q[2] <= q[3], "vertex %d depth %g in 0..1", v, q[2] / q[3]);
    }
    scene_state_free(&st);
    scene_destroy(s);
}
