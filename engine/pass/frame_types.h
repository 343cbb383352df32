/* vergence — the frame's types, shared by the frame (frame/frame.h) and
 * every pass module (the pass kit, pass/frame_ctx.h): the enums of how a
 * stereo frame is made and shown (each pass module's desc takes the ones it
 * renders), the frame's times, what it hands back (frame_outputs) and the
 * HUD a windowed frame draws. Pure data, and pure functions over it
 * (frame_types.c). What an application asks a frame for, the disparity
 * pipeline's settings among it, is frame/frame_desc.h. */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "gpu/gpu.h"
#include "stereo/stereo_display.h"

/* Frames the engine records ahead of the GPU: per-frame buffers have a copy
 * each (the frame's constants, the scene's moving vertices). */
#define VG_FRAMES_IN_FLIGHT 2

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
    FRAME_COMPOSE_TB_HALF,       /* top-bottom, half height each (W x H: 3D TVs' "top and bottom") */
    FRAME_COMPOSE_ANAGLYPH_GREEN_MAGENTA, /* green left, magenta right, Dubois' matrices */
    FRAME_COMPOSE_ANAGLYPH_AMBER_BLUE,    /* amber left, blue right (ColorCode 3-D), Dubois' matrices */
    FRAME_COMPOSE_FRAME_PACKING, /* HDMI 1.4a frame packing: left above right, H/24 blank rows between (1080p: 1920x2205) */
    FRAME_COMPOSE_CROSS_EYED,    /* side by side with the right eye on the left, for free viewing cross-eyed */
    FRAME_COMPOSE_COUNT,
} frame_compose;

/* Names as on the command line ("sbs", "anaglyph-plain", ...), NULL-terminated. */
extern const char *const frame_compose_names[];
extern const char *const frame_stereo_names[];
extern const char *const frame_mode_names[];

#define FRAME_PROBE_MAX_IDS 8
#define FRAME_PROBES_KEPT 4      /* completed probes a frame keeps until frame_take_probes */

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
    const struct vgx_curve_data *curve; /* the global depth -> vergence curve the warp used */
    /* The shadow cascades' texels in world metres (0: the whole scene, 1: near the camera; their
     * sharpness: capture.json "shadow") and the view depth below which cascade 1 shades (0: none). */
    float shadow_texel_m[2], shadow_split_m;
} frame_outputs;

/* What the probe measured in one frame (desc.probe_ids): how the frame
 * showed those instances in depth, beside g. */
typedef struct frame_probe {
    long index;                  /* the frame */
    uint32_t pixels;             /* pixels of the probed instances */
    double shown_minus_g;        /* mean over them of (the shown map - g), arcmin; 0 with no pixel */
} frame_probe;

/* The times a frame was rendered at. */
typedef struct frame_times {
    long index;                  /* absolute frame number */
    long prev_key, next_key;     /* neighbouring keyframes (frame numbers, strictly before/after) */
    double t, t_prev, t_next;    /* seconds */
} frame_times;

/* A windowed frame's target: an acquired swapchain image; wait is signalled
 * by the acquire, signal is what vkQueuePresentKHR waits on. */
typedef struct frame_target {
    VkImage image;
    VkImageView view;
    VkSemaphore wait, signal;
} frame_target;

#define FRAME_HUD_MAX_LINES 24
#define FRAME_HUD_LINE 96
#define FRAME_HUD_MAX_MARKERS 4

/* A marker at a point of the centre image: a cross (where the player
 * clicked) or a box (the true landing spot), with a label under it. */
typedef enum frame_hud_shape {
    FRAME_HUD_CROSS,
    FRAME_HUD_BOX,
} frame_hud_shape;

typedef struct frame_hud_marker {
    float u, v;                  /* centre image, 0..1 */
    frame_hud_shape shape;
    uint8_t rgb[3];
    char label[24];
} frame_hud_marker;

/* A small line chart at the top right of each eye, under the badge (the
 * game's trace of the ball after a throw): series of points in the plot's
 * units, the ranges x0..x1 and y0..y1 (y0 < 0 < y1 draws the zero line),
 * a title over the plot and a caption under it. */
#define FRAME_HUD_CHART_SERIES 2
#define FRAME_HUD_CHART_POINTS 64

typedef struct frame_hud_series {
    int count;
    float x[FRAME_HUD_CHART_POINTS], y[FRAME_HUD_CHART_POINTS];
    uint8_t rgb[3];
    char label[24];              /* the legend */
} frame_hud_series;

typedef struct frame_hud_chart {
    bool visible;
    char title[64], caption[64];
    float x0, x1, y0, y1;
    int series_count;
    frame_hud_series series[FRAME_HUD_CHART_SERIES]; /* the last is drawn on top */
} frame_hud_chart;

/* Text drawn into each eye before the eyes are composed (output/overlay_gpu.c),
 * so every layout shows it once and whole: a panel of lines at the top
 * left (lines[0] the title), a banner in the middle, a badge at the top
 * right, markers at points of the picture, a chart under the badge. It
 * stands at `parallax` eye pixels (left eye shifted by -p/2, right by +p/2:
 * positive behind the screen, negative in front; 0 = screen depth). */
typedef struct frame_hud {
    bool visible;
    int line_count;
    char lines[FRAME_HUD_MAX_LINES][FRAME_HUD_LINE];
    float scale;                 /* eye pixels per font pixel, 0 = from the eye width (1 per 480) */
    /* A banner in the middle of the picture (pause, feedback), empty for none. */
    char banner[FRAME_HUD_LINE];
    /* A badge at the top right (the game's mode), empty for none; its colour. */
    char badge[32];
    uint8_t badge_rgb[3];
    int marker_count;
    frame_hud_marker markers[FRAME_HUD_MAX_MARKERS];
    float parallax;              /* eye pixels, 0 = screen depth */
    frame_hud_chart chart;
} frame_hud;

/* The keyframe interval a frame is in: floor(index / stride), also below 0. */
long frame_keyframe_of(long index, int stride);
/* Keyframe times around a frame number. */
frame_times frame_times_at(long index, double fps, int stride);
/* Where each eye lies in the composed output: a packed layout gives each
 * eye a rectangle of the output (squeezed to half width or height by the
 * half layouts), the others lay both eyes over the whole output
 * (interleaved, anaglyph, one eye): `overlaid`. Eye 0 is the left eye; with
 * swap_eyes the eyes exchange places. What draws on the output (a click's
 * eye pixel, a study's labels) reads the places from here. */
typedef struct frame_eye_rect {
    uint32_t x, y, w, h;
} frame_eye_rect;

typedef struct frame_layout {
    uint32_t width, height;      /* the output */
    frame_eye_rect eye[2];       /* left, right */
    bool overlaid;
} frame_layout;

frame_layout frame_compose_layout(frame_compose mode, bool swap_eyes, uint32_t width, uint32_t height);
/* The eye size whose composed output fills out_w x out_h (frame packing's
 * blank band: about), e.g. a window's. */
void frame_compose_eye_size(frame_compose mode, uint32_t out_w, uint32_t out_h, double *eye_w, double *eye_h);
/* Output size of a layout for eyes of width x height. */
void frame_compose_size(frame_compose mode, uint32_t width, uint32_t height, uint32_t *out_w, uint32_t *out_h);
