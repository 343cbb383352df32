/* vergence — the frame: scene evaluation, the frame graph and its passes.
 *
 * A frame renders the scene at t = index / fps (absolute frame numbers, so
 * keyframes fall on multiples of the keyframe stride whatever the start
 * time). Passes so far (DESIGN.md, steps 1-2):
 *
 *   shadow   (graphics) sun shadow map
 *   gbuffer  (graphics) centre eye: lit colour + saliency, linear depth,
 *                       instance id, motion to the previous/next keyframe
 *   readback (transfer) copies the G-buffer to host memory (capture only)
 *
 * Headless and windowed runs share this code; time steps are fixed, so a
 * capture is deterministic. */
#pragma once
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "disparity/disp_operator.h"
#include "disparity/mid_solver.h"
#include "gpu/gpu.h"
#include "graph/graph.h"
#include "scene/scene.h"
#include "stereo/stereo_display.h"

typedef struct frame frame;

/* How the stereo pair is made (issue 5, paper 4.6). */
typedef enum frame_stereo {
    FRAME_STEREO_OFF = 0,        /* centre eye only (G-buffer) */
    FRAME_STEREO_WARP,           /* tessellated 3D vertex warping to the target disparity */
    FRAME_STEREO_CAMERAS,        /* two real off-axis cameras (shows g only) */
    FRAME_STEREO_IMAGEWARP,      /* forward image warping with a z-buffer (disocclusion holes) */
} frame_stereo;

/* Which disparity the pair shows (paper: g, h, f). */
typedef enum frame_mode {
    FRAME_MODE_DEFAULT = 0,      /* = optimized */
    FRAME_MODE_ORIGINAL,         /* g: the original stereo camera */
    FRAME_MODE_MANIPULATED,      /* h: the operator's output */
    FRAME_MODE_OPTIMIZED,        /* f: motion in depth restored */
} frame_mode;

/* How the two eyes are packed into one output image. */
typedef enum frame_compose {
    FRAME_COMPOSE_DEFAULT = 0,   /* = sbs */
    FRAME_COMPOSE_SBS,           /* side by side, full width each (2W x H) */
    FRAME_COMPOSE_SBS_HALF,      /* side by side, half width each (W x H) */
    FRAME_COMPOSE_TB,            /* top-bottom, full height each (W x 2H) */
    FRAME_COMPOSE_ROWS,          /* row-interleaved: even rows left (passive polarised panels) */
    FRAME_COMPOSE_COLUMNS,       /* column-interleaved: even columns left */
    FRAME_COMPOSE_CHECKER,       /* checkerboard: (x + y) even left */
    FRAME_COMPOSE_ANAGLYPH,      /* red-cyan, Dubois least-squares matrices */
    FRAME_COMPOSE_ANAGLYPH_PLAIN,/* red from left, green and blue from right */
    FRAME_COMPOSE_LEFT,
    FRAME_COMPOSE_RIGHT,
    FRAME_COMPOSE_COUNT,
} frame_compose;

/* Names as on the command line ("sbs", "anaglyph-plain", ...), NULL-terminated. */
extern const char *const frame_compose_names[];
extern const char *const frame_stereo_names[];
extern const char *const frame_mode_names[];

typedef struct frame_desc {
    uint32_t width, height;      /* 0 = 960x540 */
    double fps;                  /* 0 = 60 */
    int keyframe_stride;         /* frames between keyframes, 0 = 10 (paper 4.4) */
    int camera;                  /* camera node index (in node order) */
    bool readback;               /* copy the G-buffer to the host every frame */
    uint32_t shadow_size;        /* 0 = 2048 */
    stereo_display_desc display; /* the display model (zero = paper defaults) */
    stereo_camera_desc rig;      /* the original stereo camera; zero interaxial/convergence =
                                    FRAME_DEFAULT_INTERAXIAL / _CONVERGENCE; fov and width follow the render */
    frame_stereo stereo;
    frame_mode mode;
    frame_compose compose;
    bool swap_eyes;
    double tess_px;              /* edge length target in pixels (paper: 1); 0 = use tess_error */
    double tess_error;           /* disparity error tolerance in pixels; 0 with tess_px 0 = 0.025 */
    uint32_t max_tess_level;     /* 0 = 64 (clamped to the device) */
    double depth_epsilon;        /* cascade: relative depth difference of one surface, 0 = 0.01 */
    double halton_radius;        /* cascade: Halton search radius in pixels, 0 = 24 */
    bool diffuse;                /* no specular: eyes shade identically from any viewpoint */
    bool reference;              /* also render the two-camera reference (holes, PSNR) */
    bool measure;                /* eyes compute their disparity error per pixel (aux.z) */
    VkFormat present_format;     /* windowed: the swapchain format, UNDEFINED = headless */
    uint32_t present_width, present_height; /* windowed: the swapchain extent */
    const struct vg_curve *curve; /* a baked global curve instead of the per-frame one (copied) */
    /* The disparity pipeline (issue 4, DESIGN.md steps 4-7); zero = default. */
    disp_operator_kind op;       /* h = M(g, saliency), 0 = lang */
    disp_operator_preset op_preset; /* 0 = comfort (+-60 arcmin) */
    double target_range;         /* half-width of the target range, arcmin, 0 = the preset's */
    double window_seconds;       /* MID keyframe window, 0 = 3 s (paper 4.2: several seconds) */
    double window_future;        /* share of the window ahead of the frame, 0 = 0.5 */
    int coarse_stride;           /* solver grid stride in pixels, 0 = 5 (paper 4.4); larger frames
                                    widen it so the grid stays 192 x 108 (paper 4.5: constant time) */
    mid_solver_kind solver;      /* 0 = Gauss-Newton (the CPU reference's default) */
    int solver_iterations;       /* outer iterations per window, 0 = the solver's default for the first
                                    window and MID_GN_WARM_ITERATIONS for each warm-started move */
} frame_desc;

/* The original rig when the scene gives none: a 25 cm interaxial converged at
 * 6 m puts the paper's scenes (2-40 m) around the screen with more disparity
 * than a comfortable display takes, so the operators have work to do. */
#define FRAME_DEFAULT_INTERAXIAL 0.25
#define FRAME_DEFAULT_CONVERGENCE 6.0

/* Host copies after frame_render() (readback only; NULL when not rendered). */
typedef struct frame_outputs {
    const uint8_t *color;        /* RGBA8 sRGB, alpha = saliency */
    const float *depth;          /* linear depth, metres; background = far plane */
    const uint32_t *ids;         /* instance id, 0 = background */
    const float *motion;         /* 4 floats per pixel: pixels to prev keyframe (xy), to next (zw) */
    const float *g, *h, *f;      /* vergence maps, arcmin */
    const uint8_t *left, *right; /* RGBA8 sRGB; alpha 255 geometry, 128 sky, 0 nothing (hole) */
    const float *left_aux, *right_aux; /* 4 floats: centre-view x (px), view depth (m), disparity error (px), stage */
    const uint8_t *ref_left, *ref_right; /* the two-camera reference (desc.reference) */
    const uint8_t *stereo;       /* composed output, stereo_width x stereo_height RGBA8 */
    uint32_t stereo_width, stereo_height;
    const struct vg_curve *curve; /* the global depth -> vergence curve the warp used */
} frame_outputs;

/* The times a frame was rendered at. */
typedef struct frame_times {
    long index;                  /* absolute frame number */
    long prev_key, next_key;     /* neighbouring keyframes (frame numbers, strictly before/after) */
    double t, t_prev, t_next;    /* seconds */
} frame_times;

vg_status frame_create(gpu *g, const scene *s, const frame_desc *desc, frame **out);
void frame_destroy(frame *f);

/* Renders frame `index` and waits for it (headless). Indices may skip,
 * repeat or jump: each frame shows what rendering every index would
 * (disparity_gpu_prepare). */
vg_status frame_render(frame *f, long index);

const frame_outputs *frame_get_outputs(const frame *f);
const frame_times *frame_get_times(const frame *f);
const vg_camera *frame_get_camera(const frame *f);  /* at the frame's time */
const frame_desc *frame_get_desc(const frame *f);
rg_graph *frame_get_graph(frame *f);

/* Windowed: render frame `index` into an acquired swapchain image and submit
 * without waiting (two frames in flight). wait is signalled by the acquire,
 * signal is what vkQueuePresentKHR waits on. The HUD may be NULL. */
typedef struct frame_target {
    VkImage image;
    VkImageView view;
    VkSemaphore wait, signal;
} frame_target;
struct frame_hud;
vg_status frame_present(frame *f, long index, const frame_target *target, const struct frame_hud *hud);
/* The scene's future changed (what evaluating it ahead gave is stale: a new
 * throw of the game): the next frame starts the keyframe window afresh. */
void frame_restart(frame *f);
/* Waits until no frame is in flight. */
vg_status frame_wait_idle(frame *f);

/* GPU ms of each pass of the last frame; returns the number of passes. */
uint32_t frame_pass_timings(frame *f, const char **names, double *ms, uint32_t cap);

/* The disparity pipeline's grid, window and range; false when the frame has none. */
struct disparity_gpu_info;
bool frame_disparity_info(const frame *f, struct disparity_gpu_info *info);
/* A keyframe as the solve sees it (readback frames; disparity_gpu_keyframe_read). */
struct disparity_gpu_keyframe;
vg_status frame_solved_keyframe(const frame *f, long keyframe, struct disparity_gpu_keyframe *out);

/* Keyframe times around a frame number (pure: used by tests too). */
frame_times frame_times_at(long index, double fps, int stride);
