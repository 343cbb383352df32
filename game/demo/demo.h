/* vergence demo — shared types of the headless report (issue 7).
 *
 * `vergence demo` renders every scene in the three modes (g, h, f) and
 * writes a self-contained report: cmd_demo.c drives it, demo_run.c renders
 * one scene in one mode, demo_image.c makes the pictures, demo_svg.c the
 * plots, demo_html.c the page. Everything the page shows is computed from
 * this run's frames; nothing is copied from elsewhere. */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "disparity/disp_metrics.h"
#include "disparity/disp_operator.h"
#include "graph/graph.h"
#include "frame/frame.h"
#include "scene/scene.h"
#include "capture/capture_log.h"
#include "core/manifest.h"
#include "frame/warp_metrics.h"

#define DEMO_MODES 3         /* original, manipulated, optimized */
#define DEMO_MAPS 3          /* g, h, f */
#define DEMO_MAX_TRACKS 5
#define DEMO_MAX_STILLS 4
#define DEMO_NAME 64
#define DEMO_NOTE 320

/* The options of one report (cmd_demo.c fills them). */
typedef struct demo_opts {
    const char *out;
    int width, height;
    int step;                /* the modes' videos and stills: every step-th frame */
    int analysis_step;       /* the analysis run (maps, tracks, slices, MID): every n-th frame, 1 = all */
    double fps;              /* frame rate of the fixed time step */
    int stills;              /* stereo stills per scene and mode */
    double seconds;          /* clip length, 0 = the scene's animation */
    bool video;              /* one video per scene and mode (needs ffmpeg) */
    const char *ffmpeg;      /* path of ffmpeg, NULL when not installed */
    disp_operator_kind op;   /* disparity operator, 0 = the frame's default (lang) */
    int keyframe_stride;
    double tess_error;       /* the warp's tessellation tolerance, px */
    stereo_display_desc display; /* the viewer's display (every capture.json records it) */
} demo_opts;

/* One object's mean vergence per sample (NAN where it is not visible). */
typedef struct demo_track {
    char name[DEMO_NAME];
    int node;
    float saliency;
    float *v[DEMO_MAPS];     /* samples floats each, NULL while no run produced the map */
} demo_track;

/* One scene rendered in one mode. */
typedef struct demo_run {
    frame_mode mode;
    bool available;          /* false: the mode could not be rendered (note says why) */
    bool analysis;           /* this run recorded the scene's maps (the first available mode) */
    int step, frames;        /* rendered every step-th frame, frames in all */
    char note[DEMO_NOTE];
    uint32_t pass_count;
    char pass_names[RG_MAX_PASSES][DEMO_NAME];
    double pass_ms[RG_MAX_PASSES]; /* median over the rendered frames */
    double frame_ms;         /* median CPU wall time of a frame */
    warp_metrics warp;       /* tessellated warp against the two cameras, at the stills */
    warp_metrics imagewarp;  /* the image-warping baseline at the stills */
    bool has_mid;            /* MID metrics of h and f over the clip's keyframes */
    disp_metrics mid[2];     /* h, f */
    double range_violation[2];
    double second_difference[2][2]; /* h, f: at keyframe boundaries, between them (arcmin) */
    double range_lo, range_hi;
    int keyframes;
    bool video;              /* DIR/video.webm was written */
    int still_count;
    long still_frames[DEMO_MAX_STILLS];
} demo_run;

typedef struct demo_scene {
    char name[DEMO_NAME];    /* file stem: content/NAME.gltf */
    char path[512];
    int samples;             /* frames of the analysis run */
    long *frames;            /* their absolute frame numbers */
    long last;               /* the clip's last frame (a multiple of every run's step) */
    double fps;
    int row;                 /* image row of the x-t slices */
    int width;
    float *xt[DEMO_MAPS];    /* samples x width, NULL while no run produced the map */
    float xt_lo[DEMO_MAPS], xt_hi[DEMO_MAPS]; /* colour scale of each slice (demo_figures_write) */
    demo_track tracks[DEMO_MAX_TRACKS];
    int track_count;
    float *fh_diff;          /* |f - h| (arcmin) at the middle still of the analysis run, width x height */
    long fh_frame;           /* its frame */
    float fh_max;            /* its colour scale's top (demo_figures_write) */
    int motion_points;       /* keyframes of the moving object's motion plots (demo_figures_write) */
    demo_run runs[DEMO_MODES];
} demo_scene;

/* The modes in report order. */
extern const frame_mode demo_modes[DEMO_MODES];
extern const char *const demo_map_names[DEMO_MAPS]; /* "g", "h", "f" */

/* Renders one scene in one mode: video frames, stills, the warp against
 * two cameras, DIR/SCENE/MODE/capture.json. The analysis run (the first
 * mode rendered) renders every analysis_step-th frame and also records the
 * x-t rows, the object tracks and the MID metrics (over every keyframe:
 * analysis_step divides the keyframe stride). A mode the frame cannot
 * render is recorded as
 * unavailable (with a note on stderr), not as a failure. progress(units)
 * is called after every rendered frame. */
typedef void (*demo_progress_fn)(void *user, int units);
vg_status demo_run_scene_mode(gpu *g, const scene *s, const demo_opts *o, demo_scene *sc, int mode_index,
                              bool analysis, demo_progress_fn progress, void *user);
/* Work units (frames) demo_run_scene_mode reports for one scene and mode. */
int demo_run_units(const demo_opts *o, const demo_scene *sc, bool analysis);
void demo_run_free(demo_run *r);

/* Prepares sc for a scene: samples, the x-t row (the most salient object's
 * median image row), the tracked objects. */
/* The clip's last frame: the scene's animation (or o->seconds), rounded
 * down to a multiple of o->step. */
long demo_clip_last(const demo_opts *o, const scene *s);
vg_status demo_scene_init(demo_scene *sc, const scene *s, const char *name, const char *path,
                          const demo_opts *o);
void demo_scene_free(demo_scene *sc);

/* The scene's figures after its runs: DIR/SCENE/xt_{g,h,f}.png,
 * tracks_g.svg, tracks_hf.svg, the moving object's perceived motion in
 * depth motion_v.svg and motion_a.svg, and fh_diff.png (demo_figures.c). */
vg_status demo_figures_write(const demo_opts *o, demo_scene *sc);

/* index.html in o->out. */
vg_status demo_html_write(const demo_opts *o, const demo_scene *scenes, int count, double seconds,
                          const char *device, const vg_manifest *m);
