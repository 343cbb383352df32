/* vergence — the hit-prediction game (paper Sec. 5, Fig. 6): throws, the
 * error of a click, scoring, and the balanced schedule of the hit study.
 *
 * A throw launches the ball on a straight line or a ballistic arc, either
 * near-to-far (away from the player) or far-to-near (toward the player),
 * in a random direction that keeps the whole path in view. The ball is shown
 * only for the first `visible_s` seconds; the player then clicks where it
 * will land on the ground. The error is the paper's: the closest world-space
 * distance between the true landing point and the ray through the clicked
 * pixel of the centre camera.
 *
 * Shared by `vergence play`, `vergence study` and the simulated observer;
 * pure C, no GPU. Every random draw comes from a stream seeded by (seed,
 * trial), so a trial is the same whatever ran before it (resume). */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "frame/frame_desc.h"
#include "scene/scene.h"

#define GAME_BALL_RADIUS 0.25   /* metres: the arena's `ball` node (docs/content.md) */
#define GAME_GRAVITY 9.81       /* m/s^2 */
#define GAME_VISIBLE_S 0.6      /* default visible interval after launch */

typedef enum game_path {
    GAME_PATH_DEFAULT = 0,      /* = straight */
    GAME_PATH_STRAIGHT,
    GAME_PATH_BALLISTIC,
    GAME_PATH_COUNT,
} game_path;

typedef enum game_direction {
    GAME_DIR_DEFAULT = 0,       /* = near-to-far */
    GAME_DIR_NEAR_TO_FAR,
    GAME_DIR_FAR_TO_NEAR,
    GAME_DIR_COUNT,
} game_direction;

/* Names as written in the study CSV, index = enum value (0 repeats 1). */
extern const char *const game_path_names[];
extern const char *const game_direction_names[];

/* ------------------------------------------------------------------------- */
/* Random numbers                                                            */
/* ------------------------------------------------------------------------- */

typedef struct game_rng {
    uint64_t state;
} game_rng;

/* A stream for (seed, stream): independent streams for every trial. */
game_rng game_rng_make(uint64_t seed, uint64_t stream);
uint64_t game_rng_next(game_rng *r);
double game_rng_uniform(game_rng *r, double lo, double hi);
double game_rng_normal(game_rng *r);
/* A seed from text (the participant id when --seed is not given). */
uint64_t game_seed_from_text(const char *text);

/* ------------------------------------------------------------------------- */
/* Throws                                                                    */
/* ------------------------------------------------------------------------- */

typedef struct game_throw_desc {
    game_path path;
    game_direction direction;
    double visible_s;           /* 0 = GAME_VISIBLE_S */
} game_throw_desc;

typedef struct game_throw {
    game_path path;
    game_direction direction;
    double start[3];            /* ball centre at launch */
    double velocity[3];         /* at launch, m/s */
    double gravity;             /* downward acceleration: GAME_GRAVITY or 0 (straight) */
    double flight_s;            /* until the centre is GAME_BALL_RADIUS above the ground */
    double landing[3];          /* ball centre on landing */
    double ground[3];           /* the spot it lands on (landing - radius): the error is measured to it */
    double visible_s;
} game_throw;

/* Draws a throw whose whole path stays inside the view of `cam` (the
 * arena's camera; rejection sampling from r). */
void game_throw_make(const game_throw_desc *desc, const vg_camera *cam, game_rng *r, game_throw *out);
/* Ball centre at t seconds after launch (held at the landing point after). */
void game_throw_position(const game_throw *th, double t, double out[3]);
/* The kind of a throw, 0 .. GAME_THROW_KINDS - 1: straight near-to-far,
 * ballistic near-to-far, straight far-to-near, ballistic far-to-near. */
#define GAME_THROW_KINDS 4
int game_throw_kind(const game_throw *th);
/* Free play's n-th throw (`vergence play`, `vergence bench --game`): path
 * and direction drawn from the stream (seed, 0x9a11 + n), then made as
 * game_throw_make does. */
void game_throw_free_play(uint64_t seed, int n, double visible_s, const vg_camera *cam, game_throw *out);

/* ------------------------------------------------------------------------- */
/* The centre camera                                                         */
/* ------------------------------------------------------------------------- */

/* Image coordinates: u right, v down, both in [0, 1] across the centre
 * image (a pixel x of a W-wide image is u = (x + 0.5) / W). */
void game_ray(const vg_camera *cam, double u, double v, double origin[3], double dir[3]);
/* Projects p; returns its depth along the view axis (<= 0: behind). */
double game_project(const vg_camera *cam, const double p[3], double *u, double *v);
/* The ball's exact g t seconds after th's launch: its centre's view depth
 * under cam through the frame's original rig (frame_original_vergence),
 * arcmin. Its silhouette's mean would move with the pixels it covers. */
struct frame;
double game_ball_vergence(const struct frame *fr, const vg_camera *cam, const game_throw *th, double t);
/* The paper's error: distance from `target` to the ray through (u, v). */
double game_click_error(const vg_camera *cam, double u, double v, const double target[3]);
/* A click at fractions (x, y) of a win_w x win_h window showing eyes of
 * width x height composed by `compose` (scaled to fit, centred) -> the
 * centre image's (u, v). False when it is outside the picture. */
bool game_click_to_image(frame_compose compose, uint32_t width, uint32_t height, uint32_t win_w, uint32_t win_h,
                         double x, double y, double *u, double *v);

/* ------------------------------------------------------------------------- */
/* Scoring                                                                   */
/* ------------------------------------------------------------------------- */

/* Points for an error in metres: 100 on the spot, halving every 1.5 m. */
int game_points(double error_m);

/* ------------------------------------------------------------------------- */
/* The hit study's schedule                                                  */
/* ------------------------------------------------------------------------- */

/* Balanced and randomised: consecutive blocks of `cells` trials each hold
 * every cell 0 .. cells-1 once, in a random order (the last block may be
 * partial). Trial i's cell depends on (seed, i) only, not on the number of
 * trials, so a study can be resumed or extended. cells <= GAME_MAX_CELLS. */
#define GAME_MAX_CELLS 64
void game_schedule(uint64_t seed, int cells, int trials, int *out);

/* A cell of the hit study: condition (3) x direction (2) x path (2). */
typedef struct game_cell {
    int condition;               /* 0 original, 1 manipulated, 2 optimized */
    game_direction direction;
    game_path path;
} game_cell;
#define GAME_HIT_CELLS 12
game_cell game_hit_cell(int cell);

/* The frame of the game and the studies on a device: a CPU rasteriser gets
 * error-driven tessellation at 0.5 px (tess_error overrides; 0 = default),
 * to stay interactive; a GPU the engine's. */
void game_frame_defaults(const gpu *g, double tess_error, frame_desc *fd);
/* `vergence play`'s window and layout by default. */
#define GAME_WINDOW_W 1280
#define GAME_WINDOW_H 720
#define GAME_LAYOUT FRAME_COMPOSE_ANAGLYPH
/* The frame the game renders in a mode: eyes of w x h at 60 Hz, keyframes
 * every 10th frame (paper 4.4), the tessellated warp, the layout, the
 * manipulation op (a study's compresses as the paper's did, play's for
 * comfort) and game_frame_defaults. With ball_aim (the camera throws are
 * aimed with: a frame that shows the ball), the solver's grid is the one
 * game_grid_stride chooses for the ball. The caller adds display and window. */
frame_desc game_frame_desc(const gpu *g, double tess_error, frame_mode mode, uint32_t w, uint32_t h,
                           frame_compose layout, disp_operator_kind op, bool study, const vg_camera *ball_aim);
/* The solver grid's stride chosen from the content, not the eye size (paper
 * 4.5: "based on content structure details rather than screen
 * resolution"): the ball is what the player judges, so the grid's cells are
 * at most 1 / GAME_GRID_CELLS_ACROSS of its diameter where the game shows it
 * smallest (the farthest point of any throw's visible flight, game_throw_make's
 * bounds), seen by `cam` in an image h pixels high; the paper's 5 px where
 * that is finer already. */
#define GAME_GRID_CELLS_ACROSS 2.5
int game_grid_stride(const vg_camera *cam, uint32_t h);
/* How far from the eye a throw's ball is at most while it is shown, m. */
double game_ball_farthest_m(const vg_camera *cam);
/* The eye size of `vergence play` in a window of win_w x win_h: the eyes fill
 * it in the layout, and a CPU rasteriser gets at most 480 pixels across
 * (not the interleaved layouts: they need 1:1 pixels). */
void game_render_size(const gpu *g, frame_compose c, uint32_t win_w, uint32_t win_h, uint32_t *w, uint32_t *h);
/* The ball's local transform (scene_pose_fn layout: translation 0-2, scale
 * 7-9) at scene time t of a throw launched at t_launch: at its start before,
 * on its path after; scale 0 (no pixels, bounds unchanged) when not shown. */
void game_ball_local(const game_throw *th, double t_launch, double t, bool shown, const float scale[3],
                     float *local);
/* A throw posed on a scene without a game around it (the game bench, the
 * simulated observer's frames): scene_set_pose_hook(s, game_ball_pose, &b).
 * The ball rests at its start until t_launch, flies, and is hidden after
 * its visible interval, as in play. */
typedef struct game_ball {
    int node;                    /* the scene's `ball` node */
    float scale[3];              /* its scale when shown */
    game_throw th;
    double t_launch;
} game_ball;
void game_ball_pose(void *user, const scene *s, float t, float *local);
/* b throws the scene's `ball` node: its node and shown scale from the scene,
 * the pose hook set; aim (optional) receives the camera play aims its
 * throws with (camera 0 at t = 0, 16:9 whatever the window's shape).
 * False, with nothing set, when the scene has no node named `ball`. */
bool game_ball_attach(scene *s, game_ball *b, vg_camera *aim);
