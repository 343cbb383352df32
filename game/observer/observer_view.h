/* vergence — what the display shows the simulated observer: the vergence a
 * moving object is given under g, h or f, computed with the CPU reference
 * of the engine's passes instead of a GPU frame (docs/game.md).
 *
 *   g  the original rig (engine/stereo) at the object's centre depth;
 *   h  the operator (engine/disparity/disp_operator) run on every frame's
 *      whole g image: a small software render of the static scene (depth
 *      and saliency, once) with the object splatted in as a disc, so a
 *      histogram operator sees what the frame's operator would;
 *   f  the MID optimiser (mid_window + mid_solve, paper Sec. 4.3) over the
 *      object's own trajectory: its keyframe samples linked by its motion
 *      (a Lagrangian window, flows zero), then f/h interpolated between
 *      keyframes as the temporal upsampling does (paper Sec. 4.4). The
 *      static surround keeps f = h there (no motion, nothing to restore).
 * Deterministic: no threads, no GPU. */
#pragma once
#include "frame/frame_desc.h"
#include "scene/scene.h"
#include "stereo/stereo_display.h"
#include "disparity/disp_operator.h"

typedef struct observer_view_desc {
    const scene *scene;
    int camera;                   /* camera node (as frame_desc.camera) */
    int moving_node;              /* the object the observer follows (not rendered statically) */
    int width, height;            /* the observer's image, 0 = 160 x 90 */
    stereo_display_desc display;  /* zero = the paper's display */
    stereo_camera_desc rig;       /* zero = FRAME_DEFAULT_INTERAXIAL / _CONVERGENCE */
    disp_operator_kind op;        /* 0 = lang */
    disp_operator_preset preset;  /* 0 = comfort; the studies use DISP_PRESET_STUDY */
    double range;                 /* operator half range, arcmin, 0 = preset */
    double fps;                   /* 0 = 60 */
    int keyframe_stride;          /* 0 = 10 (paper 4.4) */
} observer_view_desc;

typedef struct observer_view observer_view;

/* What a display showed of a track, when it is not this CPU view's model
 * (observer_engine: the engine's frames). */
typedef struct observer_shown {
    const double *offset;     /* per frame: the object's displayed minus original vergence, arcmin */
    int count;
    const float *surround;    /* the last frame's displayed minus original vergence per pixel, arcmin */
    int width, height;        /* of surround (the frame's size; [0,1] image coordinates map onto it) */
} observer_shown;

vg_status observer_view_create(const observer_view_desc *desc, observer_view **out);
void observer_view_destroy(observer_view *v);

const vg_camera *observer_view_camera(const observer_view *v);
const stereo_display *observer_view_display(const observer_view *v);
const stereo_camera *observer_view_rig(const observer_view *v);
double observer_view_radius(const observer_view *v);    /* the moving object's bounding radius, m */
int observer_view_keyframe_stride(const observer_view *v);

/* Displayed vergence (arcmin) of the moving object whose centre is at
 * pos[i] in frame i (count frames at the fixed step), for `mode`. */
vg_status observer_view_track(observer_view *v, const double (*pos)[3], int count, frame_mode mode,
                              double *vergence);
/* Displayed vergence of a static surface point at view depth z, seen at
 * image position (u, v), under the mapping of the last frame
 * observer_view_track processed, or, given `shown`, the displacement its
 * last frame had at that pixel (the nearest one inside the image). */
double observer_view_surround(const observer_view *v, const observer_shown *shown, frame_mode mode, double depth_m,
                              double u, double vv);
