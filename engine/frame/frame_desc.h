/* vergence — what an application asks a frame for (frame_create): the
 * image, the display, the stereo pair, the disparity pipeline, each with its
 * default at zero. The frame resolves the defaults once and hands each pass
 * module the part it renders (its X_gpu_desc: shadow, gbuffer, warp,
 * compose, present). */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "disparity/disp_operator.h"
#include "disparity/mid_solver.h"
#include "pass/frame_types.h"

/* Where the keyframe window's future comes from (paper 4.5: "a prediction
 * of future frames"). */
typedef enum frame_look_ahead {
    FRAME_LOOK_AHEAD_FORESIGHT = 0, /* the scene evaluated ahead: every animation is known */
    FRAME_LOOK_AHEAD_CAUSAL,        /* the past only: scene_evaluate_known's constant-velocity prediction,
                                       every future keyframe predicted again at each window move */
} frame_look_ahead;

/* Where the operator's saliency comes from (docs/method.md section 3). */
typedef enum frame_saliency {
    FRAME_SALIENCY_AUTO = 0,     /* authored when the scene authors any, else computed */
    FRAME_SALIENCY_AUTHORED,     /* the glTF's extras.saliency (none: uniform) */
    FRAME_SALIENCY_COMPUTED,     /* from colour contrast, motion and depth (disp_saliency_computed) */
} frame_saliency;

extern const char *const frame_look_ahead_names[]; /* "foresight", "causal" */
extern const char *const frame_saliency_names[];   /* "auto", "authored", "computed" */

/* Shadow texels per frame row by default (frame_desc.shadow_size): at 960x540
 * about the 2048-texel map the engine had (2160); a texel of the whole scene's cascade
 * covers two pixels at the split depth, the near cascade's about one at the
 * balloon house (docs/architecture.md "Lighting"). */
#define FRAME_SHADOW_TEXELS_PER_ROW 4u

typedef struct frame_desc {
    uint32_t width, height;      /* 0 = 960x540 */
    double fps;                  /* 0 = 60 */
    int keyframe_stride;         /* frames between keyframes, 0 = 10 (paper 4.4) */
    int camera;                  /* camera node index (in node order) */
    bool readback;               /* copy the G-buffer to the host every frame */
    bool maps_only;              /* stereo frames: the G-buffer and the disparity maps g, h, f only (with
                                    readback: a simulated observer's view); no eyes are drawn */
    uint32_t shadow_size;        /* a shadow cascade's side in texels, 0 = FRAME_SHADOW_TEXELS_PER_ROW x height
                                    (at least 256; the atlas of the cascades at most the device's widest image) */
    stereo_display_desc display; /* the display model (zero = paper defaults) */
    stereo_camera_desc rig;      /* the original stereo camera; zero interaxial/convergence =
                                    FRAME_DEFAULT_INTERAXIAL / _CONVERGENCE; fov and width follow the render */
    frame_stereo stereo;
    frame_mode mode;
    frame_compose compose;
    bool swap_eyes;
    double tess_px;              /* edge length target in pixels (paper: 1); 0 = use tess_error */
    double tess_error;           /* disparity error tolerance in pixels; 0 with tess_px 0 = 0.025 */
    uint32_t max_tess_level;     /* 0 = 32, 64 with tess_px (clamped to the device) */
    double depth_epsilon;        /* cascade: relative depth difference of one surface, 0 = 0.01 */
    double halton_radius;        /* cascade: Halton search radius in pixels, 0 = 24 */
    /* (the defaults: warp/warp_settings.h, shared with the SDK) */
    bool diffuse;                /* no specular: eyes shade identically from any viewpoint */
    bool reference;              /* also render the two-camera reference (holes, PSNR) */
    bool measure;                /* eyes compute their disparity error per pixel (aux.z) */
    bool overlay;                /* headless: draw frame_set_hud's text into the eyes (windowed: always) */
    VkFormat present_format;     /* windowed: the swapchain format, UNDEFINED = headless */
    uint32_t present_width, present_height; /* windowed: the swapchain extent */
    const struct vgx_curve_data *curve; /* a baked global curve instead of the per-frame one (copied) */
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
    frame_saliency saliency;     /* the operator's saliency: authored, computed, or auto (0) */
    frame_look_ahead look_ahead; /* the window's future keyframes: the scene's own (perfect foresight,
                                    0) or predicted from the past (causal; docs/method.md "Look-ahead") */
    bool budgeted_solve;         /* a constant share of the solve a rendered frame, published settled
                                    when its keyframe is due (disparity_gpu_desc.budgeted; live play);
                                    false: frames that skip ticks catch up (f as if every tick rendered) */
    bool temporal_depth_only;    /* the temporal upsampling's occlusion test by depth alone (paper 4.4),
                                    not the links' test: kept to measure the two (docs/method.md Sec. 8) */
    /* Instance ids whose pixels the probe measures in every frame (frame_take_probes: the game's
     * ball), 0-terminated; none: no probe pass. */
    uint32_t probe_ids[FRAME_PROBE_MAX_IDS];
} frame_desc;

/* The original rig when the scene gives none: a 25 cm interaxial converged at
 * 6 m puts the paper's scenes (2-40 m) around the screen with more disparity
 * than a comfortable display takes, so the operators have work to do. */
#define FRAME_DEFAULT_INTERAXIAL 0.25
#define FRAME_DEFAULT_CONVERGENCE 6.0
