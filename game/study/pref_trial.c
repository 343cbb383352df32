/* vergence — a preference trial: its design and its clips. */
#include "pref_trial.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/log.h"
#include "frame/frame.h"
#include "rules/game.h"

/* ------------------------------------------------------------------------- */
/* Design                                                                    */
/* ------------------------------------------------------------------------- */

const char *const pref_scene_names[PREF_SCENES] = {"balloon", "cubes", "arena"};
const char *const pref_saliency_names[2] = {"moving", "static"};

/* Cell c: scene (3) x saliency (2) x side of the optimized version (2). */
pref_cell pref_cell_of(int c)
{
    return (pref_cell){.scene = c / 4, .saliency = (c / 2) % 2, .optimized_right = c % 2};
}

/* ------------------------------------------------------------------------- */
/* Scenes: the moving object, the saliency variant, its track                */
/* ------------------------------------------------------------------------- */

/* The moving object: the node an animation translates (one per scene). */
int pref_moving_node(const scene *s)
{
    for (int c = 0; c < s->channel_count; c++)
        if (s->channels[c].path == SCENE_PATH_TRANSLATION)
            return s->channels[c].node;
    return -1;
}

/* Saliency on the static objects instead: the landmarks get the moving
 * object's weight and it gets theirs (ground and sky stay as they are). */
void pref_saliency_apply(scene *s, int moving, int variant)
{
    if (variant == 0)
        return;
    for (int i = 0; i < s->instance_count; i++) {
        scene_instance *in = &s->instances[i];
        if (in->node == moving)
            in->saliency = 0.1f;
        else if (in->saliency >= 0.2f)
            in->saliency = 1.0f;
    }
}

vg_status pref_scene_path(const char *arena_path, int scene_index, char *out, size_t cap)
{
    /* The three scenes sit together in content/. */
    const char *slash = strrchr(arena_path, '/');
    int dir = slash ? (int)(slash - arena_path + 1) : 0;
    int n = snprintf(out, cap, "%.*s%s.gltf", dir, arena_path, pref_scene_names[scene_index]);
    return n > 0 && (size_t)n < cap ? VG_OK : VG_ERR_ARG;
}

/* ------------------------------------------------------------------------- */
/* Clips                                                                     */
/* ------------------------------------------------------------------------- */

void pref_panel_size(bool cpu, int ew, int eh, int *pw, int *ph)
{
    int w = (ew - 2 * PREF_GAP) / 3, h = w * 9 / 16;
    if (h > eh - 64) {
        h = eh - 64;
        w = h * 16 / 9;
    }
    if (cpu && w > 320) {
        w = 320;
        h = 180;
    }
    *pw = w & ~1, *ph = h & ~1;
}

frame_desc pref_clip_frame_desc(const gpu *g, const pref_clip_desc *d)
{
    frame_desc fd = game_frame_desc(g, d->tess_error, d->mode, d->width, d->height, d->compose, d->op, true, NULL);
    fd.readback = true;
    fd.display = d->display;
    fd.swap_eyes = d->swap_eyes;
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
