/* vergence — the observer's view from the engine's own frames. */
#include "observer_engine.h"

#include <stdlib.h>
#include <string.h>

struct observer_engine {
    observer_engine_desc d;
    frame *frames[FRAME_MODE_OPTIMIZED + 1];
    uint32_t *object_ids;      /* the moving node's instance ids, 0-terminated */
    double *offset;
    int cap;
    float *surround;
    int w, h;
};

vg_status observer_engine_create(const observer_engine_desc *desc, observer_engine **out)
{
    *out = NULL;
    observer_engine *e = calloc(1, sizeof *e);
    if (!e)
        return VG_ERR_NOMEM;
    e->d = *desc;
    e->w = (int)desc->frame.width, e->h = (int)desc->frame.height;
    const scene *s = desc->scene;
    e->object_ids = observer_node_ids(s, desc->moving_node);
    e->surround = calloc((size_t)e->w * (size_t)e->h, sizeof *e->surround);
    if (!e->object_ids || !e->surround || e->w <= 0 || e->h <= 0) {
        vg_status st = e->w <= 0 || e->h <= 0 ? VG_ERR_ARG : VG_ERR_NOMEM;
        observer_engine_destroy(e);
        return st;
    }
    *out = e;
    return VG_OK;
}

void observer_engine_destroy(observer_engine *e)
{
    if (!e)
        return;
    for (int m = 0; m <= FRAME_MODE_OPTIMIZED; m++)
        frame_destroy(e->frames[m]);
    free(e->object_ids), free(e->offset), free(e->surround);
    free(e);
}

frame_desc observer_maps_frame(const frame_desc *game, frame_mode mode)
{
    frame_desc fd = *game;
    fd.mode = mode;
    fd.readback = true;
    fd.maps_only = true;
    fd.overlay = false;
    fd.reference = false;
    fd.measure = false;
    fd.present_format = VK_FORMAT_UNDEFINED;
    return fd;
}

uint32_t *observer_node_ids(const scene *s, int node)
{
    uint32_t *ids = calloc((size_t)s->instance_count + 1, sizeof *ids);
    if (ids)
        scene_node_instance_ids(s, node, ids, s->instance_count);
    return ids;
}

bool observer_is_node_id(const uint32_t *ids, uint32_t id)
{
    for (const uint32_t *p = ids; id && *p; p++)
        if (*p == id)
            return true;
    return false;
}

vg_status observer_engine_track(observer_engine *e, frame_mode mode, long first, int step, int count,
                                observer_shown *shown)
{
    if (count > e->cap) {
        double *p = realloc(e->offset, (size_t)count * sizeof *p);
        if (!p)
            return VG_ERR_NOMEM;
        e->offset = p, e->cap = count;
    }
    size_t n = (size_t)e->w * (size_t)e->h;
    *shown = (observer_shown){.offset = e->offset, .count = count, .surround = e->surround, .width = e->w,
                              .height = e->h};
    if (mode == FRAME_MODE_ORIGINAL) {
        memset(e->offset, 0, (size_t)count * sizeof *e->offset);
        memset(e->surround, 0, n * sizeof *e->surround);
        return VG_OK;
    }
    if (mode == FRAME_MODE_DEFAULT)
        mode = FRAME_MODE_OPTIMIZED;
    vg_status st = VG_OK;
    frame **fr = &e->frames[mode];
    if (!*fr) {
        frame_desc fd = observer_maps_frame(&e->d.frame, mode);
        if ((st = frame_create(e->d.gpu, e->d.scene, &fd, fr)) != VG_OK)
            return st;
    }
    frame_restart(*fr);
    int stride = frame_get_desc(*fr)->keyframe_stride;
    for (int k = e->d.lead_keyframes; k > 0 && st == VG_OK; k--)
        st = frame_render(*fr, first - (long)k * stride);
    double last = 0.0;
    for (int i = 0; i < count && st == VG_OK; i++) {
        if ((st = frame_render(*fr, first + (long)i * step)) != VG_OK)
            break;
        const frame_outputs *o = frame_get_outputs(*fr);
        const float *map = mode == FRAME_MODE_MANIPULATED ? o->h : o->f;
        double sum = 0.0;
        long hits = 0;
        for (size_t p = 0; p < n; p++)
            if (observer_is_node_id(e->object_ids, o->ids[p])) {
                sum += (double)map[p] - (double)o->g[p];
                hits++;
            }
        last = e->offset[i] = hits ? sum / (double)hits : last;
        if (i == count - 1)
            for (size_t p = 0; p < n; p++)
                e->surround[p] = map[p] - o->g[p];
    }
    return st;
}
