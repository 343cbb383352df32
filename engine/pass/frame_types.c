/* vergence — the frame's types: names and pure functions. */
#include "frame_types.h"

const char *const frame_compose_names[] = {"sbs", "sbs", "sbs-half", "tb", "rows", "columns", "checker",
                                          "anaglyph", "anaglyph-plain", "left", "right", "tb-half",
                                          "anaglyph-green-magenta", "anaglyph-amber-blue", "frame-packing",
                                          "cross-eyed", NULL};
const char *const frame_stereo_names[] = {"off", "warp", "cameras", "imagewarp", NULL};
const char *const frame_mode_names[] = {"optimized", "original", "manipulated", "optimized", NULL};

long frame_keyframe_of(long index, int stride)
{
    long q = index / stride;
    return (index % stride != 0 && ((index < 0) != (stride < 0))) ? q - 1 : q;
}

frame_times frame_times_at(long index, double fps, int stride)
{
    /* Neighbouring keyframes strictly before and after: on a keyframe these
     * are the keyframes one stride away, as the keyframe window needs. */
    long prev = frame_keyframe_of(index - 1, stride) * stride;
    long next = prev + stride;
    if (next <= index)
        next += stride;
    return (frame_times){
        .index = index, .prev_key = prev, .next_key = next,
        .t = (double)index / fps, .t_prev = (double)prev / fps, .t_next = (double)next / fps,
    };
}

frame_layout frame_compose_layout(frame_compose mode, bool swap_eyes, uint32_t w, uint32_t h)
{
    frame_layout l = {.width = w, .height = h, .eye = {{0, 0, w, h}, {0, 0, w, h}}};
    /* HDMI 1.4a frame packing: an active space of 45 lines at 1080p, 30 at 720p. */
    uint32_t gap = (h + 12) / 24;
    switch (mode) {
    case FRAME_COMPOSE_CROSS_EYED: /* side by side, the other way round */
        swap_eyes = !swap_eyes;
        /* fall through */
    case FRAME_COMPOSE_DEFAULT:
    case FRAME_COMPOSE_SBS:
        l.width = 2 * w;
        l.eye[1].x = w;
        break;
    case FRAME_COMPOSE_SBS_HALF:
        l.eye[0].w = l.eye[1].w = w / 2;
        l.eye[1].x = w / 2;
        break;
    case FRAME_COMPOSE_TB:
        l.height = 2 * h;
        l.eye[1].y = h;
        break;
    case FRAME_COMPOSE_TB_HALF:
        l.eye[0].h = l.eye[1].h = h / 2;
        l.eye[1].y = h / 2;
        break;
    case FRAME_COMPOSE_FRAME_PACKING:
        l.height = 2 * h + gap;
        l.eye[1].y = h + gap;
        break;
    default:
        l.overlaid = true;
        break;
    }
    if (swap_eyes && !l.overlaid) {
        frame_eye_rect t = l.eye[0];
        l.eye[0] = l.eye[1];
        l.eye[1] = t;
    }
    return l;
}

void frame_compose_eye_size(frame_compose mode, uint32_t out_w, uint32_t out_h, double *eye_w, double *eye_h)
{
    /* Eyes of the output's size compose to l: scaled by out / l they fill it. */
    frame_layout l = frame_compose_layout(mode, false, out_w, out_h);
    *eye_w = (double)out_w * out_w / l.width;
    *eye_h = (double)out_h * out_h / l.height;
}

void frame_compose_size(frame_compose mode, uint32_t w, uint32_t h, uint32_t *out_w, uint32_t *out_h)
{
    frame_layout l = frame_compose_layout(mode, false, w, h);
    *out_w = l.width;
    *out_h = l.height;
}
