/* vergence — what the files of `vergence optimize`'s pipeline share: the
 * run state and each file's functions. Private to engine/offline (offline.h
 * is the library's API).
 *
 *   offline.c        offline_run: the steps below, in order
 *   offline_read.c   the inputs: file patterns, every frame read and checked
 *                    (pass A), g's units, depth
 *   offline_solve.c  saliency, the operator, keyframe samples and flows
 *                    (pass B), the solve, the upsampling to every frame (pass C)
 *   offline_write.c  what --out receives: f, previews, videos, x-t slices,
 *                    the new stereo pair, metrics.json; and the check that
 *                    none of it is an input
 *
 * The calls run one way: offline.c calls the three; offline_solve.c calls
 * offline_read.c and hands each upsampled frame to offline_write.c, which
 * calls offline_read.c (the --image frames). No two files of the project
 * may use each other's functions, even around a circle (arch.circles), so a
 * helper that two of them need goes into the lower one, or here when tiny. */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "core/manifest.h"
#include "core/parallel.h"
#include "core/status.h"
#include "disparity/disp_operator.h"
#include "disparity/disp_pattern.h"
#include "disparity/disp_upsample.h"
#include "disparity/mid_solver.h"
#include "disparity/disp_metrics.h"
#include "figure/figure.h"
#include "offline.h"
#include "stereo/stereo_display.h"

#define OFFLINE_PATH_CAP 4096
#define OFFLINE_VERGENCE_MAX 10800.0 /* arcmin: a vergence angle is below 180 degrees */

/* One run of offline_run: the sequence as read, and what the passes share. */
typedef struct offline_seq {
    const offline_desc *desc;
    /* The frames' file names (printf-style, disp_pattern.h), one per input;
     * has_* says which of the optional ones were given (g, or depth). */
    disp_pattern g_pattern, h_pattern, depth_pattern, flow_next_pattern, flow_prev_pattern, saliency_pattern,
        ids_pattern, image_pattern;
    bool has_h, has_depth, has_flow_next, has_flow_prev, has_saliency, has_ids, has_image;
    bool g_from_depth;    /* no --g: g is the display's vergence of the depth through the rig */
    stereo_camera rig;
    char video_dir[OFFLINE_PATH_CAP]; /* --video's frames, decoded (removed at the end); "" = none */
    char video_pattern[OFFLINE_PATH_CAP + 16]; /* ... and their names, the image pattern */
    char depth_video_pattern[OFFLINE_PATH_CAP + 16]; /* --depth-video's, the depth pattern */
    int width, height;    /* of every frame, from the first g */
    int frames;           /* desc->last - desc->first + 1 */
    int keyframe_stride;  /* frames between keyframes */
    int keyframes;        /* how many */
    int *keyframe_numbers; /* frame number of each keyframe */
    double fps;
    double range_lo, range_hi; /* the operator's target range, arcmin */
    double g_min, g_max;  /* g over the sequence, arcmin (the operator's domain) */
    stereo_display display;
    disp_grid grid;       /* the solver's coarse samples */
    disp_operator *op;
    vg_pool *pool;
    float *saliency;      /* scratch: saliency of one frame */
    uint8_t *unknown;     /* scratch: the last frame read's pixels of unknown g (inf) */
    vg_manifest manifest; /* the result in out_dir: metrics.json lists its files */
    long unknown_total;   /* over the sequence, counted when checking the inputs */
    long pair_holes;      /* of the new pair before the fill, both eyes over the sequence */
    const char *g_dataset_png; /* g from dataset files: "KITTI" or "Sintel" PNGs, "Spring" HDF5 (pixels), else NULL */
    double g_raw_min, g_raw_max; /* known g as read, before any unit conversion */
    double g_raw_median;  /* of the first frame's known g, as read */
    int causal_past, causal_future, causal_windows; /* the causal window (desc.causal) */
    float *f_ungated;          /* ... and its f before the gate (the solve's own; mid_causal_desc.ungated) */
    bool compute_saliency; /* no --saliency, --h or --uniform-saliency: the engine's computed saliency */
    float *saliency_scratch; /* 3 planes: depth and flow of one frame (computed saliency) */
    /* The flows in use (desc.flow resolved: never AUTO). Computed ones are
     * held for the last few pairs of frames (offline_read.c): pair (a, b) is
     * the flow of frame a to b (fwd) and of b to a (bwd), filled from the
     * nearest consistent pixel where the forward-backward check fails. */
    offline_flow flow;
    bool flow_direct;        /* each frame's flows go straight to its previous and next keyframe (given
                                with --flow-to keyframe; computed unless --flow-to frame), not to the
                                neighbouring frames */
    int flow_slots;          /* pairs held */
    int *flow_pair, *flow_pair_b; /* each slot's frames (first < second), -1: empty */
    unsigned long *flow_used; /* each slot's last use (the least recent is replaced) */
    float **flow_fwd, **flow_bwd;
    unsigned long flow_clock;
    long flow_computed;      /* pairs computed (a pair may be computed again in pass C) */
    double flow_occluded;    /* of the computed flows' pixels (both directions), how many failed the check */
    double flow_ms;          /* spent computing */
    /* desc.ema: each frame's range of known g (pass A), then smoothed
     * (offline_ema_ranges) into the range h maps from. */
    struct offline_range { float lo, hi; } *ema; /* one per frame */
    /* Scene cuts (offline_cuts.c): the first frame of each new shot. */
    struct offline_cut {
        int frame;
        float distance;      /* the histogram distance (NaN: named, not found) */
    } *cut;
    int cuts, cut_cap;
    double *cut_hist;        /* pass A: the last two frames' colour histograms */
    double cut_within_max;   /* the largest distance of frames left in one shot */
} offline_seq;

/* What pass C leaves for metrics.json, and the videos it writes into. */
typedef struct offline_outputs {
    float *slice_g, *slice_h, *slice_f; /* frames x width */
    float *f_key;                       /* coarse samples of the written f at keyframes (n) */
    long h_outside_range, f_outside_range; /* full-resolution samples outside the range */
    figure_video *video[3];             /* g.mp4, h.mp4, f.mp4 (NULL: none) */
    figure_video *pair_video[2];        /* the new pair packed (offline_stereo_name): .mp4, .mkv (NULL: none) */
    uint8_t *rgb;                       /* one video frame of a map */
    disp_tepe tepe[2];                  /* h and f against g, fed every frame (TEPE) */
    double tepe_v[2], tepe_a[2];        /* their means, kept when the frames are done */
} offline_outputs;

/* g in pixels: --g-units px, or a dataset's PNGs. */
static inline bool offline_g_in_px(const offline_seq *s)
{
    return !s->g_from_depth && (s->desc->g_units == DISP_G_PX || s->g_dataset_png);
}

/* offline_read.c: the inputs. */
vg_status offline_patterns_parse(offline_seq *s);
vg_status offline_frame_path(const disp_pattern *p, int t, char *buf);
vg_status offline_check_flows(offline_seq *s);
vg_status offline_validate(offline_seq *s);
vg_status offline_read_g(offline_seq *s, int t, float *out);
vg_status offline_read_h(offline_seq *s, int t, float *out);
vg_status offline_read_depth(offline_seq *s, int t, const float *g, float *z);
vg_status offline_read_flow(offline_seq *s, int t, bool next, float *out);
/* The frame the flow of frame t goes to: t +- 1, or with s->flow_direct
 * the nearest keyframe after (next) or before it. */
int offline_flow_target(const offline_seq *s, int t, bool next);
void offline_flow_free(offline_seq *s);
const char *offline_flow_name(offline_flow f);
vg_status offline_read_saliency(offline_seq *s, int t, float *out);
vg_status offline_read_ids(offline_seq *s, int t, float *out);
vg_status offline_read_image(offline_seq *s, int t, uint8_t **out);

/* offline_cuts.c: cuts named or found in pass A (begin, feed each frame's
 * colours in order, end); keyframes restart at each. */
#define OFFLINE_CUT_THRESHOLD 0.3
vg_status offline_cuts_begin(offline_seq *s);
vg_status offline_cuts_feed(offline_seq *s, int t, const uint8_t *rgb);
void offline_cuts_end(offline_seq *s);
void offline_cuts_free(offline_seq *s);
bool offline_is_cut(const offline_seq *s, int t);
int offline_keyframes(const offline_seq *s, int *numbers);

/* offline_video.c: --video's and --depth-video's frames decoded by ffmpeg
 * into s->video_dir (made by prepare, removed by remove) as frame_%d.png
 * and depth_%d.png. */
vg_status offline_video_prepare(offline_seq *s);
vg_status offline_video_decode(offline_seq *s);
void offline_video_remove(offline_seq *s);

/* offline_solve.c: the method. */
vg_status offline_operator_create(offline_seq *s);
/* offline_ema.c, desc.ema: record frame t's range of g (pass A, in order);
 * smooth them all; h of frame t from them. */
vg_status offline_ema_record(offline_seq *s, int t, double lo, double hi);
vg_status offline_ema_ranges(offline_seq *s);
void offline_ema_apply(const offline_seq *s, int t, const float *g, float *h);
vg_status offline_window_build(offline_seq *s, mid_window **w);
vg_status offline_solve(offline_seq *s, mid_window *w, float *f_sol, mid_solve_stats *ss);
vg_status offline_upsample(offline_seq *s, const mid_window *w, const float *f_sol, offline_outputs *o);

/* offline_write.c: the result in --out. */
vg_status offline_check_out_dir(offline_seq *s);
vg_status offline_outputs_alloc(const offline_seq *s, int samples, offline_outputs *o);
void offline_outputs_free(offline_outputs *o);
vg_status offline_videos_open(const offline_seq *s, offline_outputs *o);
void offline_videos_close(offline_outputs *o);
vg_status offline_write_frame(offline_seq *s, int t, float *g, float *h, float *f, const float *z,
                              offline_outputs *o);
vg_status offline_write_results(offline_seq *s, const mid_window *w, const float *f_sol, const offline_outputs *o,
                                const mid_solve_stats *ss);
