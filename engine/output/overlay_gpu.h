/* vergence — overlays: the HUD drawn into each eye before the eyes are
 * composed, so that every layout shows it once and whole, at a parallax of
 * its own (frame_hud.parallax; screen depth by default).
 *
 *   overlay.left, overlay.right  (graphics) text panels, banner and badge,
 *                                 alpha-blended, on res->left / res->right
 *
 * The eye images the frame reads back (captures) then hold the overlay too:
 * a headless frame draws one only when asked (frame_desc.overlay). */
#pragma once
#include "pass/frame_ctx.h"

typedef struct overlay_gpu overlay_gpu;

vg_status overlay_gpu_create(frame_ctx *fc, overlay_gpu **out);
void overlay_gpu_destroy(overlay_gpu *o);
/* Declares the two passes, between the warp and compose. */
void overlay_gpu_add(overlay_gpu *o, rg_graph *g, frame_resources *res);
/* Builds this frame's geometry (slot = frame_ctx slot); NULL draws nothing. */
void overlay_gpu_update(overlay_gpu *o, const frame_hud *hud);
