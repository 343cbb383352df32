/* vergence — a throw's flight rendered ahead and shown frame-exactly. */
#include "flight.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/clock.h"
#include "core/fault.h"
#include "core/log.h"
#include "picture.h"

struct flight {
    window *win;
    picture *pic;
    uint32_t *frames;            /* count x sw x sh, in the picture's channel order */
    int count, cap;
    uint32_t sw, sh;             /* composed image */
    uint32_t *col;               /* window column -> image column */
    uint32_t col_w, col_sw;      /* what col was made for */
};

vg_status flight_create(window *w, flight **out)
{
    flight *fl = calloc(1, sizeof *fl);
    if (!fl)
        return VG_ERR_NOMEM;
    fl->win = w;
    vg_status st = picture_fit(&fl->pic, w);
    if (st != VG_OK) {
        free(fl);
        fl = NULL;
    }
    *out = fl;
    return st;
}

void flight_destroy(flight *fl)
{
    if (!fl)
        return;
    picture_destroy(fl->pic);
    free(fl->frames);
    free(fl->col);
    free(fl);
}

vg_status flight_render(flight *fl, frame *fr, long first, int count, flight_progress_fn progress, void *user)
{
    fl->count = 0;
    int r, g, b;
    picture_channels(fl->pic, &r, &g, &b);
    vg_status st = VG_OK;
    for (int k = 0; k < count && st == VG_OK; k++) {
        if ((st = frame_render(fr, first + k)) != VG_OK)
            break;
        const frame_outputs *o = frame_get_outputs(fr);
        size_t n = (size_t)o->stereo_width * o->stereo_height;
        if (k == 0) {
            fl->sw = o->stereo_width, fl->sh = o->stereo_height;
            if (count * n > (size_t)fl->cap) {
                uint32_t *p = realloc(fl->frames, (size_t)count * n * 4);
                if (!p)
                    return VG_ERR_NOMEM;
                fl->frames = p;
                fl->cap = (int)(count * n);
            }
        }
        uint32_t *dst = fl->frames + (size_t)k * n;
        for (size_t i = 0; i < n; i++) {
            const uint8_t *s = o->stereo + 4 * i;
            uint8_t px[4];
            px[r] = s[0], px[g] = s[1], px[b] = s[2], px[3] = 255;
            memcpy(dst + i, px, 4);
        }
        fl->count = k + 1;
        if (progress)
            st = progress(user, k + 1, count);
    }
    return st;
}

/* The kept image k (or nothing: the background) scaled into the picture. */
static vg_status fill(flight *fl, int k)
{
    VkExtent2D e = picture_extent(fl->pic);
    uint32_t *dst = (uint32_t *)picture_begin(fl->pic);
    if (k < 0 || !fl->count) {
        memset(dst, 0, (size_t)e.width * e.height * 4);
        return VG_OK;
    }
    if (!fl->col || fl->col_w != e.width || fl->col_sw != fl->sw) {
        free(fl->col);
        if (!(fl->col = malloc(e.width * sizeof *fl->col)))
            return VG_ERR_NOMEM;
        for (uint32_t x = 0; x < e.width; x++)
            fl->col[x] = (uint32_t)(((uint64_t)x * fl->sw) / e.width);
        fl->col_w = e.width, fl->col_sw = fl->sw;
    }
    const uint32_t *src = fl->frames + (size_t)k * fl->sw * fl->sh;
    long prev = -1;
    for (uint32_t y = 0; y < e.height; y++) {
        uint32_t *row = dst + (size_t)y * e.width;
        long sy = (long)(((uint64_t)y * fl->sh) / e.height);
        if (sy == prev) { /* the same image row: copy the window row above */
            memcpy(row, row - e.width, e.width * 4);
            continue;
        }
        const uint32_t *s = src + (size_t)sy * fl->sw;
        for (uint32_t x = 0; x < e.width; x++)
            row[x] = s[fl->col[x]];
        prev = sy;
    }
    return VG_OK;
}

static void sleep_until_ms(double t)
{
    double left = t - vg_now_ms();
    if (left <= 0)
        return;
    struct timespec ts = {(time_t)(left / 1000), (long)(fmod(left, 1000.0) * 1e6)};
    while (nanosleep(&ts, &ts) && errno == EINTR)
        ;
}

/* Shows `count` frames (image k of each, -1: blank) one per refresh. */
static vg_status show(flight *fl, int count, bool blank, flight_record *rec, bool *quit)
{
    const double period = 1000.0 / FLIGHT_HZ;
    long extra_ms = vg_fault("present-ms"); /* tests: a display that cannot keep up */
    *rec = (flight_record){.frames = count};
    double t0 = 0, last = 0;
    vg_status st = picture_fit(&fl->pic, fl->win); /* the window may have been resized since */
    for (int k = 0; k < count && st == VG_OK && !*quit; k++) {
        window_event ev[32];
        int n = 0;
        if (blank)
            window_pump(fl->win); /* the check: no game time passes */
        else
            window_tick(fl->win, ev, 32, &n); /* input, and one tick a frame for a replay */
        for (int i = 0; i < n; i++)
            if (ev[i].kind == WINDOW_EVENT_KEY && (ev[i].key == GLFW_KEY_ESCAPE || ev[i].key == GLFW_KEY_Q))
                *quit = true;
        if (window_closed(fl->win))
            *quit = true;
        if ((st = fill(fl, blank ? -1 : k)) != VG_OK)
            break;
        if (extra_ms > 0)
            sleep_until_ms(vg_now_ms() + (double)extra_ms);
        /* Not before this frame's refresh (a swapchain that does not wait). */
        if (k > 0)
            sleep_until_ms(t0 + k * period - 0.5);
        bool rebuilt;
        if ((st = picture_show(&fl->pic, fl->win, &rebuilt)) != VG_OK)
            break;
        if (rebuilt) { /* resized mid-flight: this frame was not shown */
            rec->missed++;
            continue;
        }
        double now = vg_now_ms();
        if (rec->shown == 0)
            t0 = now;
        else {
            double dt = now - last;
            rec->worst_ms = fmax(rec->worst_ms, dt);
            if (dt >= 1.5 * period)
                rec->missed++;
        }
        last = now;
        rec->shown++;
    }
    if (rec->shown)
        rec->shown_s = (last - t0 + period) * 1e-3;
    return st;
}

vg_status flight_show(flight *fl, flight_record *rec, bool *quit)
{
    *quit = false;
    return show(fl, fl->count, false, rec, quit);
}

vg_status flight_rate_check(flight *fl, int count, flight_record *rec)
{
    bool quit = false;
    return show(fl, count, true, rec, &quit);
}
