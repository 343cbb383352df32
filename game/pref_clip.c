/* vergence — a preference trial's clips. */
#include "pref_clip.h"

#include <math.h>

#include "core/log.h"
#include "frame/frame.h"
#include "game.h"

frame_desc pref_clip_frame_desc(const gpu *g, const pref_clip_desc *d)
{
    frame_desc fd = {
        .width = d->width, .height = d->height, .fps = 60, .keyframe_stride = 10, .readback = true,
        .display = d->display, .stereo = FRAME_STEREO_WARP, .mode = d->mode, .compose = d->compose,
        .op = d->op, .op_preset = DISP_PRESET_STUDY,
    };
    game_frame_defaults(g, d->tess_error, &fd);
    return fd;
}

int pref_clip_frames(const scene *s) { return (int)floor(s->duration * 60.0 / PREF_CLIP_STEP) + 1; }

vg_status pref_clip_render(gpu *g, const scene *s, const frame_desc *fd, pref_clip_fn on_frame, void *user)
{
    frame *f;
    int errors = vg_log_error_count();
    vg_status st = frame_create(g, s, fd, &f);
    if (st != VG_OK) {
        if (vg_log_error_count() == errors)
            vg_error("the preference study shows the %s version beside the others; this build cannot render it",
                     frame_mode_names[fd->mode]);
        return st;
    }
    bool stop = false;
    for (int k = 0, n = pref_clip_frames(s); k < n && st == VG_OK && !stop; k++) {
        /* The frame's solve does not depend on which indices are rendered
         * (disparity_gpu_prepare): every 2nd frame shows the f of all. */
        if ((st = frame_render(f, (long)k * PREF_CLIP_STEP)) == VG_OK)
            st = on_frame(user, k, frame_get_outputs(f), &stop);
    }
    frame_destroy(f);
    return st;
}
