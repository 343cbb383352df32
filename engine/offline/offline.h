/* vergence — the offline MID pipeline behind `vergence optimize`: disparity
 * videos from files, including ones that did not come from this engine.
 *
 * Three passes over the frames (docs/method.md "Offline pipeline"):
 *   A. read every input once: sizes, channels, values (one clear error naming
 *      the file); the range of g for the operator's domain;
 *   B. h per frame (the operator, or --h files); coarse keyframe samples of
 *      g, h, depth; keyframe flows composed from the per-frame flows (.flo
 *      files, or computed from consecutive --image frames) by tracking the
 *      coarse samples through them; then the window solve;
 *   C. per frame: temporal and spatial upsampling of f/h, f written as PFM,
 *      and as colour previews for people (engine/figure): the middle frame
 *      of g, h and f as PNG with a legend, a video of each with ffmpeg;
 *      x-t slices of g, h and f at one row in colour with a legend;
 *      with --image, a new stereo pair from f (warp/image_warp.h);
 *      metrics.json written last.
 * A stale metrics.json is removed first, so a failed run never looks complete. */
#pragma once
#include <stdbool.h>

#include "core/status.h"
#include "disparity/disp_operator.h"
#include "disparity/mid_solver.h"
#include "flow/flow.h"
#include "stereo/stereo_display.h"

typedef enum disp_g_units {
    DISP_G_ARCMIN = 0, /* vergence, arcmin (this engine's convention) */
    DISP_G_PX,         /* stereo-dataset pixel disparity x_left - x_right, larger = nearer */
} disp_g_units;

typedef enum offline_view {
    OFFLINE_VIEW_AUTO = 0, /* left for pixel disparities (datasets), else centre */
    OFFLINE_VIEW_CENTRE,   /* the engine's captures: g of the centre camera */
    OFFLINE_VIEW_LEFT,     /* stereo datasets: g of the left camera */
} offline_view;

/* How the new pair's video packs the two eyes (--image, ffmpeg). */
typedef enum offline_stereo_layout {
    OFFLINE_STEREO_FULL_SBS = 0, /* side by side, each eye whole (2W x H) */
    OFFLINE_STEREO_HALF_SBS,     /* side by side, each eye at half width (W x H) */
    OFFLINE_STEREO_FULL_TB,      /* top-bottom, each eye whole (W x 2H) */
    OFFLINE_STEREO_HALF_TB,      /* top-bottom, each eye at half height (W x H) */
} offline_stereo_layout;

typedef enum offline_edge_norm {
    OFFLINE_EDGE_RANGE = 0, /* h normalised over the target range (paper 4.1 as DESIGN.md reads it) */
    OFFLINE_EDGE_ARCMIN,    /* arcmin per coarse sample */
    OFFLINE_EDGE_PIXEL,     /* arcmin per full-resolution pixel */
} offline_edge_norm;

/* The new pair's video file of a layout, named as VR and 3D players read
 * it (the suffixes iw3 writes, nunif iw3/utils.py): "stereo_LRF_Full_SBS",
 * "stereo_LR", "stereo_TBF_fulltb", "stereo_TB"; the extension is the
 * caller's. */
const char *offline_stereo_name(offline_stereo_layout layout);

/* Where the per-frame flows come from (--flow). */
typedef enum offline_flow {
    OFFLINE_FLOW_AUTO = 0, /* the .flo files when named, else computed when --image is, else none */
    OFFLINE_FLOW_GIVEN,    /* --flow-next / --flow-prev (.flo) */
    OFFLINE_FLOW_COMPUTED, /* DIS optical flow between consecutive --image frames (engine/flow); a
                              pixel failing the forward-backward check takes its row's nearest
                              consistent flow (offline_read.c) */
    OFFLINE_FLOW_NONE,     /* a static camera and scene: zero flow */
} offline_flow;

/* Scene cuts (offline_cuts.c): found in the colour frames, none, or named. */
typedef enum offline_cuts {
    OFFLINE_CUTS_AUTO = 0, /* the colour histograms of consecutive --image / --video frames */
    OFFLINE_CUTS_NONE,     /* one shot */
    OFFLINE_CUTS_GIVEN,    /* cut_frames */
} offline_cuts;

typedef struct offline_desc {
    /* printf-style patterns (disp_pattern.h); all but out optional, and g
     * or depth needed.
     * ids: instance ids as capture writes them (24-bit RGB PNG, R the low
     * byte; 0 = background), for the links' same-surface test. */
    const char *g, *h, *depth, *flow_next, *flow_prev, *saliency, *ids;
    const char *image;        /* 8-bit RGB PNG per frame, the view g belongs to: a new stereo pair from f */
    const char *video_in;     /* instead of image: a colour video (any file ffmpeg reads), its frames
                                 first..last (counted from 0) decoded to PNGs in a temporary folder */
    const char *depth_video;  /* instead of depth: a grey video of depth, decoded to 16-bit PNGs (an 8-bit
                                 video's v as v * 257), read with depth_scale and depth_inverse */
    /* Depth files (PFM, or 16-bit grey PNG whose 0 is unknown) hold
     * value * depth_scale metres, or with depth_inverse 1 / (value *
     * depth_scale) metres (inverse depth, as monocular estimators write
     * it). depth_scale 0 = 1; a PNG needs it given. Without g, g is the
     * vergence the display gives depth through the rig (stereo_camera). */
    double depth_scale;
    bool depth_inverse;
    stereo_camera_desc rig;
    offline_view image_view;  /* where that view is */
    offline_flow flow;        /* where the flows come from */
    flow_preset flow_preset;  /* of computed flows */
    bool flow_to_keyframe;    /* flows go to the previous / next keyframe (as capture writes them),
                                 not to the previous / next frame; first is a keyframe */
    bool flow_to_frame;       /* computed flows from frame to frame, chained to the keyframes (the
                                 default computes each frame's flow to its keyframes directly) */
    const char *out_dir;
    int first, last;          /* inclusive frame numbers */
    int keyframe_stride;      /* frames between keyframes, 0 = 10 (paper 4.4) */
    int coarse;               /* spatial stride of the solver grid, 0 = 5 (paper 4.4) */
    double fps;               /* 0 = 60 */
    int row;                  /* full-resolution row of the x-t slices, < 0 = the middle */
    disp_operator_kind op;    /* ignored when h is given */
    /* The baseline the stereo converters use (nunif's iw3, depth_scaler.py
     * WindowEMAScaler): h maps g linearly from a per-frame range to the
     * target range, that range the minimum and maximum of g over the next
     * ema_window frames (within the shot), smoothed by an exponential
     * moving average of decay ema_decay. op is then LINEAR (its target range). */
    bool ema;
    double ema_decay;         /* 0 = 0.9 */
    int ema_window;           /* frames, 0 = 30 */
    disp_operator_preset preset;
    double target_range;      /* half-width, arcmin, 0 = preset */
    mid_weights weights;      /* all zero = the paper's */
    mid_solver_kind solver;
    int iterations, cg_iterations;
    int threads;              /* 0 = all cores */
    stereo_display_desc display;
    disp_g_units g_units;
    double px_zero;           /* pixel disparity shown on the screen plane (px units) */
    float occlusion_tolerance; /* 0 = MID_OCCLUSION_TOLERANCE */
    bool video;               /* g.mp4, h.mp4, f.mp4 when ffmpeg is installed */
    offline_stereo_layout stereo_layout; /* the new pair's video (offline_stereo_name) */
    bool stereo_mkv;          /* that video as Matroska too, its StereoMode set */
    /* The sensitivity study's choices (docs/method.md section 16): the
     * spatial weights' |dh| in the target range (default), in arcmin per
     * coarse sample or per pixel; velocities per second (default) or per
     * keyframe interval. */
    offline_edge_norm edge_norm;
    bool velocity_per_keyframe;
    bool uniform_saliency;    /* without --saliency: every pixel weighs alike, not the computed saliency */
    bool causal;              /* the engine's sliding window with its future predicted from the past
                                 (mid_causal.h), not one window over the whole sequence */
    offline_cuts scene_cuts;  /* where the window restarts */
    const int *cut_frames;    /* GIVEN: the first frame of each new shot, increasing */
    int cut_count;
    double cut_threshold;     /* AUTO: histogram distance above which frames are cut apart, 0 = OFFLINE_CUT_THRESHOLD */
} offline_desc;

vg_status offline_run(const offline_desc *desc);
const char *offline_cuts_name(offline_cuts c);
