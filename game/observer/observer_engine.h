/* vergence — what the engine shows the simulated observer: a moving
 * object's displayed vergence read back from a headless frame's own maps,
 * made with the window, passes and size the study's frames use (issue 18:
 * the observer's f is the engine's f, not a CPU model's).
 *
 * Per frame, the object's displacement from its original vergence is the
 * mean of (map - g) over the pixels whose instance id is the object's
 * (the warp moves each of its vertices by the map at its pixel); the last
 * frame's per-pixel displacement is kept for the surround (where the
 * observer decodes the ground). The observer adds these to the exact g of
 * the object's centre and of the ground (observer_view), so g itself is
 * decoded without the bias of the object's front surface. Mode g needs no
 * frame: its displacement is zero by definition (and the frame's g map
 * equals the rig's, tested elsewhere). */
#pragma once
#include "frame/frame.h"
#include "observer_view.h"

typedef struct observer_engine_desc {
    gpu *gpu;
    const scene *scene;           /* its pose hook (if any) moves the object; the caller's */
    int moving_node;
    frame_desc frame;             /* the study's frame of any mode (mode, readback and maps_only are set here) */
    int lead_keyframes;           /* keyframes rendered before `first` after the restart (a throw: 1, the
                                     ball resting at its start in the window, as play's window has it) */
} observer_engine_desc;

typedef struct observer_engine observer_engine;

/* The instance ids of scene node `node` (what the G-buffer's id image
 * shows of it), 0-terminated; free() them. */
uint32_t *observer_node_ids(const scene *s, int node);
bool observer_is_node_id(const uint32_t *ids, uint32_t id);
/* A game frame of `mode` made to be read, not shown: its maps come back
 * (readback, maps only: the G-buffer and disparity passes), no eyes, no
 * overlay, no reference, no measures, no present. */
frame_desc observer_maps_frame(const frame_desc *game, frame_mode mode);

vg_status observer_engine_create(const observer_engine_desc *desc, observer_engine **out);
void observer_engine_destroy(observer_engine *e);

/* Renders frames first, first + step, ... (count of them) of `mode` after a
 * restart of the frame's window (as a throw or a clip starts it) and the
 * desc's lead keyframes, and
 * fills *shown (valid until the next call). A frame where the object covers
 * no pixel keeps the previous frame's displacement (0 before the first). */
vg_status observer_engine_track(observer_engine *e, frame_mode mode, long first, int step, int count,
                                observer_shown *shown);
