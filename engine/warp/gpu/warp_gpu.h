/* vergence — the stereo pair (DESIGN.md steps 8-9, paper 4.6).
 *
 *   warp.curve.*   global depth -> vergence curve of the target map
 *   warp.left/right      tessellated 3D vertex warping with the cascade
 *   cameras.left/right   two real off-axis cameras of the original rig
 *   imagewarp.left/right forward image warping with a z-buffer
 *   reference.left/right the two-camera render as ground truth (desc.reference)
 *
 * Reads the G-buffer and the target map selected by the mode; fills
 * res->curve, left, right, left_aux, right_aux (and ref_left/right). */
#pragma once
#include "pass/frame_ctx.h"

typedef struct warp_gpu warp_gpu;

typedef struct warp_gpu_desc {
    frame_stereo stereo;         /* how the pair is made (not FRAME_STEREO_OFF) */
    bool measure;                /* the eyes' disparity error per pixel (aux.z), the two cameras' too */
    bool reference;              /* the two-camera reference eyes too */
    uint32_t max_tess_level;     /* within the device's limit */
    const struct vgx_curve_data *curve; /* a baked global curve instead of each frame's (copied) */
} warp_gpu_desc;

vg_status warp_gpu_create(frame_ctx *fc, const warp_gpu_desc *desc, warp_gpu **out);
void warp_gpu_destroy(warp_gpu *w);
void warp_gpu_add(warp_gpu *w, rg_graph *g, frame_resources *res, rg_res target);
/* Each frame before recording: binds the module's imported resources (a
 * baked curve) and takes the frame's camera (the curve's background). */
void warp_gpu_bind(warp_gpu *w, rg_graph *g);

/* Eye attachments. */
#define WARP_COLOR_FORMAT VK_FORMAT_R8G8B8A8_UNORM
#define WARP_AUX_FORMAT VK_FORMAT_R32G32B32A32_SFLOAT

/* Largest tessellation level that keeps one draw under lavapipe's
 * 65,535-vertex limit for WARP_PATCHES_PER_DRAW patches (PLATFORM.md). */
#define WARP_MAX_LEVEL 64
#define WARP_PATCHES_PER_DRAW 16
