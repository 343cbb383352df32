/* vergence — the game's rules, the scene pose hook, the simulated observer
 * and the study CSV log (issue 6). */
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../test.h"
#include "core/stats.h"
#include "frame/frame.h"
#include "frame/warp_metrics.h"
#include "rules/game.h"
#include "observer/observer.h"
#include "observer/ball_measure.h"
#include "observer/observer_engine.h"
#include "study/pref_trial.h"
#include "study/study_log.h"

#define ARENA "content/arena.gltf"

static int load_arena(scene **s, vg_camera *cam)
{
    if (scene_load(ARENA, s) != VG_OK)
        return 1;
    scene_state st;
    if (scene_state_init(*s, &st) != VG_OK)
        return 1;
    scene_evaluate(*s, 0.0f, &st);
    scene_camera_resolve(*s, &st, 0, 16.0f / 9.0f, cam);
    scene_state_free(&st);
    return 0;
}

/* ------------------------------------------------------------------------- */
/* Rules                                                                     */
/* ------------------------------------------------------------------------- */

/* A ray through a point's own projection passes through it; a point off the
 * ray by a known distance reports that distance (the paper's error). */
static int click_error(void)
{
    scene *s;
    vg_camera cam;
    CHECK(!load_arena(&s, &cam), "arena");
    double p[3] = {2.5, 0.0, -20.0}, u, v;
    double z = game_project(&cam, p, &u, &v);
    CHECK(z > 19 && z < 21, "depth %g", z);
    double e = game_click_error(&cam, u, v, p);
    CHECK(e < 1e-6, "error through the point itself: %g m", e);
    double o[3], d[3];
    game_ray(&cam, u, v, o, d);
    /* Move the target sideways, perpendicular to the ray, by 0.75 m. */
    double side[3] = {d[2], 0.0, -d[0]}, len = sqrt(side[0] * side[0] + side[2] * side[2]);
    double q[3] = {p[0] + 0.75 * side[0] / len, p[1], p[2] + 0.75 * side[2] / len};
    e = game_click_error(&cam, u, v, q);
    CHECK(fabs(e - 0.75) < 1e-6, "error %g m, want 0.75", e);
    /* Projection agrees with the camera's own view-projection matrix. */
    const float *m = cam.view_proj;
    double cx = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12], cy = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
    double cw = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
    CHECK(fabs(0.5 + 0.5 * cx / cw - u) < 1e-5 && fabs(0.5 + 0.5 * cy / cw - v) < 1e-5,
          "u %g v %g vs matrix %g %g", u, v, 0.5 + 0.5 * cx / cw, 0.5 + 0.5 * cy / cw);
    scene_destroy(s);
    return 0;
}

/* Every kind of throw lands on the ground at flight_s, in view all along,
 * moving the way its direction says; the same stream gives the same throw. */
static int throws(void)
{
    scene *s;
    vg_camera cam;
    CHECK(!load_arena(&s, &cam), "arena");
    for (int c = 0; c < 4; c++)
        for (int i = 0; i < 50; i++) {
            game_throw_desc td = {.path = (game_path)(GAME_PATH_STRAIGHT + c % 2),
                                  .direction = (game_direction)(GAME_DIR_NEAR_TO_FAR + c / 2)};
            game_rng r = game_rng_make(42, (uint64_t)(c * 100 + i)), r2 = r;
            game_throw a, b;
            game_throw_make(&td, &cam, &r, &a);
            game_throw_make(&td, &cam, &r2, &b);
            CHECK(!memcmp(&a, &b, sizeof a), "throw %d/%d differs between two draws of one stream", c, i);
            double p[3];
            game_throw_position(&a, a.flight_s, p);
            CHECK(fabs(p[1] - GAME_BALL_RADIUS) < 1e-9, "lands at height %g", p[1]);
            CHECK(fabs(a.ground[1]) < 1e-12, "ground spot height %g", a.ground[1]);
            double u, v, z0 = game_project(&cam, a.start, &u, &v), z1 = game_project(&cam, a.landing, &u, &v);
            CHECK(c / 2 == 0 ? z1 > z0 + 8 : z1 < z0 - 8, "direction %s: depth %g -> %g",
                  game_direction_names[a.direction], z0, z1);
            for (int k = 0; k <= 20; k++) {
                game_throw_position(&a, a.flight_s * k / 20, p);
                game_project(&cam, p, &u, &v);
                CHECK(u > 0 && u < 1 && v > 0 && v < 1 && p[1] >= GAME_BALL_RADIUS - 1e-9,
                      "throw %d/%d leaves the view or the field at t %g: u %g v %g y %g", c, i,
                      a.flight_s * k / 20, u, v, p[1]);
            }
        }
    scene_destroy(s);
    return 0;
}

/* Blocks of 12 hold every cell once; a trial's cell does not depend on the
 * number of trials asked for (resume, extension). */
static int schedule(void)
{
    int a[120], b[50];
    game_schedule(7, GAME_HIT_CELLS, 120, a);
    game_schedule(7, GAME_HIT_CELLS, 50, b);
    CHECK(!memcmp(a, b, sizeof b), "the first 50 cells depend on the trial count");
    for (int blk = 0; blk < 10; blk++) {
        int seen[GAME_HIT_CELLS] = {0};
        for (int i = 0; i < GAME_HIT_CELLS; i++)
            seen[a[blk * GAME_HIT_CELLS + i]]++;
        for (int c = 0; c < GAME_HIT_CELLS; c++)
            CHECK(seen[c] == 1, "block %d holds cell %d %d times", blk, c, seen[c]);
    }
    int other[120];
    game_schedule(8, GAME_HIT_CELLS, 120, other);
    CHECK(memcmp(a, other, sizeof a), "seeds 7 and 8 give the same order");
    game_cell c = game_hit_cell(11);
    CHECK(c.condition == 2 && c.direction == GAME_DIR_FAR_TO_NEAR && c.path == GAME_PATH_BALLISTIC, "cell 11");
    return 0;
}

/* Window clicks land on the eye image for every layout. */
static int click_mapping(void)
{
    double u, v;
    /* anaglyph 320x180 eyes in a 640x360 window: the picture fills it */
    CHECK(game_click_to_image(FRAME_COMPOSE_ANAGLYPH, 320, 180, 640, 360, 0.25, 0.5, &u, &v) &&
          fabs(u - 0.25) < 1e-9 && fabs(v - 0.5) < 1e-9, "anaglyph u %g v %g", u, v);
    /* side by side: both halves are the same place */
    CHECK(game_click_to_image(FRAME_COMPOSE_SBS, 320, 180, 640, 180, 0.75, 0.5, &u, &v) && fabs(u - 0.5) < 1e-9,
          "sbs right half u %g", u);
    CHECK(game_click_to_image(FRAME_COMPOSE_SBS_HALF, 320, 180, 320, 180, 0.625, 0.5, &u, &v) &&
          fabs(u - 0.25) < 1e-9, "sbs-half u %g", u);
    CHECK(game_click_to_image(FRAME_COMPOSE_TB, 320, 180, 320, 360, 0.5, 0.75, &u, &v) && fabs(v - 0.5) < 1e-9,
          "tb v %g", v);
    CHECK(game_click_to_image(FRAME_COMPOSE_TB_HALF, 320, 180, 320, 180, 0.5, 0.75, &u, &v) && fabs(v - 0.5) < 1e-9,
          "tb-half v %g", v);
    CHECK(game_click_to_image(FRAME_COMPOSE_CROSS_EYED, 320, 180, 640, 180, 0.25, 0.5, &u, &v) &&
              fabs(u - 0.5) < 1e-9, "cross-eyed left half u %g", u);
    /* frame packing: 180 + 8 blank + 180 rows; the right eye's middle row,
     * and a click on the blank rows between the eyes misses */
    CHECK(game_click_to_image(FRAME_COMPOSE_FRAME_PACKING, 320, 180, 320, 368, 0.5, (188 + 90) / 368.0, &u, &v) &&
              fabs(v - 0.5) < 1e-9, "frame packing v %g", v);
    CHECK(!game_click_to_image(FRAME_COMPOSE_FRAME_PACKING, 320, 180, 320, 368, 0.5, 184 / 368.0, &u, &v),
          "a click on frame packing's blank rows");
    /* letterbox: a 16:9 picture in a square window has bars above and below */
    CHECK(!game_click_to_image(FRAME_COMPOSE_ANAGLYPH, 320, 180, 400, 400, 0.5, 0.1, &u, &v), "click on a bar");
    /* 400 x 225 at y 87 (integer placement, as the blit): row 200 is 113 / 225 down */
    CHECK(game_click_to_image(FRAME_COMPOSE_ANAGLYPH, 320, 180, 400, 400, 0.5, 0.5, &u, &v) &&
          fabs(v - 113.0 / 225.0) < 1e-9, "letterboxed centre v %g", v);
    return 0;
}

/* ------------------------------------------------------------------------- */
/* The scene pose hook                                                       */
/* ------------------------------------------------------------------------- */

static void hook(void *user, const scene *s, float t, float *local)
{
    (void)s;
    int ball = *(int *)user;
    local[ball * 10 + 0] = 1.0f + t;
    local[ball * 10 + 1] = 2.0f;
    local[ball * 10 + 2] = -7.0f;
}

static int pose_hook(void)
{
    scene *s;
    vg_camera cam;
    CHECK(!load_arena(&s, &cam), "arena");
    int ball = scene_find_node(s, "ball");
    CHECK(ball >= 0, "no ball node");
    CHECK(scene_find_node(s, "no such node") == -1, "found a node that is not there");
    scene_state st;
    CHECK(scene_state_init(s, &st) == VG_OK, "state");
    scene_set_pose_hook(s, hook, &ball);
    scene_evaluate(s, 0.5f, &st);
    const float *w = st.world + (size_t)ball * 16;
    CHECK(fabsf(w[12] - 1.5f) < 1e-6f && fabsf(w[13] - 2.0f) < 1e-6f && fabsf(w[14] + 7.0f) < 1e-6f,
          "ball at (%g %g %g), want (1.5 2 -7)", w[12], w[13], w[14]);
    scene_set_pose_hook(s, NULL, NULL);
    scene_evaluate(s, 0.0f, &st);
    CHECK(fabsf(w[14] + 7.0f) > 0.5f, "the hook still applies after removal (z %g)", w[14]);
    scene_state_free(&st);
    scene_destroy(s);
    return 0;
}

/* ------------------------------------------------------------------------- */
/* Observer                                                                  */
/* ------------------------------------------------------------------------- */

static int make_observer(scene **s, observer **o, double k, bool size_cue)
{
    vg_camera cam;
    if (load_arena(s, &cam))
        return 1;
    return observer_create(&(observer_desc){.view = {.scene = *s, .moving_node = scene_find_node(*s, "ball"),
                                                     .preset = DISP_PRESET_STUDY},
                                            .weber_k = k, .size_cue = size_cue}, o) != VG_OK;
}

/* Without noise and with the original disparity the observer's decoding is
 * exact, so it hits every throw (straight and ballistic, both directions),
 * with disparity alone and with disparity and size. */
static int observer_exact(void)
{
    for (int cues = 0; cues < 2; cues++) {
        scene *s;
        observer *o;
        CHECK(!make_observer(&s, &o, -1, cues), "observer");
        for (int i = 0; i < 40; i++) {
            game_throw th;
            game_rng r = game_rng_make(1, (uint64_t)i), n = game_rng_make(2, (uint64_t)i);
            game_throw_make(&(game_throw_desc){.path = (game_path)(1 + i % 2), .direction = (game_direction)(1 + (i / 2) % 2)},
                            observer_camera(o), &r, &th);
            observer_result res;
            CHECK(observer_play(o, &th, FRAME_MODE_ORIGINAL, NULL, &n, &res) == VG_OK, "play");
            CHECK(res.error_m < 0.01, "throw %d (%s, %s, %s): error %g m without noise under g", i,
                  game_direction_names[th.direction], game_path_names[th.path], cues ? "two cues" : "disparity",
                  res.error_m);
        }
        observer_destroy(o);
        scene_destroy(s);
    }
    return 0;
}

/* The two-cue observer's size cue is not manipulated (h moves the ball in
 * depth, not its image size), so under h its clicks land nearer the truth
 * than the disparity-only observer's, and further than under g. */
static int observer_two_cue(void)
{
    double sum[2][4] = {{0}};
    int n = 24;
    for (int cues = 0; cues < 2; cues++) {
        scene *s;
        observer *o;
        CHECK(!make_observer(&s, &o, -1, cues), "observer");
        for (int i = 0; i < n; i++) {
            game_throw th;
            game_rng r = game_rng_make(5, (uint64_t)i), nz = game_rng_make(9, (uint64_t)i);
            game_throw_make(&(game_throw_desc){.path = (game_path)(1 + i % 2),
                                               .direction = (game_direction)(1 + (i / 2) % 2)},
                            observer_camera(o), &r, &th);
            for (int m = FRAME_MODE_ORIGINAL; m <= FRAME_MODE_MANIPULATED; m++) {
                observer_result res;
                CHECK(observer_play(o, &th, (frame_mode)m, NULL, &nz, &res) == VG_OK, "play");
                sum[cues][m] += res.error_m / n;
            }
        }
        observer_destroy(o);
        scene_destroy(s);
    }
    printf("mean error under h, no noise: disparity %.3f m, two cues %.3f m\n", sum[0][2], sum[1][2]);
    CHECK(sum[1][FRAME_MODE_MANIPULATED] < 0.8 * sum[0][FRAME_MODE_MANIPULATED],
          "two cues %.3f m, disparity %.3f m under h", sum[1][2], sum[0][2]);
    CHECK(sum[1][FRAME_MODE_MANIPULATED] > sum[1][FRAME_MODE_ORIGINAL] + 0.05, "two cues: h %.3f m, g %.3f m",
          sum[1][2], sum[1][1]);
    return 0;
}

/* The same seed gives the same clicks; a disparity-only observer errs more
 * under h than under g (the compressed depth moves the ball wrongly). */
static int observer_conditions(void)
{
    scene *s;
    observer *o;
    CHECK(!make_observer(&s, &o, 0, false), "observer");
    double sum[4] = {0};
    int n = 48;
    for (int i = 0; i < n; i++) {
        game_throw th;
        game_rng r = game_rng_make(5, (uint64_t)i);
        game_throw_make(&(game_throw_desc){.path = (game_path)(1 + i % 2), .direction = (game_direction)(1 + (i / 2) % 2)},
                        observer_camera(o), &r, &th);
        for (int m = FRAME_MODE_ORIGINAL; m <= FRAME_MODE_OPTIMIZED; m++) {
            game_rng a = game_rng_make(9, (uint64_t)i), b = a;
            observer_result ra, rb;
            CHECK(observer_play(o, &th, (frame_mode)m, NULL, &a, &ra) == VG_OK, "play");
            CHECK(observer_play(o, &th, (frame_mode)m, NULL, &b, &rb) == VG_OK, "play");
            CHECK(ra.click_u == rb.click_u && ra.click_v == rb.click_v, "trial %d mode %d not deterministic", i, m);
            sum[m] += ra.error_m;
        }
    }
    printf("mean error: original %.3f m, manipulated %.3f m, optimized %.3f m\n", sum[1] / n, sum[2] / n, sum[3] / n);
    CHECK(sum[FRAME_MODE_MANIPULATED] > 2.0 * sum[FRAME_MODE_ORIGINAL], "manipulated %.3f m, original %.3f m",
          sum[2] / n, sum[1] / n);
    observer_destroy(o);
    scene_destroy(s);
    return 0;
}

/* ------------------------------------------------------------------------- */
/* CSV log                                                                   */
/* ------------------------------------------------------------------------- */

static const char *const k_cols[] = {"participant", "trial", "value"};

static int csv_log(void)
{
    char path[] = "/tmp/vergence_test_log_XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0, "temp file");
    close(fd);
    unlink(path);
    study_log_desc d = {.path = path, .kind = "test", .columns = k_cols, .column_count = 3, .participant = "p1"};
    study_log l;
    CHECK(study_log_open(&d, &l) == VG_OK && l.rows == 0, "create");
    CHECK(study_log_append(&l, (const char *const[]){"p1", "0", "1.5"}) == VG_OK, "append");
    CHECK(study_log_append(&l, (const char *const[]){"p1", "1", "2.5"}) == VG_OK, "append");
    study_log_close(&l);
    /* Again without resume: refused. Another participant: refused. */
    CHECK(study_log_open(&d, &l) == VG_ERR_ARG, "reopened without resume");
    d.resume = true;
    d.participant = "p2";
    CHECK(study_log_open(&d, &l) == VG_ERR_ARG, "another participant's file accepted");
    d.participant = "p1";
    CHECK(study_log_open(&d, &l) == VG_OK && l.rows == 2, "resume: %d rows", l.rows);
    CHECK(!strcmp(study_log_cell(&l, 1, 2), "2.5"), "cell (1, 2) = %s", study_log_cell(&l, 1, 2));
    CHECK(study_log_append(&l, (const char *const[]){"p1", "2", "3.5"}) == VG_OK && l.rows == 3, "append");
    study_log_close(&l);
    /* A torn last line and a wrong field count are corrupt. */
    FILE *f = fopen(path, "a");
    fputs("p1,3,4", f);
    fclose(f);
    CHECK(study_log_open(&d, &l) == VG_ERR_FORMAT, "torn line accepted");
    f = fopen(path, "a");
    fputs(",5\n", f);
    fclose(f);
    CHECK(study_log_open(&d, &l) == VG_ERR_FORMAT, "4 fields accepted");
    unlink(path);
    /* Ids that would break the CSV are refused. */
    CHECK(!study_participant_valid("a,b") && !study_participant_valid("") && study_participant_valid("P-07_a.b"),
          "participant id check");
    return 0;
}

/* ------------------------------------------------------------------------- */
/* The preference study's clips                                              */
/* ------------------------------------------------------------------------- */

typedef struct clip_f {
    float **f;
    size_t np;
} clip_f;

static vg_status keep_f(void *user, int k, const frame_outputs *o, bool *stop)
{
    clip_f *c = user;
    (void)stop;
    if (!o->f || !(c->f[k] = malloc(c->np * sizeof(float))))
        return VG_ERR_NOMEM;
    memcpy(c->f[k], o->f, c->np * sizeof(float));
    return VG_OK;
}

/* A clip holds every 2nd frame (issue 13): its optimized version, at the
 * study's CPU defaults (320 x 180 panels, the study preset, the warp at
 * 0.5 px), shows at each of its frames the f of rendering every frame. */
static int pref_clip(void)
{
    gpu *g;
    scene *s;
    frame *f;
    CHECK(gpu_create(&(gpu_desc){0}, &g) == VG_OK, "gpu_create");
    CHECK(scene_load("content/balloon.gltf", &s) == VG_OK, "scene_load");
    frame_desc fd = pref_clip_frame_desc(g, &(pref_clip_desc){.width = 320, .height = 180,
                                                              .mode = FRAME_MODE_OPTIMIZED,
                                                              .compose = FRAME_COMPOSE_ANAGLYPH});
    int n = pref_clip_frames(s);
    clip_f c = {calloc((size_t)n, sizeof(float *)), (size_t)fd.width * fd.height};
    CHECK(c.f, "memory");
    CHECK(pref_clip_render(g, s, &fd, keep_f, &c) == VG_OK, "the clip renders");
    fd.maps_only = true; /* the reference: f of every frame (the eyes do not change it) */
    CHECK(frame_create(g, s, &fd, &f) == VG_OK, "frame_create");
    double worst = 0;
    long worst_at = -1;
    for (long t = 0; t <= (long)(n - 1) * PREF_CLIP_STEP; t++) {
        CHECK(frame_render(f, t) == VG_OK, "frame %ld", t);
        if (t % PREF_CLIP_STEP)
            continue;
        const float *ref = frame_get_outputs(f)->f, *got = c.f[t / PREF_CLIP_STEP];
        for (size_t p = 0; p < c.np; p++)
            if (fabs((double)got[p] - ref[p]) > worst) {
                worst = fabs((double)got[p] - ref[p]);
                worst_at = t;
            }
    }
    frame_destroy(f);
    for (int k = 0; k < n; k++)
        free(c.f[k]);
    free(c.f);
    scene_destroy(s);
    gpu_destroy(g);
    int v = gpu_validation_messages();
    printf("preference clip of balloon: %d frames, one every %d; max |f - f(every frame)| %.3g arcmin (frame %ld); "
           "%d validation messages\n", n, PREF_CLIP_STEP, worst, worst_at, v);
    CHECK(worst <= 0.05, "the clip's f is %.3g arcmin off (bound 0.05)", worst);
    CHECK(v == 0, "%d validation messages", v);
    return 0;
}

/* The two versions a preference trial shows side by side must be equally
 * clean: a participant who sees artifacts on one side only can answer
 * without judging motion. For each scene and saliency cell, the h and the f
 * clip at the study's CPU defaults (320 x 180 panels, the study preset, the
 * warp at 0.5 px), their first PREF_QUALITY_FRAMES frames: cracks (warp
 * metrics) at most PREF_CRACKS pixels per clip and eye, the p99 warp
 * error of either within PREF_P99_GAP px of the other's, and speckles
 * (which texture detail seen from an eye's viewpoint makes too: a few per
 * frame in the original mode) within PREF_SPECKLE_GAP of each other
 * (relative to the larger count, plus PREF_SPECKLE_SLACK pixels). */
#define PREF_QUALITY_FRAMES 36
#define PREF_CRACKS 2
#define PREF_P99_GAP 0.25
#define PREF_SPECKLE_GAP 0.25
#define PREF_SPECKLE_SLACK 36

static vg_status add_metrics(void *user, int k, const frame_outputs *o, bool *stop)
{
    warp_metrics *m = user;
    *stop = k + 1 >= PREF_QUALITY_FRAMES;
    return warp_metrics_add(m, o, 320, 180);
}

static int pref_equal_quality(void)
{
    gpu *g;
    CHECK(gpu_create(&(gpu_desc){0}, &g) == VG_OK, "gpu_create");
    for (int cell = 0; cell < PREF_SCENES * 2; cell++) {
        int sc = cell / 2, variant = cell % 2;
        char path[1024];
        scene *s;
        CHECK(pref_scene_path("content/arena.gltf", sc, path, sizeof path) == VG_OK && scene_load(path, &s) == VG_OK,
              "scene %d", sc);
        pref_saliency_apply(s, pref_moving_node(s), variant);
        warp_metrics m[2];
        memset(m, 0, sizeof m);
        for (int v = 0; v < 2; v++) {
            frame_desc fd = pref_clip_frame_desc(
                g, &(pref_clip_desc){.width = 320, .height = 180,
                                     .mode = v ? FRAME_MODE_OPTIMIZED : FRAME_MODE_MANIPULATED,
                                     .compose = FRAME_COMPOSE_ANAGLYPH});
            fd.measure = true;
            CHECK(pref_clip_render(g, s, &fd, add_metrics, &m[v]) == VG_OK, "%s clip", path);
            warp_metrics_finish(&m[v]);
        }
        printf("%-8s saliency %-6s  h: cracks %llu px, speckles %4llu px, warp p99 %.3f px  |  "
               "f: cracks %llu px, speckles %4llu px, warp p99 %.3f px\n",
               pref_scene_names[sc], pref_saliency_names[variant], (unsigned long long)m[0].crack_pixels,
               (unsigned long long)m[0].speckle_pixels, m[0].error_p99, (unsigned long long)m[1].crack_pixels,
               (unsigned long long)m[1].speckle_pixels, m[1].error_p99);
        double sh = (double)m[0].speckle_pixels, sf = (double)m[1].speckle_pixels;
        EXPECT(fabs(sf - sh) <= PREF_SPECKLE_GAP * fmax(sh, sf) + PREF_SPECKLE_SLACK, "%s %s: speckles h %.0f, f %.0f",
               pref_scene_names[sc], pref_saliency_names[variant], sh, sf);
        for (int v = 0; v < 2; v++)
            EXPECT(m[v].crack_pixels <= 2 * PREF_CRACKS, "%s %s: %llu crack pixels in the %s clip", pref_scene_names[sc],
                   pref_saliency_names[variant], (unsigned long long)m[v].crack_pixels, v ? "f" : "h");
        EXPECT(fabs(m[1].error_p99 - m[0].error_p99) <= PREF_P99_GAP, "%s %s: warp p99 h %.3f px, f %.3f px",
               pref_scene_names[sc], pref_saliency_names[variant], m[0].error_p99, m[1].error_p99);
        warp_metrics_free(&m[0]);
        warp_metrics_free(&m[1]);
        scene_destroy(s);
    }
    gpu_destroy(g);
    int v = gpu_validation_messages();
    CHECK(v == 0, "%d validation messages", v);
    return 0;
}

/* The observer's view from the engine (issue 18): the ball's displayed
 * vergence in the study's own frames (480 x 270 per eye, the CPU default,
 * the window restarted at the launch) against the CPU view's model of the
 * same throws. Stated tolerances: the displayed h and f within 3 arcmin of
 * the CPU view's at every frame (one operator, fitted to the frame's coarse
 * samples vs a small software render; measured 2.3), and what f changes
 * over h within 0.25 arcmin (the frame solves a 3 s window of the whole
 * picture, the CPU view the ball's visible keyframes alone; measured: both
 * move the ball by less than 0.13 arcmin, docs/game.md says why). */
static int observer_engine_agrees(void)
{
    gpu *g;
    scene *s;
    vg_camera cam;
    CHECK(load_arena(&s, &cam) == 0, "arena");
    CHECK(gpu_create(&(gpu_desc){0}, &g) == VG_OK, "gpu_create");
    game_ball ball = {.node = scene_find_node(s, "ball"), .t_launch = 1.0};
    memcpy(ball.scale, s->nodes[ball.node].scale, sizeof ball.scale);
    scene_set_pose_hook(s, game_ball_pose, &ball);
    frame_desc fd = game_frame_desc(g, 0, FRAME_MODE_OPTIMIZED, 480, 270, FRAME_COMPOSE_ANAGLYPH, DISP_OPERATOR_LANG, true,
                                    &cam);
    observer_engine *e;
    CHECK(observer_engine_create(&(observer_engine_desc){.gpu = g, .scene = s, .moving_node = ball.node, .frame = fd,
                                                         .lead_keyframes = 1}, &e) == VG_OK, "observer_engine_create");
    observer_view *v;
    CHECK(observer_view_create(&(observer_view_desc){.scene = s, .moving_node = ball.node,
                                                     .preset = DISP_PRESET_STUDY}, &v) == VG_OK, "view");
    enum { N = 36, THROWS = 4 };
    double worst[2] = {0, 0}, worst_gain = 0;
    for (int k = 0; k < THROWS; k++) {
        game_rng r = game_rng_make(31, (uint64_t)k);
        game_throw_make(&(game_throw_desc){.path = k % 2 ? GAME_PATH_BALLISTIC : GAME_PATH_STRAIGHT,
                                           .direction = k / 2 ? GAME_DIR_FAR_TO_NEAR : GAME_DIR_NEAR_TO_FAR},
                        observer_view_camera(v), &r, &ball.th);
        double pos[N][3], gv[N], cpu[N], shown_h[N], cpu_h[N];
        for (int i = 0; i < N; i++)
            game_throw_position(&ball.th, i / 60.0, pos[i]);
        CHECK(observer_view_track(v, (const double (*)[3])pos, N, FRAME_MODE_ORIGINAL, gv) == VG_OK, "g");
        for (int m = 0; m < 2; m++) {
            frame_mode mode = m ? FRAME_MODE_OPTIMIZED : FRAME_MODE_MANIPULATED;
            observer_shown sh;
            CHECK(observer_engine_track(e, mode, 60, 1, N, &sh) == VG_OK, "engine track");
            CHECK(observer_view_track(v, (const double (*)[3])pos, N, mode, cpu) == VG_OK, "cpu track");
            double d = 0, gain = 0, cgain = 0, dgain = 0;
            for (int i = 0; i < N; i++) {
                double a = gv[i] + sh.offset[i];
                d = fmax(d, fabs(a - cpu[i]));
                if (m) {
                    gain = fmax(gain, fabs(a - shown_h[i]));
                    cgain = fmax(cgain, fabs(cpu[i] - cpu_h[i]));
                    dgain = fmax(dgain, fabs((a - shown_h[i]) - (cpu[i] - cpu_h[i])));
                } else {
                    shown_h[i] = a;
                    cpu_h[i] = cpu[i];
                }
            }
            printf("throw %d (%s, %s) %s: engine vs CPU view max %.3f arcmin (g %.1f..%.1f)%s",
                   k, k % 2 ? "ballistic" : "straight", k / 2 ? "far-to-near" : "near-to-far", m ? "f" : "h", d,
                   gv[0], gv[N - 1], m ? "" : "\n");
            if (m) {
                double eng_h[N], eng_f[N];
                for (int i = 0; i < N; i++)
                    eng_h[i] = shown_h[i], eng_f[i] = gv[i] + sh.offset[i];
                printf("; f vs h max: engine %.3f, CPU view %.3f arcmin; the paper's MID distortion (engine) "
                       "h %.3f f %.3f JND\n", gain, cgain,
                       observer_track_mid_distortion(eng_h, gv, N, 10, 60.0, 0.08),
                       observer_track_mid_distortion(eng_f, gv, N, 10, 60.0, 0.08));
            }
            worst[m] = fmax(worst[m], d);
            worst_gain = fmax(worst_gain, dgain);
        }
    }
    observer_view_destroy(v);
    observer_engine_destroy(e);
    scene_set_pose_hook(s, NULL, NULL);
    scene_destroy(s);
    gpu_destroy(g);
    int msgs = gpu_validation_messages();
    CHECK(msgs == 0, "%d validation messages", msgs);
    /* The gates make the mapping steep at their depths, where a 160 x 90
     * render and the frame's coarse samples of 480 x 270 differ most
     * (docs/game.md: 3.8 / 5.0 / 4.2 arcmin measured). */
    CHECK(worst[0] < 6.0, "h: engine and CPU view differ by %.3f arcmin (bound 6)", worst[0]);
    CHECK(worst[1] < 7.5, "f: engine and CPU view differ by %.3f arcmin (bound 7.5)", worst[1]);
    /* f - h holds h's own jump at a gate, which f does not follow (it
     * follows g: docs/method.md §8), where the two views' h differ most. */
    CHECK(worst_gain < 7.5, "f - h: engine and CPU view differ by %.3f arcmin (bound 7.5)", worst_gain);
    return 0;
}

/* Issue 39: at the game's CPU defaults (480 x 270, play's operator, the
 * ball's grid) the first throw of each kind free play draws (seed 1): the
 * manipulation distorts the ball's own motion in depth (h at least 1.5 JND
 * over its flight), the optimisation restores most of it (f below h on
 * each, at most 0.8 of it, and at most half of it in median), the grid
 * resolves the ball (4 samples on it at least at every keyframe), and f
 * differs from h on the ball by a visible amount (0.5 arcmin at least).
 * Every frame of each flight is rendered: at the frame rate, what a player
 * sees between keyframes, f is at most 0.75 of h on each throw and half of
 * it in median (docs/method.md §8: the upsampling in time carries g's
 * motion, not h's; when it carried h's, the near-to-far throws measured
 * 3.7 and 4.2 times h). */
static int ball_figures_shown(void)
{
    gpu *g;
    scene *s;
    CHECK(scene_load(ARENA, &s) == VG_OK, "arena");
    CHECK(gpu_create(&(gpu_desc){0}, &g) == VG_OK, "gpu_create");
    game_ball ball;
    vg_camera aim;
    CHECK(game_ball_attach(s, &ball, &aim), "the arena's ball");
    frame_desc fd = game_frame_desc(g, 0, FRAME_MODE_OPTIMIZED, 480, 270, GAME_LAYOUT, DISP_OPERATOR_DEFAULT, false,
                                    &aim);
    CHECK(fd.coarse_stride == 3, "the ball's grid at 480 x 270: stride %d, expected 3", fd.coarse_stride);
    ball_measure *m;
    CHECK(ball_measure_create(&(ball_measure_desc){.gpu = g, .scene = s, .ball = &ball, .frame = fd,
                                                   .every_frame = true}, &m) == VG_OK,
          "ball_measure_create");
    double ratio[GAME_THROW_KINDS], ratio_frame[GAME_THROW_KINDS];
    bool seen[GAME_THROW_KINDS] = {false};
    for (int n = 0, kinds = 0; kinds < GAME_THROW_KINDS && n < 64; n++) {
        game_throw th;
        game_throw_free_play(1, n, GAME_VISIBLE_S, &aim, &th);
        int k = game_throw_kind(&th);
        if (seen[k])
            continue;
        ball_figures b;
        CHECK(ball_measure_throw(m, &th, 60, &b) == VG_OK, "throw %d", n);
        printf("throw %d (%s, %s): h %.3f f %.3f JND, f/h %.3f, |f - h| up to %.2f arcmin, %d samples, %d px\n", n,
               game_path_names[th.path], game_direction_names[th.direction], b.h_jnd, b.f_jnd, b.f_jnd / b.h_jnd,
               b.max_f_minus_h, b.min_samples, b.min_pixels);
        printf("  at the frame rate: h %.3f f %.3f JND, f/h %.3f over %d frames, |f - h| up to %.2f arcmin\n",
               b.h_frame_jnd, b.f_frame_jnd, b.f_frame_jnd / b.h_frame_jnd, b.frames, b.max_f_minus_h_frame);
        CHECK(b.keys == 4, "throw %d: %d keyframes of its flight, expected 4", n, b.keys);
        CHECK(b.frames >= 30, "throw %d: %d frames of its flight measured", n, b.frames);
        CHECK(b.f_frame_jnd < 0.75 * b.h_frame_jnd, "throw %d at the frame rate: f %.3f against h %.3f JND", n,
              b.f_frame_jnd, b.h_frame_jnd);
        ratio_frame[k] = b.f_frame_jnd / b.h_frame_jnd;
        CHECK(b.h_jnd >= 1.5, "throw %d: h distorts the ball by %.3f JND only", n, b.h_jnd);
        CHECK(b.f_jnd < 0.8 * b.h_jnd, "throw %d: f %.3f against h %.3f JND", n, b.f_jnd, b.h_jnd);
        CHECK(b.min_samples >= 4, "throw %d: %d grid samples on the ball", n, b.min_samples);
        ratio[k] = b.f_jnd / b.h_jnd;
        seen[k] = true, kinds++;
        if (th.direction == GAME_DIR_NEAR_TO_FAR)
            CHECK(b.max_f_minus_h >= 0.5, "throw %d: f - h on the ball %.3f arcmin at most", n, b.max_f_minus_h);
    }
    for (int k = 0; k < GAME_THROW_KINDS; k++)
        CHECK(seen[k], "no throw of kind %d in 64", k);
    double med = vg_median(ratio, GAME_THROW_KINDS, 1);
    CHECK(med <= 0.5, "median f / h %.3f", med);
    med = vg_median(ratio_frame, GAME_THROW_KINDS, 1);
    CHECK(med <= 0.5, "median f / h at the frame rate %.3f", med);
    ball_measure_destroy(m);
    scene_set_pose_hook(s, NULL, NULL);
    scene_destroy(s);
    gpu_destroy(g);
    int msgs = gpu_validation_messages();
    CHECK(msgs == 0, "%d validation messages", msgs);
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"click_error", click_error},     {"throws", throws},           {"schedule", schedule},
        {"click_mapping", click_mapping}, {"pose_hook", pose_hook},     {"observer_exact", observer_exact},
        {"observer_two_cue", observer_two_cue},
        {"observer_conditions", observer_conditions}, {"csv_log", csv_log}, {"pref_equal_quality", pref_equal_quality},
        {"pref_clip", pref_clip},         {"observer_engine", observer_engine_agrees},
        {"ball_figures", ball_figures_shown},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
