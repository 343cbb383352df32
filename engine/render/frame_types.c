/* vergence — the frame's types: names and pure functions. */
#include "frame_types.h"

const char *const frame_compose_names[] = {"sbs", "sbs", "sbs-half", "tb", "rows", "columns", "checker",
                                          "anaglyph", "anaglyph-plain", "left", "right", NULL};
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

void frame_compose_size(frame_compose mode, uint32_t w, uint32_t h, uint32_t *out_w, uint32_t *out_h)
{
    *out_w = mode == FRAME_COMPOSE_SBS || mode == FRAME_COMPOSE_DEFAULT ? 2 * w : w;
    *out_h = mode == FRAME_COMPOSE_TB ? 2 * h : h;
}
