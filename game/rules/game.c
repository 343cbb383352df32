/* vergence — the hit-prediction game's rules (paper Sec. 5, Fig. 6). */
#include "game.h"

#include "frame/frame.h"
#include "frame/frame_desc.h"

#include <math.h>
#include <string.h>

const char *const game_path_names[] = {"straight", "straight", "ballistic", NULL};
const char *const game_direction_names[] = {"near-to-far", "near-to-far", "far-to-near", NULL};

/* ------------------------------------------------------------------------- */
/* Random numbers: splitmix64 (Steele et al. 2014), one stream per use       */
/* ------------------------------------------------------------------------- */

static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

game_rng game_rng_make(uint64_t seed, uint64_t stream)
{
    return (game_rng){mix64(seed ^ mix64(stream + 0x9e3779b97f4a7c15ull))};
}

uint64_t game_rng_next(game_rng *r)
{
    r->state += 0x9e3779b97f4a7c15ull;
    return mix64(r->state);
}

double game_rng_uniform(game_rng *r, double lo, double hi)
{
    double u = (double)(game_rng_next(r) >> 11) * 0x1.0p-53;
    return lo + (hi - lo) * u;
}

double game_rng_normal(game_rng *r)
{
    /* Box-Muller with u1 in (0, 1]: no log(0). */
    double u1 = ((double)(game_rng_next(r) >> 11) + 1.0) * 0x1.0p-53;
    double u2 = (double)(game_rng_next(r) >> 11) * 0x1.0p-53;
    return sqrt(-2.0 * log(u1)) * cos(2.0 * M_PI * u2);
}

uint64_t game_seed_from_text(const char *text)
{
    uint64_t h = 0xcbf29ce484222325ull; /* FNV-1a */
    for (const unsigned char *p = (const unsigned char *)text; *p; p++)
        h = (h ^ *p) * 0x100000001b3ull;
    return mix64(h) % 1000000000ull; /* short enough to type back as --seed */
}

/* ------------------------------------------------------------------------- */
/* The centre camera                                                         */
/* ------------------------------------------------------------------------- */

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

void game_ray(const vg_camera *cam, double u, double v, double origin[3], double dir[3])
{
    double ty = tan(0.5 * cam->yfov), tx = ty * cam->aspect;
    double x = (2.0 * u - 1.0) * tx, y = (1.0 - 2.0 * v) * ty, len2 = 0;
    for (int k = 0; k < 3; k++) {
        origin[k] = cam->position[k];
        dir[k] = cam->forward[k] + x * cam->right[k] + y * cam->up[k];
        len2 += dir[k] * dir[k];
    }
    double inv = 1.0 / sqrt(len2);
    for (int k = 0; k < 3; k++)
        dir[k] *= inv;
}

double game_project(const vg_camera *cam, const double p[3], double *u, double *v)
{
    double d[3] = {p[0] - cam->position[0], p[1] - cam->position[1], p[2] - cam->position[2]};
    double r[3] = {cam->right[0], cam->right[1], cam->right[2]};
    double up[3] = {cam->up[0], cam->up[1], cam->up[2]};
    double f[3] = {cam->forward[0], cam->forward[1], cam->forward[2]};
    double z = dot3(d, f);
    double ty = tan(0.5 * cam->yfov), tx = ty * cam->aspect;
    double zs = z > 1e-9 ? z : 1e-9;
    *u = 0.5 + 0.5 * dot3(d, r) / (zs * tx);
    *v = 0.5 - 0.5 * dot3(d, up) / (zs * ty);
    return z;
}

double game_ball_vergence(const frame *fr, const vg_camera *cam, const game_throw *th, double t)
{
    double c[3], u, v;
    game_throw_position(th, t, c);
    return frame_original_vergence(fr, game_project(cam, c, &u, &v));
}

double game_click_error(const vg_camera *cam, double u, double v, const double target[3])
{
    double o[3], d[3];
    game_ray(cam, u, v, o, d);
    double w[3] = {target[0] - o[0], target[1] - o[1], target[2] - o[2]};
    double along = dot3(w, d);
    if (along < 0) /* behind the eye: the ray starts at the eye */
        along = 0;
    double e2 = 0;
    for (int k = 0; k < 3; k++) {
        double c = w[k] - along * d[k];
        e2 += c * c;
    }
    return sqrt(e2);
}

/* ------------------------------------------------------------------------- */
/* Clicks: window -> picture -> eye image                                   */
/* ------------------------------------------------------------------------- */

bool game_click_to_image(frame_compose compose, uint32_t width, uint32_t height, uint32_t win_w, uint32_t win_h,
                         double x, double y, double *u, double *v)
{
    frame_layout l = frame_compose_layout(compose, false, width, height);
    /* The picture is fitted into the window keeping its aspect, centred
     * (output/present_gpu.c place_picture). */
    double s = fmin((double)win_w / l.width, (double)win_h / l.height);
    double pw = floor(l.width * s + 0.5), ph = floor(l.height * s + 0.5);
    double x0 = floor((win_w - pw) / 2), y0 = floor((win_h - ph) / 2);
    double cx = (x * win_w - x0) / pw * l.width, cy = (y * win_h - y0) / ph * l.height;
    if (cx < 0 || cy < 0 || cx >= l.width || cy >= l.height)
        return false;
    /* Each eye sits in its own rectangle of the composed image (squeezed
     * by the half layouts); in the interleaved and anaglyph layouts a point
     * of the picture is that point of both eyes. The eye image stands for
     * the centre image: a click is one eye's pixel, half its disparity from
     * the centre view. A click between the eyes (frame packing's blank
     * rows) is outside. */
    for (int e = 0; e < 2; e++) {
        const frame_eye_rect *r = &l.eye[e];
        if (cx >= r->x && cy >= r->y && cx < r->x + r->w && cy < r->y + r->h) {
            *u = (cx - r->x) / r->w;
            *v = (cy - r->y) / r->h;
            return true;
        }
    }
    return false;
}

/* ------------------------------------------------------------------------- */
/* Throws                                                                    */
/* ------------------------------------------------------------------------- */

void game_throw_position(const game_throw *th, double t, double out[3])
{
    if (t > th->flight_s) {
        memcpy(out, th->landing, sizeof th->landing);
        return;
    }
    if (t < 0)
        t = 0;
    for (int k = 0; k < 3; k++)
        out[k] = th->start[k] + th->velocity[k] * t;
    out[1] -= 0.5 * th->gravity * t * t;
}

int game_throw_kind(const game_throw *th)
{
    return 2 * (th->direction == GAME_DIR_FAR_TO_NEAR) + (th->path == GAME_PATH_BALLISTIC);
}

void game_throw_free_play(uint64_t seed, int n, double visible_s, const vg_camera *cam, game_throw *out)
{
    game_rng r = game_rng_make(seed, 0x9a11ull + (uint64_t)n);
    game_throw_desc td = {.visible_s = visible_s};
    td.path = (game_path)(GAME_PATH_STRAIGHT + (int)(game_rng_next(&r) & 1));
    td.direction = (game_direction)(GAME_DIR_NEAR_TO_FAR + (int)(game_rng_next(&r) & 1));
    game_throw_make(&td, cam, &r, out);
}

/* The throws' bounds (metres from the camera's foot, heights above the
 * ground): near-to-far from 4-5.5 m to 14-24 m, far-to-near from 17-22 m to
 * 5-9 m (a 0.5 m ball at 22 m is 8 pixels across in a 270-pixel-high eye). */
#define NEAR_START_M 4.0
#define FAR_LAND_M 24.0
#define FAR_START_M 22.0
#define START_Y_MAX_M 5.0

double game_ball_farthest_m(const vg_camera *cam)
{
    double d = fmax(FAR_LAND_M, FAR_START_M), dy = START_Y_MAX_M - cam->position[1];
    return sqrt(d * d + dy * dy);
}

int game_grid_stride(const vg_camera *cam, uint32_t h)
{
    double px = GAME_BALL_RADIUS / game_ball_farthest_m(cam) * h / tan(0.5 * cam->yfov); /* its diameter */
    int s = (int)floor(px / GAME_GRID_CELLS_ACROSS);
    return s < 1 ? 1 : s > MID_COARSE_STRIDE ? MID_COARSE_STRIDE : s;
}

/* The whole flight in view with a margin, never nearer than 2 m. */
static bool throw_in_view(const game_throw *th, const vg_camera *cam)
{
    const int steps = 48;
    for (int i = 0; i <= steps; i++) {
        double p[3], u, v;
        game_throw_position(th, th->flight_s * i / steps, p);
        double z = game_project(cam, p, &u, &v);
        if (z < 2.0 || u < 0.05 || u > 0.95 || v < 0.05 || v > 0.95)
            return false;
    }
    return true;
}

/* A point on the ground plane (height y) at distance d from the camera's
 * foot, az radians to the right of its horizontal forward direction. */
static void ground_point(const vg_camera *cam, double d, double az, double y, double out[3])
{
    double fx = cam->forward[0], fz = cam->forward[2], len = sqrt(fx * fx + fz * fz);
    if (len < 1e-6)
        fx = 0, fz = -1, len = 1;
    fx /= len, fz /= len;
    /* Right of forward (fx, fz) on the ground is (-fz, fx). */
    out[0] = cam->position[0] + d * (cos(az) * fx - sin(az) * fz);
    out[1] = y;
    out[2] = cam->position[2] + d * (cos(az) * fz + sin(az) * fx);
}

void game_throw_make(const game_throw_desc *desc, const vg_camera *cam, game_rng *r, game_throw *out)
{
    const double deg = M_PI / 180.0;
    game_throw th = {
        .path = desc->path ? desc->path : GAME_PATH_STRAIGHT,
        .direction = desc->direction ? desc->direction : GAME_DIR_NEAR_TO_FAR,
        .visible_s = desc->visible_s > 0 ? desc->visible_s : GAME_VISIBLE_S,
    };
    bool ballistic = th.path == GAME_PATH_BALLISTIC;
    for (int attempt = 0; attempt < 1000; attempt++) {
        double d0, d1, y0;
        if (th.direction == GAME_DIR_NEAR_TO_FAR) {
            d0 = game_rng_uniform(r, NEAR_START_M, NEAR_START_M + 1.5);
            d1 = game_rng_uniform(r, FAR_LAND_M - 10.0, FAR_LAND_M);
            /* A straight throw needs height to descend from over ~20 m. */
            y0 = ballistic ? game_rng_uniform(r, 0.9, 1.5) : game_rng_uniform(r, 1.8, 2.8);
        } else {
            d0 = game_rng_uniform(r, FAR_START_M - 5.0, FAR_START_M);
            d1 = game_rng_uniform(r, 5.0, 9.0);
            y0 = ballistic ? game_rng_uniform(r, 1.0, 2.5) : game_rng_uniform(r, 3.0, START_Y_MAX_M);
        }
        double az0 = game_rng_uniform(r, -12.0, 12.0) * deg, az1 = game_rng_uniform(r, -20.0, 20.0) * deg;
        th.flight_s = ballistic ? game_rng_uniform(r, 1.6, 2.2) : game_rng_uniform(r, 1.4, 2.0);
        ground_point(cam, d0, az0, y0, th.start);
        ground_point(cam, d1, az1, GAME_BALL_RADIUS, th.landing);
        th.gravity = ballistic ? GAME_GRAVITY : 0.0;
        for (int k = 0; k < 3; k++)
            th.velocity[k] = (th.landing[k] - th.start[k]) / th.flight_s;
        /* y(T) = y0 + vy T - g T^2 / 2 lands exactly at T. */
        th.velocity[1] += 0.5 * th.gravity * th.flight_s;
        if (throw_in_view(&th, cam))
            break;
    }
    memcpy(th.ground, th.landing, sizeof th.ground);
    th.ground[1] -= GAME_BALL_RADIUS;
    *out = th;
}

/* ------------------------------------------------------------------------- */
/* Scoring and schedule                                                      */
/* ------------------------------------------------------------------------- */

int game_points(double error_m)
{
    if (!(error_m >= 0))
        return 0;
    return (int)lround(100.0 * exp2(-error_m / 1.5));
}

void game_schedule(uint64_t seed, int cells, int trials, int *out)
{
    for (int first = 0, block = 0; first < trials; first += cells, block++) {
        int order[GAME_MAX_CELLS];
        for (int i = 0; i < cells; i++)
            order[i] = i;
        game_rng r = game_rng_make(seed, 0x5c4ed01eull + (uint64_t)block);
        for (int i = cells - 1; i > 0; i--) { /* Fisher-Yates */
            int j = (int)(game_rng_next(&r) % (uint64_t)(i + 1));
            int t = order[i];
            order[i] = order[j], order[j] = t;
        }
        for (int i = 0; i < cells && first + i < trials; i++)
            out[first + i] = order[i];
    }
}

game_cell game_hit_cell(int c)
{
    return (game_cell){
        .condition = c / 4,
        .direction = (game_direction)(GAME_DIR_NEAR_TO_FAR + (c / 2) % 2),
        .path = (game_path)(GAME_PATH_STRAIGHT + c % 2),
    };
}

void game_frame_defaults(const gpu *g, double tess_error, frame_desc *fd)
{
    fd->tess_error = tess_error > 0 ? tess_error : g->is_cpu ? 0.5 : 0.0; /* 0: the engine's */
}

frame_desc game_frame_desc(const gpu *g, double tess_error, frame_mode mode, uint32_t w, uint32_t h,
                           frame_compose layout, disp_operator_kind op, bool study, const vg_camera *ball_aim)
{
    frame_desc fd = {
        .width = w, .height = h, .fps = 60, .keyframe_stride = 10, .camera = 0, .stereo = FRAME_STEREO_WARP,
        .mode = mode, .compose = layout, .op = op, .op_preset = study ? DISP_PRESET_STUDY : DISP_PRESET_DEFAULT,
        .coarse_stride = ball_aim ? game_grid_stride(ball_aim, h) : 0,
    };
    game_frame_defaults(g, tess_error, &fd);
    return fd;
}

void game_render_size(const gpu *g, frame_compose c, uint32_t win_w, uint32_t win_h, uint32_t *w, uint32_t *h)
{
    double ew, eh;
    frame_compose_eye_size(c, win_w, win_h, &ew, &eh);
    bool interleaved = c == FRAME_COMPOSE_ROWS || c == FRAME_COMPOSE_COLUMNS || c == FRAME_COMPOSE_CHECKER;
    if (g->is_cpu && !interleaved && ew > 480) {
        eh *= 480 / ew;
        ew = 480;
    }
    *w = (uint32_t)fmax(16, round(ew));
    *h = (uint32_t)fmax(16, round(eh));
}

void game_ball_local(const game_throw *th, double t_launch, double t, bool shown, const float scale[3], float *local)
{
    double p[3];
    if (t < t_launch)
        memcpy(p, th->start, sizeof p);
    else
        game_throw_position(th, t - t_launch, p);
    for (int k = 0; k < 3; k++) {
        local[k] = (float)p[k];
        local[7 + k] = shown ? scale[k] : 0.0f;
    }
}

void game_ball_pose(void *user, const scene *s, float t, float *local)
{
    (void)s;
    const game_ball *b = user;
    game_ball_local(&b->th, b->t_launch, t, t < b->t_launch + b->th.visible_s, b->scale, local + (size_t)b->node * 10);
}

bool game_ball_attach(scene *s, game_ball *b, vg_camera *aim)
{
    int node = scene_find_node(s, "ball");
    if (node < 0)
        return false;
    b->node = node;
    memcpy(b->scale, s->nodes[node].scale, sizeof b->scale);
    scene_state s0;
    if (aim && scene_state_init(s, &s0) == VG_OK) {
        scene_evaluate(s, 0.0f, &s0);
        scene_camera_resolve(s, &s0, 0, 16.0f / 9.0f, aim); /* as play aims its throws */
        scene_state_free(&s0);
    }
    scene_set_pose_hook(s, game_ball_pose, b);
    return true;
}
