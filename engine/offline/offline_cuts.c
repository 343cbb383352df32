/* vergence — scene cuts in `vergence optimize`: where one shot ends and the
 * next begins, so that the jump of g across a cut never becomes motion in
 * depth. A cut restarts the window: the keyframes restart at the cut's
 * frame (the shot before it ends on one), the keyframe flows across the cut
 * are lost (no velocity or acceleration term links the two shots), the
 * operator's temporal state and the TEPE history are reset there.
 *
 * Detected (--scene-cuts auto) from the colour frames: the distance of
 * consecutive frames' joint RGB histograms, 4 bins a channel (half the L1
 * distance of the normalised histograms: 0 for the same colours, 1 for
 * disjoint ones). A cut in footage changes what the picture shows at once,
 * where motion within a shot moves few pixels across bins; the threshold
 * and the figures that chose it are in docs/formats.md. */
#include "offline_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"

#define CUT_BINS 4 /* per channel */
#define CUT_HIST (CUT_BINS * CUT_BINS * CUT_BINS)

const char *offline_cuts_name(offline_cuts c)
{
    return c == OFFLINE_CUTS_NONE ? "none" : c == OFFLINE_CUTS_GIVEN ? "given" : "auto";
}

static vg_status cut_add(offline_seq *s, int t, float dist)
{
    if (s->cuts == s->cut_cap) {
        int cap = s->cut_cap ? 2 * s->cut_cap : 8;
        struct offline_cut *c = realloc(s->cut, (size_t)cap * sizeof *c);
        if (!c)
            return VG_ERR_NOMEM;
        s->cut = c;
        s->cut_cap = cap;
    }
    s->cut[s->cuts++] = (struct offline_cut){t, dist};
    return VG_OK;
}

vg_status offline_cuts_begin(offline_seq *s)
{
    const offline_desc *d = s->desc;
    s->cut_within_max = 0;
    if (d->flow_to_keyframe && d->scene_cuts == OFFLINE_CUTS_GIVEN) {
        vg_error("optimize: --scene-cuts with flows to the keyframes: those keyframes are fixed (one shot)");
        return VG_ERR_ARG;
    }
    if (d->flow_to_keyframe || d->scene_cuts == OFFLINE_CUTS_NONE)
        return VG_OK;
    for (int i = 0; d->scene_cuts == OFFLINE_CUTS_GIVEN && i < d->cut_count; i++) {
        int t = d->cut_frames[i];
        if (t <= d->first || t > d->last || (i && t <= d->cut_frames[i - 1])) {
            vg_error("optimize: --scene-cuts: frame %d is not %s (a cut names the first frame of a new shot, "
                     "in increasing order)", t, i && t <= d->cut_frames[i - 1] ? "after the cut before it"
                                                                             : "within --frames after its first");
            return VG_ERR_ARG;
        }
        vg_status st = cut_add(s, t, NAN);
        if (st != VG_OK)
            return st;
    }
    if (d->scene_cuts == OFFLINE_CUTS_AUTO && s->has_image &&
        !(s->cut_hist = malloc(2 * CUT_HIST * sizeof(double))))
        return VG_ERR_NOMEM;
    if (d->scene_cuts == OFFLINE_CUTS_AUTO && !s->has_image)
        vg_info("optimize: scene cuts are found in the colour frames: without --image or --video none are looked "
                "for (name them with --scene-cuts N,N,...)");
    return VG_OK;
}

/* Frame t's colours (pass A, in frame order): a cut before t when its
 * histogram is far from frame t - 1's. */
vg_status offline_cuts_feed(offline_seq *s, int t, const uint8_t *rgb)
{
    const offline_desc *d = s->desc;
    if (!s->cut_hist || !rgb)
        return VG_OK;
    size_t np = (size_t)s->width * s->height;
    double *cur = s->cut_hist + ((t - d->first) % 2) * CUT_HIST;
    const double *prev = s->cut_hist + ((t - d->first + 1) % 2) * CUT_HIST;
    memset(cur, 0, CUT_HIST * sizeof(double));
    for (size_t i = 0; i < np; i++) {
        const uint8_t *p = rgb + 3 * i;
        cur[(p[0] * CUT_BINS / 256 * CUT_BINS + p[1] * CUT_BINS / 256) * CUT_BINS + p[2] * CUT_BINS / 256] +=
            1.0 / (double)np;
    }
    if (t == d->first)
        return VG_OK;
    double dist = 0;
    for (int b = 0; b < CUT_HIST; b++)
        dist += fabs(cur[b] - prev[b]);
    dist *= 0.5;
    double threshold = d->cut_threshold > 0 ? d->cut_threshold : OFFLINE_CUT_THRESHOLD;
    if (dist <= threshold) {
        s->cut_within_max = fmax(s->cut_within_max, dist);
        return VG_OK;
    }
    vg_info("optimize: a scene cut before frame %d (colour histogram distance %.3f > %.3f): the window restarts "
            "there", t, dist, threshold);
    return cut_add(s, t, (float)dist);
}

void offline_cuts_end(offline_seq *s)
{
    free(s->cut_hist);
    s->cut_hist = NULL;
}

bool offline_is_cut(const offline_seq *s, int t)
{
    for (int i = 0; i < s->cuts; i++)
        if (s->cut[i].frame == t)
            return true;
    return false;
}

/* Keyframes every stride frames from the start of each shot, and on the
 * last frame of each shot (its interval may be shorter: dt is per
 * interval). numbers NULL: only counted. */
int offline_keyframes(const offline_seq *s, int *numbers)
{
    const offline_desc *d = s->desc;
    int count = 0, start = d->first;
    for (int t = d->first; t <= d->last; t++) {
        if (offline_is_cut(s, t))
            start = t;
        bool key = (t - start) % s->keyframe_stride == 0 || t == d->last || offline_is_cut(s, t + 1);
        if (key && numbers)
            numbers[count] = t;
        count += key;
    }
    return count;
}

void offline_cuts_free(offline_seq *s)
{
    free(s->cut);
    free(s->cut_hist);
    s->cut = NULL;
    s->cut_hist = NULL;
    s->cuts = s->cut_cap = 0;
}
