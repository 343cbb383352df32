/* vergence — dense optical flow between two images, for footage that comes
 * without flow files (`vergence optimize` without --flow-next/--flow-prev).
 *
 * flow.cpp: OpenCV's DIS optical flow (Kroeger et al., "Fast Optical Flow
 * using Dense Inverse Search", ECCV 2016; cv::DISOpticalFlow of Debian's
 * OpenCV 4.6), the project's second and last C++ file behind this C API.
 * flow.c: the forward-backward consistency check that marks the pixels
 * whose flow cannot be trusted (occluded, or leaving the frame), in C.
 *
 * A flow is 2 floats per pixel, row-major, top row first, (u, v) in pixels
 * (x right, y down), as Middlebury's .flo and core/io.h's vg_imagef hold
 * them: the pixel (x, y) of the first image shows what the second shows at
 * (x + u, y + v). */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "core/status.h"

/* DIS's presets (cv::DISOpticalFlow::PRESET_*), and FINE: MEDIUM refined
 * down to full resolution (finest scale 0; MEDIUM stops at half, FAST and
 * ULTRAFAST at a quarter). FINE is the default: the offline tool has time
 * (about 3x MEDIUM's), and small moving objects, which a coarse sample of
 * the solver's grid must follow, are lost at half resolution: on a balloon
 * capture optimize's f came within 3 % of the MID distortion that exact
 * flows give with FINE, 29 % above it with MEDIUM (docs/formats.md). */
typedef enum flow_preset {
    FLOW_PRESET_FINE = 0,
    FLOW_PRESET_MEDIUM,
    FLOW_PRESET_FAST,
    FLOW_PRESET_ULTRAFAST,
} flow_preset;

const char *flow_preset_name(flow_preset p);

/* An 8-bit image: channels 1 (grey), 3 (RGB) or 4 (RGBA, alpha ignored),
 * row-major, top row first, rows packed. Colour is turned to grey (BT.601
 * luma on the stored values) before the flow. */
typedef struct flow_image {
    const uint8_t *pixels;
    int width, height, channels;
} flow_image;

/* DIS has patches of up to 12 pixels and a pyramid: smaller images are refused. */
#define FLOW_MIN_SIDE 16

/* Flow from a to b (fwd) and, when bwd is not NULL, from b to a; each
 * width x height x 2 floats. Images of different sizes, too small, of
 * another channel count or without pixels are refused with one error line
 * (VG_ERR_ARG); an OpenCV failure is one line too (VG_ERR_UNSUPPORTED, or
 * VG_ERR_NOMEM), never an exception or an abort. `what` names the pair in
 * the messages ("frames 3 and 4"). */
vg_status flow_dis(const flow_image *a, const flow_image *b, flow_preset preset, const char *what, float *fwd,
                   float *bwd);

/* OpenCV's worker threads for the flows that follow, process-wide (n <= 0:
 * its default, every core). */
void flow_set_threads(int n);

/* The forward-backward consistency check of Sundaram, Brox and Keutzer
 * ("Dense point trajectories by GPU-accelerated large displacement optical
 * flow", ECCV 2010, Sec. 4.1, eq. 5): a pixel x is occluded (or its flow
 * wrong) when the backward flow at x + w(x), bilinearly interpolated, does not
 * bring it back:
 *     |w + w^|^2 > FLOW_CHECK_REL (|w|^2 + |w^|^2) + FLOW_CHECK_ABS,
 *     w = fwd(x), w^ = bwd(x + w)
 * (their 0.01 and 0.5 px^2: about 0.7 px plus 14 % of the flow's length).
 * x + w outside the frame counts as occluded too (no pixel of the other
 * image). occluded (width x height bytes, 1 = occluded) may be NULL;
 * returns the number of occluded pixels. Non-finite flows are occluded. */
#define FLOW_CHECK_REL 0.01f
#define FLOW_CHECK_ABS 0.5f
long flow_occlusions(const float *fwd, const float *bwd, int width, int height, uint8_t *occluded);

/* Each occluded pixel's flow replaced by that of the nearest kept pixel of
 * its row (the right one on a tie); NaN on a row with none. */
void flow_fill_occluded(float *flow, const uint8_t *occluded, int width, int height);

/* Mean end-point error |a - b| (pixels) over the pixels where mask is
 * NULL or 0; *count (may be NULL) receives how many. NAN when none. */
double flow_epe(const float *a, const float *b, int width, int height, const uint8_t *mask, long *count);
