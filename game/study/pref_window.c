/* vergence — the preference study's window: three clips side by side. */
#include "pref_window.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "core/log.h"
#include "play/picture.h"
#include "pref_trial.h"
#include "play/window.h"


static const uint8_t k_back[3] = {18, 22, 30}, k_text[3] = {236, 240, 245}, k_title[3] = {255, 214, 110};

/* Where the panels go: eye-image coordinates of the whole window, then the
 * output layout maps each eye to its place in the window. */
typedef struct layout {
    frame_compose compose;
    int ew, eh;              /* eye image of the whole window */
    int pw, ph;              /* one panel's eye image */
    int x[3], y;             /* panel corners in the eye image (even: interleaving keeps parity) */
    bool swap;
    frame_layout win;        /* the eyes of the whole window in the window */
    frame_layout panel;      /* one panel's eyes in its composed image */
} layout;

typedef struct pref {
    const pref_window_desc *d;
    window *win;
    picture *pic;
    layout lay;
    uint8_t *clip[3];        /* per version: frames x composed panel (RGB) */
    int frames;
    uint32_t sw, sh;         /* composed panel size */
    bool quit;
} pref;

static void layout_make(pref *p)
{
    layout *l = &p->lay;
    VkExtent2D e = window_extent(p->win);
    l->compose = (frame_compose)p->d->win->compose;
    l->swap = p->d->win->swap_eyes;
    double ew, eh;
    frame_compose_eye_size(l->compose, e.width, e.height, &ew, &eh);
    l->ew = (int)ew, l->eh = (int)eh;
    l->win = frame_compose_layout(l->compose, l->swap, (uint32_t)l->ew, (uint32_t)l->eh);
    pref_panel_size(window_gpu(p->win)->is_cpu, l->ew, l->eh, &l->pw, &l->ph);
    int x0 = ((l->ew - 3 * l->pw - 2 * PREF_GAP) / 2) & ~1;
    for (int i = 0; i < 3; i++)
        l->x[i] = x0 + i * (l->pw + PREF_GAP);
    l->y = ((l->eh - l->ph) / 2) & ~1;
    /* Where the output layout puts one panel's eyes (frame_compose_layout
     * for the panel), for blit_panel. */
    l->panel = frame_compose_layout(l->compose, l->swap, (uint32_t)l->pw, (uint32_t)l->ph);
}

/* ------------------------------------------------------------------------- */
/* Drawing in eye coordinates                                                */
/* ------------------------------------------------------------------------- */

/* The window positions of an eye-image position: one for the interleaved
 * and anaglyph layouts, one per eye for the packed ones (squeezed by the
 * half layouts). */
static int eye_places(const layout *l, int ex, int ey, int xs[2], int ys[2])
{
    if (l->win.overlaid) {
        xs[0] = ex, ys[0] = ey;
        return 1;
    }
    for (int e = 0; e < 2; e++) {
        const frame_eye_rect *r = &l->win.eye[e];
        xs[e] = (int)r->x + ex * (int)r->w / l->ew;
        ys[e] = (int)r->y + ey * (int)r->h / l->eh;
    }
    return 2;
}

static void text_eyes(pref *p, int ex, int ey, int scale, const char *text, const uint8_t rgb[3], bool centred)
{
    int xs[2], ys[2], n = eye_places(&p->lay, ex, ey, xs, ys);
    int w = centred ? picture_text_width(text, scale) * (int)p->lay.win.eye[0].w / p->lay.ew : 0;
    for (int i = 0; i < n; i++)
        picture_text(p->pic, xs[i] - w / 2, ys[i], scale, text, rgb);
}

/* Copies a composed panel into the picture at panel slot i: each eye's
 * rectangle of the panel to that eye's place in the window. */
static void blit_panel(pref *p, int slot, const uint8_t *rgb)
{
    const layout *l = &p->lay;
    VkExtent2D e = picture_extent(p->pic);
    uint8_t *px = picture_begin(p->pic);
    int r, g, b;
    picture_channels(p->pic, &r, &g, &b);
    int xs[2], ys[2], places = eye_places(l, l->x[slot], l->y, xs, ys);
    for (int k = 0; k < places; k++) {
        const frame_eye_rect *src = l->win.overlaid ? &(frame_eye_rect){0, 0, p->sw, p->sh} : &l->panel.eye[k];
        for (uint32_t sy = src->y; sy < src->y + src->h && sy < p->sh; sy++)
            for (uint32_t sx = src->x; sx < src->x + src->w && sx < p->sw; sx++) {
                int dx = xs[k] + (int)(sx - src->x), dy = ys[k] + (int)(sy - src->y);
                if (dx < 0 || dy < 0 || dx >= (int)e.width || dy >= (int)e.height)
                    continue;
                const uint8_t *s = rgb + ((size_t)sy * p->sw + sx) * 3;
                uint8_t *q = px + ((size_t)dy * e.width + (size_t)dx) * 4;
                q[r] = s[0], q[g] = s[1], q[b] = s[2], q[3] = 255;
            }
    }
}

static void background(pref *p)
{
    VkExtent2D e = picture_extent(p->pic);
    picture_begin(p->pic);
    picture_fill(p->pic, 0, 0, (int)e.width, (int)e.height, k_back);
}

/* Shows the picture; a stale swapchain is rebuilt (and the layout with it:
 * the caller starts the trial again when *relayout is set). */
static vg_status show(pref *p, bool *relayout)
{
    bool rebuilt;
    vg_status st = picture_show(&p->pic, p->win, &rebuilt);
    if (rebuilt && relayout)
        *relayout = true;
    return st;
}

/* ------------------------------------------------------------------------- */
/* A trial                                                                   */
/* ------------------------------------------------------------------------- */

static void clips_free(pref *p)
{
    for (int v = 0; v < 3; v++) {
        free(p->clip[v]);
        p->clip[v] = NULL;
    }
}

static vg_status progress(pref *p, int trial, int done, int total)
{
    char line[96];
    background(p);
    snprintf(line, sizeof line, "Preparing trial %d of %d ... %d %%", trial + 1, p->d->trial_count,
             100 * done / (total > 0 ? total : 1));
    text_eyes(p, p->lay.ew / 2, p->lay.eh / 2 - 8, 2, line, k_text, true);
    window_pump(p->win);
    return show(p, NULL);
}

/* One version's clip being rendered ahead. */
typedef struct clip_ctx {
    pref *p;
    int trial, version;
} clip_ctx;

static vg_status clip_frame(void *user, int k, const frame_outputs *fo, bool *stop)
{
    clip_ctx *c = user;
    pref *p = c->p;
    p->sw = fo->stereo_width, p->sh = fo->stereo_height;
    size_t n = (size_t)p->sw * p->sh;
    if (!p->clip[c->version] && !(p->clip[c->version] = malloc(n * 3 * (size_t)p->frames)))
        return VG_ERR_NOMEM;
    uint8_t *dst = p->clip[c->version] + n * 3 * (size_t)k;
    for (size_t i = 0; i < n; i++)
        memcpy(dst + 3 * i, fo->stereo + 4 * i, 3);
    *stop = window_closed(p->win);
    return k % 8 == 0 ? progress(p, c->trial, c->version * p->frames + k, 3 * p->frames) : VG_OK;
}

/* Renders the three versions of the clip: slot 0 left, 1 middle (g), 2 right. */
static vg_status prerender(pref *p, int trial, scene *s, const frame_mode modes[3])
{
    gpu *g = window_gpu(p->win);
    const pref_window_desc *d = p->d;
    p->frames = pref_clip_frames(s);
    vg_status st = VG_OK;
    for (int v = 0; v < 3 && st == VG_OK && !window_closed(p->win); v++) {
        frame_desc fd = pref_clip_frame_desc(g, &(pref_clip_desc){
            .width = (uint32_t)p->lay.pw, .height = (uint32_t)p->lay.ph, .mode = modes[v], .compose = p->lay.compose, .swap_eyes = p->lay.swap,
            .op = d->op, .display = d->display, .tess_error = d->win->tess_error});
        st = pref_clip_render(g, s, &fd, clip_frame, &(clip_ctx){p, trial, v});
    }
    return st;
}

/* Plays the clips in a loop until an answer: Left / Right or a click on a
 * side panel, taken once the clip has been seen through. */
static vg_status ask(pref *p, int trial, int *choice, double *response_s, bool *relayout)
{
    static const char *const labels[3] = {"A", "reference", "B"};
    *choice = -1;
    long t0 = -1;
    vg_info("study preference: trial %d: showing %d frames per version", trial, p->frames);
    while (*choice < 0 && !p->quit && !*relayout) {
        window_event ev[32];
        int n;
        long tick = window_tick(p->win, ev, 32, &n);
        if (window_closed(p->win) || (p->d->win->ticks && tick >= p->d->win->ticks)) {
            p->quit = true;
            break;
        }
        t0 = t0 < 0 ? tick : t0;
        long t = tick - t0;
        bool seen = t >= (long)p->frames * PREF_CLIP_STEP;
        for (int i = 0; i < n; i++) {
            const window_event *e = &ev[i];
            if (e->kind == WINDOW_EVENT_KEY && (e->key == GLFW_KEY_ESCAPE || e->key == GLFW_KEY_Q))
                p->quit = true;
            else if (seen && e->kind == WINDOW_EVENT_KEY && (e->key == GLFW_KEY_LEFT || e->key == GLFW_KEY_RIGHT))
                *choice = e->key == GLFW_KEY_RIGHT;
            else if (seen && e->kind == WINDOW_EVENT_CLICK)
                *choice = e->x < 0.4 ? 0 : e->x > 0.6 ? 1 : -1;
        }
        if (*choice >= 0) {
            *response_s = (t - (double)p->frames * PREF_CLIP_STEP) / 60.0;
            vg_info("study preference: trial %d: %s", trial, *choice ? "right" : "left");
            break;
        }
        int k = (int)((t / PREF_CLIP_STEP) % p->frames);
        size_t n3 = (size_t)p->sw * p->sh * 3;
        background(p);
        for (int v = 0; v < 3; v++) {
            blit_panel(p, v, p->clip[v] + n3 * (size_t)k);
            text_eyes(p, p->lay.x[v] + p->lay.pw / 2, p->lay.y - 22, 2, labels[v], v == 1 ? k_title : k_text, true);
        }
        char line[96];
        snprintf(line, sizeof line, "Trial %d of %d", trial + 1, p->d->trial_count);
        text_eyes(p, 12, 10, 2, line, k_title, false);
        text_eyes(p, p->lay.ew / 2, p->lay.y + p->lay.ph + 12, 2,
                  seen ? "Which side moves more like the reference?  Left or Right"
                       : "Watch how the objects move ...", k_text, true);
        vg_status st = show(p, relayout);
        if (st != VG_OK)
            return st;
    }
    return VG_OK;
}

static vg_status trial_run(pref *p, int trial)
{
    const pref_window_desc *d = p->d;
    pref_cell c = pref_cell_of(d->cells[trial]);
    char path[1100];
    scene *s = NULL;
    vg_status st = pref_scene_path(d->arena_path, c.scene, path, sizeof path);
    if (st == VG_OK)
        st = scene_load(path, &s);
    int moving = st == VG_OK ? pref_moving_node(s) : -1;
    if (st == VG_OK && moving < 0) {
        vg_error("%s: no animated object to compare", path);
        st = VG_ERR_FORMAT;
    }
    frame_mode side[2] = {FRAME_MODE_MANIPULATED, FRAME_MODE_OPTIMIZED};
    const frame_mode modes[3] = {side[c.optimized_right ? 0 : 1], FRAME_MODE_ORIGINAL, side[c.optimized_right ? 1 : 0]};
    for (bool again = true; again && st == VG_OK && !p->quit;) {
        again = false;
        layout_make(p);
        pref_saliency_apply(s, moving, c.saliency);
        st = prerender(p, trial, s, modes);
        int choice;
        double response;
        if (st == VG_OK)
            st = ask(p, trial, &choice, &response, &again);
        if (st == VG_OK && !again && choice >= 0)
            st = d->on_choice(d->user, trial, choice, response);
        clips_free(p);
    }
    scene_destroy(s);
    return st;
}

vg_status pref_window_run(const pref_window_desc *d)
{
    pref p = {.d = d};
    vg_status st = window_create(&(window_desc){.title = "vergence preference study", .width = d->win->size[0],
                                                .height = d->win->size[1], .fullscreen = d->win->fullscreen,
                                                .gpu = &d->win->gpu, .replay = d->win->replay,
                                                .frame_ticks = d->win->frame_ticks,
                                                .record = d->win->record}, &p.win);
    gpu *g = p.win ? window_gpu(p.win) : NULL;
    if (st == VG_OK)
        st = picture_fit(&p.pic, p.win);
    for (int t = d->first_trial; t < d->trial_count && st == VG_OK && !p.quit; t++)
        st = trial_run(&p, t);
    clips_free(&p);
    picture_destroy(p.pic);
    if (p.win)
        window_destroy(p.win);
    if (g && gpu_cli_close(g, st) && st == VG_OK)
        st = VG_ERR_VALIDATION;
    return st;
}
