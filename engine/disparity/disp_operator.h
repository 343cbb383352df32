/* vergence — disparity manipulation operators h = M(g, saliency), per frame.
 *
 *   none           h = g
 *   linear         scale about the screen vergence a_s until [min g, max g] fits the
 *                  target range; the identity when it already fits
 *   lang           after Lang et al. 2010: a saliency-weighted histogram of g; the
 *                  mapping's slope in each bin is floor + importance (monotone),
 *                  integrated and scaled onto the interval the linear operator would
 *                  produce; no temporal smoothing (the paper's study, Sec. 5)
 *   lang-smoothed  lang with first-order temporal smoothing of the mapping
 *                  (exponential, time constant smooth_seconds): the usual baseline
 * The target range is a_s +- range (arcmin); the `study` preset compresses
 * harder, as the paper's study did ("larger than what the display would require").
 * Equations: docs/method.md. */
#pragma once
#include "core/parallel.h"
#include "core/status.h"

typedef enum disp_operator_kind {
    DISP_OPERATOR_DEFAULT = 0, /* lang */
    DISP_OPERATOR_NONE,
    DISP_OPERATOR_LINEAR,
    DISP_OPERATOR_LANG,
    DISP_OPERATOR_LANG_SMOOTHED,
} disp_operator_kind;

typedef enum disp_operator_preset {
    DISP_PRESET_DEFAULT = 0, /* comfort: +-60 arcmin (the 1 degree rule), floor 0.1 */
    DISP_PRESET_STUDY,       /* +-30 arcmin, floor 0.02 */
} disp_operator_preset;

typedef struct disp_operator_desc {
    disp_operator_kind kind;
    disp_operator_preset preset;
    double screen_vergence;  /* a_s, arcmin (required) */
    double range;            /* half-width of the target range, arcmin; 0 = preset */
    double in_min, in_max;   /* domain of the mapping; both 0 = each frame's min/max of g */
    int bins;                /* histogram bins, 0 = 128 */
    double floor;            /* slope floor of an empty bin, relative to a uniform bin; 0 = preset */
    double blur_bins;        /* Gaussian blur of the importance, in bins; 0 = 1.5 */
    double saliency_floor;   /* pixel weight = saliency_floor + saliency; 0 = 0.1 */
    double smooth_seconds;   /* lang-smoothed time constant, 0 = 0.5 s */
    double frame_seconds;    /* time between calls, 0 = 1/60 s */
} disp_operator_desc;

typedef struct disp_operator disp_operator;

/* desc with every zero field at its default (kind lang, the preset's range
 * and floor, 128 bins, ...): the one resolution the CPU operator and the GPU
 * pass (operator_gpu) both make. */
disp_operator_desc disp_operator_desc_defaults(const disp_operator_desc *desc);
vg_status disp_operator_create(const disp_operator_desc *desc, disp_operator **out);
void disp_operator_destroy(disp_operator *op);
/* Forgets the temporal state (lang-smoothed starts again at the next frame). */
void disp_operator_reset(disp_operator *op);
/* h for one frame of n pixels; saliency in [0,1] or NULL (uniform). */
void disp_operator_apply(disp_operator *op, const float *g, const float *saliency, int n, float *h,
                         vg_pool *pool);
/* The target range [lo, hi] in arcmin; for `none` with a fixed domain, the
 * hull of the target range and the domain (nothing is compressed). */
void disp_operator_range(const disp_operator *op, double *lo, double *hi);
/* The mapping of the last applied frame at vergence x (for tests and plots). */
double disp_operator_map(const disp_operator *op, double x);
/* Names by kind: [0] names what DISP_OPERATOR_DEFAULT stands for ("lang"),
 * then "none", "linear", "lang", "lang-smoothed"; NULL-terminated. */
extern const char *const disp_operator_names[];
/* Parses "none", "linear", "lang", "lang-smoothed"; returns DISP_OPERATOR_DEFAULT if unknown. */
disp_operator_kind disp_operator_kind_parse(const char *name);
const char *disp_operator_kind_name(disp_operator_kind kind);
