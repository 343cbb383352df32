/* vergence — G-buffer verification (issue "Engine foundation").
 *
 *   depth_embree.<scene>  linear depth against an Embree 3 ray cast of the
 *                         same evaluated triangles (DESIGN.md: "An Embree ray
 *                         cast of the scene must agree with the gbuffer depth")
 *   motion_cubes          motion to the previous/next keyframe against the
 *                         analytic motion of each instance's rigid transform
 *   deterministic         two frame objects render the same frames byte for byte
 *
 * Every case runs the GPU with validation from the environment (CTest sets
 * VERGENCE_VALIDATE=1) and fails on any validation message. Run from the
 * project root (content/ paths are relative). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_util.h"
#include "test.h"

/* Small images keep each case at a few seconds on lavapipe. */
#define TEST_W 480
#define TEST_H 270

/* ------------------------------------------------------------------------- */
/* depth_embree                                                              */
/* ------------------------------------------------------------------------- */

/* Median relative depth difference allowed (the bound), and the
 * share of pixels on which raster and ray cast must agree about hit/miss and
 * about the instance hit (edge snapping moves only a few silhouette pixels). */
#define DEPTH_MEDIAN_MAX 0.005
#define DEPTH_P95_MAX 0.01
#define HIT_AGREEMENT_MIN 0.998
#define ID_AGREEMENT_MIN 0.995

static int depth_embree(const char *path, long index)
{
    rt_ctx c;
    if (rt_open(&c, path, TEST_W, TEST_H))
        return 1;
    vg_status st = frame_render(c.frame, index);
    CHECK(st == VG_OK, "frame_render(%ld): %s", index, vg_status_text(st));
    const frame_outputs *o = frame_get_outputs(c.frame);
    const frame_times *ft = frame_get_times(c.frame);
    vg_camera cam = *frame_get_camera(c.frame);

    /* The same instant the G-buffer was rendered at (the engine evaluates in float). */
    scene_state ss;
    CHECK(scene_state_init(c.scene, &ss) == VG_OK, "scene_state_init");
    scene_evaluate(c.scene, (float)ft->t, &ss);
    rt_embree e;
    CHECK(rt_embree_build(&e, c.scene, &ss) == 0, "embree scene");

    double vp[16], inv[16];
    rt_mat4_to_double(cam.view_proj, vp);
    CHECK(rt_mat4_invert(vp, inv), "camera view_proj is singular");

    size_t px = (size_t)c.width * c.height, both = 0, agree_hit = 0, agree_id = 0;
    size_t raster_only = 0, ray_only = 0;
    double *rel = malloc(px * sizeof *rel);
    CHECK(rel, "out of memory");
    double worst = -1.0, worst_gb = 0.0, worst_rt = 0.0;
    uint32_t worst_x = 0, worst_y = 0;
    for (uint32_t y = 0; y < c.height; y++) {
        for (uint32_t x = 0; x < c.width; x++) {
            size_t i = (size_t)y * c.width + x;
            rt_ray r;
            rt_pixel_ray(inv, c.width, c.height, x + 0.5, y + 0.5, &r);
            double t = 0.0;
            int inst = rt_embree_cast(&e, &r, &t);
            bool raster_hit = o->ids[i] != 0, ray_hit = inst >= 0;
            agree_hit += raster_hit == ray_hit;
            raster_only += raster_hit && !ray_hit;
            ray_only += ray_hit && !raster_hit;
            if (!raster_hit || !ray_hit)
                continue;
            agree_id += o->ids[i] == c.scene->instances[inst].id;
            double hit[3];
            for (int k = 0; k < 3; k++)
                hit[k] = r.org[k] + t * r.dir[k];
            double d_rt = rt_linear_depth(&cam, hit), d_gb = o->depth[i];
            double diff = fabs(d_gb - d_rt) / d_rt;
            rel[both++] = diff;
            if (diff > worst)
                worst = diff, worst_gb = d_gb, worst_rt = d_rt, worst_x = x, worst_y = y;
        }
    }
    rt_stats s = rt_stats_of(rel, both);
    free(rel);
    rt_embree_destroy(&e);
    scene_state_free(&ss);
    double hit_share = (double)agree_hit / (double)px, id_share = both ? (double)agree_id / (double)both : 0.0;
    printf("%s frame %ld (t = %.4f s) %ux%u\n", path, index, ft->t, TEST_W, TEST_H);
    printf("  pixels hit by both: %zu of %zu; hit/miss agreement %.4f%% (raster only %zu, ray only %zu); "
           "same instance %.4f%%\n", both, px, 100.0 * hit_share, raster_only, ray_only, 100.0 * id_share);
    printf("  relative depth difference: median %.3g  p95 %.3g  p99 %.3g  max %.3g "
           "(pixel %u,%u: gbuffer %.5f m, embree %.5f m)\n",
           s.median, s.p95, s.p99, s.max, worst_x, worst_y, worst_gb, worst_rt);
    int messages = rt_close(&c);

    CHECK(both > px / 4, "only %zu of %zu pixels hit geometry in both", both, px);
    CHECK(s.median < DEPTH_MEDIAN_MAX, "median relative depth difference %.4g >= %.4g", s.median, DEPTH_MEDIAN_MAX);
    CHECK(s.p95 < DEPTH_P95_MAX, "p95 relative depth difference %.4g >= %.4g", s.p95, DEPTH_P95_MAX);
    CHECK(hit_share >= HIT_AGREEMENT_MIN, "hit/miss agreement %.4f%% < %.2f%%", 100.0 * hit_share,
          100.0 * HIT_AGREEMENT_MIN);
    CHECK(id_share >= ID_AGREEMENT_MIN, "instance agreement %.4f%% < %.2f%%", 100.0 * id_share,
          100.0 * ID_AGREEMENT_MIN);
    CHECK(messages == 0, "%d validation message(s)", messages);
    return 0;
}

static int test_depth_balloon(void) { return depth_embree("content/balloon.gltf", 90); }
static int test_depth_cubes(void) { return depth_embree("content/cubes.gltf", 90); }
static int test_depth_arena(void) { return depth_embree("content/arena.gltf", 90); }
/* Skinned wings, a morphing tail, a moving camera (docs/content.md). */
static int test_depth_bird(void) { return depth_embree("content/bird.gltf", 90); }

/* ------------------------------------------------------------------------- */
/* motion_cubes                                                              */
/* ------------------------------------------------------------------------- */

#define MOTION_MAX_ERROR 0.25 /* pixels */

typedef struct motion_report {
    double *moving, *still;       /* per-pixel error: max over the prev and next vectors */
    size_t n_moving, n_still;
    /* Mean motion over the flying cube's interior: G-buffer and analytic. */
    double gb_prev[2], gb_next[2], an_prev[2], an_next[2];
    size_t n_flying;
} motion_report;

static bool matrices_equal(const float *a, const float *b)
{
    for (int k = 0; k < 16; k++)
        if (a[k] != b[k])
            return false;
    return true;
}

/* Interior pixel: its 8 neighbours exist and carry the same id (1 px from
 * any silhouette or id boundary). */
static bool interior(const uint32_t *ids, uint32_t w, uint32_t h, uint32_t x, uint32_t y)
{
    if (x == 0 || y == 0 || x + 1 >= w || y + 1 >= h)
        return false;
    uint32_t id = ids[(size_t)y * w + x];
    for (uint32_t ny = y - 1; ny <= y + 1; ny++)
        for (uint32_t nx = x - 1; nx <= x + 1; nx++)
            if (ids[(size_t)ny * w + nx] != id)
                return false;
    return true;
}

/* World point `p` of `node` at the frame's time, carried rigidly to another
 * time (world_to = that time's world matrix) and projected with that time's camera. */
static bool carry(const double inv_world_now[16], const float *world_to, const vg_camera *cam_to,
                  const double p[3], uint32_t w, uint32_t h, double out[2])
{
    double local[4], to[16], moved[4];
    rt_mat4_mul_point(inv_world_now, p, local);
    rt_mat4_to_double(world_to, to);
    double l3[3] = {local[0] / local[3], local[1] / local[3], local[2] / local[3]};
    rt_mat4_mul_point(to, l3, moved);
    double m3[3] = {moved[0] / moved[3], moved[1] / moved[3], moved[2] / moved[3]};
    return rt_project(cam_to->view_proj, m3, w, h, out);
}

static int motion_frame(rt_ctx *c, long index, int flying_node, motion_report *rep)
{
    vg_status st = frame_render(c->frame, index);
    CHECK(st == VG_OK, "frame_render(%ld): %s", index, vg_status_text(st));
    const frame_outputs *o = frame_get_outputs(c->frame);
    const frame_times *ft = frame_get_times(c->frame);
    const vg_camera *cam = frame_get_camera(c->frame);
    uint32_t w = c->width, h = c->height;
    float aspect = (float)w / (float)h;

    scene_state now, prev, next;
    CHECK(scene_state_init(c->scene, &now) == VG_OK && scene_state_init(c->scene, &prev) == VG_OK &&
          scene_state_init(c->scene, &next) == VG_OK, "scene_state_init");
    scene_evaluate(c->scene, (float)ft->t, &now);
    scene_evaluate(c->scene, (float)ft->t_prev, &prev);
    scene_evaluate(c->scene, (float)ft->t_next, &next);
    vg_camera cam_prev, cam_next;
    scene_camera_resolve(c->scene, &prev, 0, aspect, &cam_prev);
    scene_camera_resolve(c->scene, &next, 0, aspect, &cam_next);

    double vp[16], inv_vp[16];
    rt_mat4_to_double(cam->view_proj, vp);
    CHECK(rt_mat4_invert(vp, inv_vp), "camera view_proj is singular");

    double worst = -1.0, worst_gb[4] = {0}, worst_an[4] = {0};
    uint32_t worst_x = 0, worst_y = 0;
    size_t n_moving0 = rep->n_moving, n_still0 = rep->n_still;
    for (uint32_t y = 0; y < h; y++) {
        for (uint32_t x = 0; x < w; x++) {
            size_t i = (size_t)y * w + x;
            uint32_t id = o->ids[i];
            if (!id || !interior(o->ids, w, h, x, y))
                continue;
            CHECK(id <= (uint32_t)c->scene->instance_count && c->scene->instances[id - 1].id == id,
                  "pixel %u,%u: id %u names no instance", x, y, id);
            int node = c->scene->instances[id - 1].node;
            const float *wn = now.world + 16 * (size_t)node;
            double world_now[16], inv_world[16];
            rt_mat4_to_double(wn, world_now);
            CHECK(rt_mat4_invert(world_now, inv_world), "node %d world matrix is singular", node);

            /* The surface point under the pixel centre, at the G-buffer's depth. */
            rt_ray r;
            rt_pixel_ray(inv_vp, w, h, x + 0.5, y + 0.5, &r);
            double along = 0.0;
            for (int k = 0; k < 3; k++)
                along += r.dir[k] * cam->forward[k];
            double s = (o->depth[i] - rt_linear_depth(cam, r.org)) / along, p[3];
            for (int k = 0; k < 3; k++)
                p[k] = r.org[k] + s * r.dir[k];

            double to_prev[2], to_next[2];
            CHECK(carry(inv_world, prev.world + 16 * (size_t)node, &cam_prev, p, w, h, to_prev) &&
                  carry(inv_world, next.world + 16 * (size_t)node, &cam_next, p, w, h, to_next),
                  "pixel %u,%u: surface point behind a keyframe camera", x, y);
            double an[4] = {to_prev[0] - (x + 0.5), to_prev[1] - (y + 0.5), to_next[0] - (x + 0.5),
                            to_next[1] - (y + 0.5)};
            const float *gb = o->motion + 4 * i;
            double e_prev = hypot(gb[0] - an[0], gb[1] - an[1]), e_next = hypot(gb[2] - an[2], gb[3] - an[3]);
            double err = fmax(e_prev, e_next);
            if (!(err == err))
                err = INFINITY; /* a NaN in the G-buffer fails as an infinite error */

            bool moving = !matrices_equal(wn, prev.world + 16 * (size_t)node) ||
                          !matrices_equal(wn, next.world + 16 * (size_t)node);
            if (moving)
                rep->moving[rep->n_moving++] = err;
            else
                rep->still[rep->n_still++] = err;
            if (err > worst) {
                worst = err, worst_x = x, worst_y = y;
                for (int k = 0; k < 4; k++)
                    worst_gb[k] = gb[k], worst_an[k] = an[k];
            }
            if (node == flying_node) {
                rep->n_flying++;
                for (int k = 0; k < 2; k++) {
                    rep->gb_prev[k] += gb[k], rep->gb_next[k] += gb[2 + k];
                    rep->an_prev[k] += an[k], rep->an_next[k] += an[2 + k];
                }
            }
        }
    }
    printf("frame %ld (t %.4f, keyframes %ld/%ld): %zu moving + %zu static interior pixels; worst %.4f px at "
           "%u,%u: gbuffer prev (%.3f, %.3f) next (%.3f, %.3f), analytic prev (%.3f, %.3f) next (%.3f, %.3f)\n",
           index, ft->t, ft->prev_key, ft->next_key, rep->n_moving - n_moving0, rep->n_still - n_still0, worst,
           worst_x, worst_y, worst_gb[0], worst_gb[1], worst_gb[2], worst_gb[3], worst_an[0], worst_an[1],
           worst_an[2], worst_an[3]);
    scene_state_free(&now);
    scene_state_free(&prev);
    scene_state_free(&next);
    return 0;
}

static double cosine(const double a[2], const double b[2])
{
    return (a[0] * b[0] + a[1] * b[1]) / (hypot(a[0], a[1]) * hypot(b[0], b[1]));
}

/* One frame's flying-cube means: non-zero, in the analytic direction, and in
 * the direction the scene description predicts (docs/content.md: the cube
 * recedes leftwards and, seen from above it, rises towards the horizon, i.e.
 * up the image = towards smaller pixel y in Vulkan's y-down convention). */
static int check_flying(const motion_report *r, long index)
{
    CHECK(r->n_flying >= 20, "frame %ld: only %zu interior pixels on the flying cube", index, r->n_flying);
    double n = (double)r->n_flying;
    double gp[2] = {r->gb_prev[0] / n, r->gb_prev[1] / n}, gn[2] = {r->gb_next[0] / n, r->gb_next[1] / n};
    double ap[2] = {r->an_prev[0] / n, r->an_prev[1] / n}, an[2] = {r->an_next[0] / n, r->an_next[1] / n};
    printf("  frame %ld flying cube (%zu px) mean motion: gbuffer prev (%.3f, %.3f) next (%.3f, %.3f); "
           "analytic prev (%.3f, %.3f) next (%.3f, %.3f)\n", index, r->n_flying, gp[0], gp[1], gn[0], gn[1],
           ap[0], ap[1], an[0], an[1]);
    CHECK(hypot(gp[0], gp[1]) > 0.5 && hypot(gn[0], gn[1]) > 0.5,
          "frame %ld: flying cube barely moves in the G-buffer: |prev| %.3f |next| %.3f px", index,
          hypot(gp[0], gp[1]), hypot(gn[0], gn[1]));
    CHECK(cosine(gp, ap) > 0.99 && cosine(gn, an) > 0.99,
          "frame %ld: flying cube motion direction differs from the analytic one: cos prev %.4f next %.4f",
          index, cosine(gp, ap), cosine(gn, an));
    CHECK(gn[0] < 0.0 && gn[1] < 0.0 && gp[0] > 0.0 && gp[1] > 0.0,
          "frame %ld: expected the cube to move left and up the image towards the next keyframe "
          "(next x<0, y<0; prev x>0, y>0): next (%.3f, %.3f) prev (%.3f, %.3f)", index, gn[0], gn[1], gp[0], gp[1]);
    return 0;
}

static int test_motion_cubes(void)
{
    rt_ctx c;
    if (rt_open(&c, "content/cubes.gltf", TEST_W, TEST_H))
        return 1;
    int flying = -1;
    for (int n = 0; n < c.scene->node_count; n++)
        if (strcmp(c.scene->nodes[n].name, "flying_cube") == 0)
            flying = n;
    CHECK(flying >= 0, "content/cubes.gltf has no node named flying_cube");

    /* Between keyframes (15, 95) and on keyframes (20, 100), near and far. */
    static const long frames[] = {15, 20, 95, 100};
    enum { FRAMES = sizeof frames / sizeof frames[0] };
    size_t px = (size_t)TEST_W * TEST_H;
    motion_report rep = {.moving = malloc(FRAMES * px * sizeof(double)), .still = malloc(FRAMES * px * sizeof(double))};
    CHECK(rep.moving && rep.still, "out of memory");
    for (int k = 0; k < FRAMES; k++) {
        motion_report one = {.moving = rep.moving + rep.n_moving, .still = rep.still + rep.n_still};
        if (motion_frame(&c, frames[k], flying, &one) || check_flying(&one, frames[k]))
            return 1;
        rep.n_moving += one.n_moving;
        rep.n_still += one.n_still;
    }
    rt_stats m = rt_stats_of(rep.moving, rep.n_moving), s = rt_stats_of(rep.still, rep.n_still);
    printf("motion error, moving objects: %zu px, median %.4g  p99 %.4g  max %.4g px\n", m.n, m.median, m.p99, m.max);
    printf("motion error, static objects: %zu px, median %.4g  p99 %.4g  max %.4g px\n", s.n, s.median, s.p99, s.max);
    free(rep.moving);
    free(rep.still);
    int messages = rt_close(&c);

    CHECK(m.n >= 100 && s.n >= 10000, "too few interior pixels: %zu moving, %zu static", m.n, s.n);
    CHECK(m.max < MOTION_MAX_ERROR, "moving objects: max motion error %.4f px >= %.2f (median %.4f, p99 %.4f)",
          m.max, MOTION_MAX_ERROR, m.median, m.p99);
    CHECK(s.max < MOTION_MAX_ERROR, "static objects: max motion error %.4f px >= %.2f (median %.4f, p99 %.4f)",
          s.max, MOTION_MAX_ERROR, s.median, s.p99);
    CHECK(messages == 0, "%d validation message(s)", messages);
    return 0;
}

/* ------------------------------------------------------------------------- */
/* deterministic                                                             */
/* ------------------------------------------------------------------------- */

#define DET_W 320
#define DET_H 180

/* Index of the first differing element of size `elem`, or -1. */
static long first_difference(const void *a, const void *b, size_t count, size_t elem)
{
    const uint8_t *x = a, *y = b;
    for (size_t i = 0; i < count; i++)
        if (memcmp(x + i * elem, y + i * elem, elem) != 0)
            return (long)i;
    return -1;
}

static int test_deterministic(void)
{
    rt_ctx c;
    if (rt_open(&c, "content/balloon.gltf", DET_W, DET_H))
        return 1;
    frame *other = NULL;
    if (rt_open_frame(&c, &other))
        return 1;
    static const long frames[] = {60, 95, 100};
    enum { FRAMES = sizeof frames / sizeof frames[0] };
    size_t px = (size_t)DET_W * DET_H;
    /* Per pixel: colour 4 + depth 4 + id 4 + motion 16 bytes, as the readback lays them out. */
    static const size_t bytes[4] = {4, 4, 4, 16};
    static const char *names[4] = {"color", "depth", "ids", "motion"};
    uint8_t *first = malloc(FRAMES * px * 28);
    CHECK(first, "out of memory");

    for (int k = 0; k < FRAMES; k++) {
        CHECK(frame_render(c.frame, frames[k]) == VG_OK, "frame_render(%ld)", frames[k]);
        const frame_outputs *o = frame_get_outputs(c.frame);
        const void *src[4] = {o->color, o->depth, o->ids, o->motion};
        uint8_t *dst = first + (size_t)k * px * 28;
        for (int b = 0; b < 4; b++)
            memcpy(dst, src[b], px * bytes[b]), dst += px * bytes[b];
    }
    int different = 0;
    for (int k = 0; k < FRAMES; k++) {
        CHECK(frame_render(other, frames[k]) == VG_OK, "frame_render(%ld) (second frame object)", frames[k]);
        const frame_outputs *o = frame_get_outputs(other);
        const void *now[4] = {o->color, o->depth, o->ids, o->motion};
        const uint8_t *was = first + (size_t)k * px * 28;
        for (int b = 0; b < 4; b++) {
            long i = first_difference(was, now[b], px, bytes[b]);
            if (i >= 0) {
                long n = 0;
                for (size_t j = (size_t)i; j < px; j++)
                    n += memcmp(was + j * bytes[b], (const uint8_t *)now[b] + j * bytes[b], bytes[b]) != 0;
                fprintf(stderr, "frame %ld %s: %ld of %zu pixels differ, first at %ld,%ld\n", frames[k], names[b], n,
                        px, i % DET_W, i / DET_W);
                different++;
            } else {
                printf("frame %ld %s: identical (%zu bytes)\n", frames[k], names[b], px * bytes[b]);
            }
            was += px * bytes[b];
        }
    }
    free(first);
    frame_destroy(other);
    int messages = rt_close(&c);
    CHECK(different == 0, "%d output image(s) differ between two renders of the same frames", different);
    CHECK(messages == 0, "%d validation message(s)", messages);
    return 0;
}

/* ------------------------------------------------------------------------- */

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"depth_embree.balloon", test_depth_balloon},
        {"depth_embree.cubes", test_depth_cubes},
        {"depth_embree.arena", test_depth_arena},
        {"depth_embree.bird", test_depth_bird},
        {"motion_cubes", test_motion_cubes},
        {"deterministic", test_deterministic},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
