/* vergence — what a stereo capture measures (issue 5), from the readback:
 *
 *   cascade        fraction of geometry pixels (both eyes) whose vertices took
 *                  their disparity from each stage
 *   warp error     achieved minus target disparity in pixels, per fragment:
 *                  the eye shader knows its own position and the centre-view
 *                  position of the surface point it shows, so the achieved
 *                  disparity is twice their horizontal offset, and the target
 *                  is the cascade at the centre-view position
 *   holes          pixels where the two-camera reference shows geometry, away
 *                  from its silhouettes (all 8 neighbours are geometry too),
 *                  and the method left empty (nothing drawn: image warping's
 *                  disocclusions) or tore open (sky between geometry of one
 *                  surface, where the centre view shows that surface). Sky
 *                  the centre view shows too, or sky between objects at
 *                  different depths, is not a hole: under h or f silhouettes
 *                  rightly move against each other, away from where the
 *                  cameras (which show g) put them.
 *   cracks         eye pixels that show something farther than the surface
 *                  on both sides of them (across, one or two pixels wide:
 *                  the sky or the scene behind seen through the surface)
 *                  where the centre view shows that surface unbroken: the
 *                  speckles of a warp that is not watertight. Needs no
 *                  reference, so every mode is measured
 *   speckles       eye geometry pixels that stand out from their neighbours
 *                  where the centre view, at the place their surface point
 *                  comes from, has no such detail: the dots a wrong eye
 *                  shows, whatever made it wrong
 *   silhouette     with the reference (g only: the cameras show g): of its
 *                  silhouette pixels, the fraction the eye covers otherwise
 *                  (geometry for sky or the reverse): ragged edges
 *   PSNR           of each eye against the two-camera reference, in dB */
#pragma once
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"
#include "pass/frame_types.h"

/* Two depths within this fraction belong to one surface. */
#define WARP_SAME_SURFACE 0.02f
/* An eye pixel this far (luma, of 255) from the centre view's colour at its
 * surface point, its neighbours within a third of it, is a speckle. */
#define WARP_SPECKLE_LUMA 40

typedef struct warp_metrics {
    /* accumulated */
    uint64_t stage_pixels[5];          /* VGX_STAGE_NONE .. VGX_STAGE_CURVE */
    float *errors, *errors_curve;      /* |error| samples (grown as needed) */
    size_t error_count, error_cap, curve_count, curve_cap;
    uint64_t reference_geometry, holes;
    uint64_t crack_pixels, crack_frame_max; /* both eyes; the most of one eye of one frame */
    uint64_t speckle_pixels;
    uint64_t silhouette_pixels, silhouette_flips;
    double sq_error[2];                /* sum of squared 8-bit RGB differences per eye */
    uint64_t samples[2];
    /* results of warp_metrics_finish */
    double stage_fraction[5];
    double error_median, error_p99, error_p99_curve;
    double hole_fraction;
    double crack_fraction;             /* of the eyes' geometry pixels */
    double speckle_fraction;           /* of the eyes' geometry pixels */
    double silhouette_mismatch;        /* NAN without a reference */
    double psnr[2];                    /* left, right; INFINITY when identical */
} warp_metrics;

/* Adds one frame (outputs must hold the stereo readback; the reference is optional). */
vg_status warp_metrics_add(warp_metrics *m, const frame_outputs *o, uint32_t width, uint32_t height);
void warp_metrics_finish(warp_metrics *m);
void warp_metrics_free(warp_metrics *m);

/* Peak signal-to-noise ratio of two RGBA8 images over RGB, in dB. */
double warp_psnr(const uint8_t *a, const uint8_t *b, size_t pixels);
