/* vergence — figures for people: colour map, maps with a legend, videos. */
#include "figure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <stb_easy_font.h>

#include "core/io.h"
#include "core/log.h"

void figure_colormap(float t, uint8_t rgb[3])
{
    /* Eight stops of a viridis-like map: ordered in lightness, readable in grey. */
    static const float stops[8][3] = {
        {0.267f, 0.005f, 0.329f}, {0.275f, 0.194f, 0.496f}, {0.213f, 0.359f, 0.552f}, {0.153f, 0.497f, 0.558f},
        {0.122f, 0.633f, 0.531f}, {0.288f, 0.762f, 0.428f}, {0.626f, 0.854f, 0.224f}, {0.993f, 0.906f, 0.144f}};
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    float x = t * 7.0f;
    int i = x >= 7.0f ? 6 : (int)x;
    float u = x - (float)i;
    for (int k = 0; k < 3; k++)
        rgb[k] = (uint8_t)lrintf(255.0f * (stops[i][k] + u * (stops[i + 1][k] - stops[i][k])));
}

void figure_map_rgb(const float *v, int w, int rows, int repeat, float lo, float hi, uint8_t *rgb)
{
    float span = hi > lo ? hi - lo : 1.0f;
    for (int r = 0; r < rows; r++)
        for (int x = 0; x < w; x++) {
            float a = v[(size_t)r * (size_t)w + (size_t)x];
            uint8_t c[3] = {128, 128, 128};
            if (isfinite(a))
                figure_colormap((a - lo) / span, c);
            for (int k = 0; k < repeat; k++)
                memcpy(rgb + 3 * ((size_t)(r * repeat + k) * (size_t)w + (size_t)x), c, 3);
        }
}

/* ------------------------------------------------------------------------- */
/* Legend                                                                    */
/* ------------------------------------------------------------------------- */

typedef struct canvas {
    uint8_t *rgb;
    int w, h;
} canvas;

static void fill(canvas *c, int x, int y, int w, int h, const uint8_t rgb[3])
{
    for (int j = y < 0 ? 0 : y; j < y + h && j < c->h; j++)
        for (int i = x < 0 ? 0 : x; i < x + w && i < c->w; i++)
            memcpy(c->rgb + 3 * ((size_t)j * (size_t)c->w + (size_t)i), rgb, 3);
}

typedef struct font_vertex {
    float x, y, z;
    uint8_t color[4];
} font_vertex;

static int text_width(const char *text, int scale) { return stb_easy_font_width((char *)text) * scale; }

static void text(canvas *c, int x, int y, int scale, const char *s, const uint8_t rgb[3])
{
    static font_vertex v[4 * 1024];
    int quads = stb_easy_font_print(0, 0, (char *)s, NULL, v, (int)sizeof v);
    for (int q = 0; q < quads; q++) {
        const font_vertex *a = &v[4 * q], *b = &v[4 * q + 2];
        fill(c, x + (int)a->x * scale, y + (int)a->y * scale, (int)(b->x - a->x) * scale, (int)(b->y - a->y) * scale,
             rgb);
    }
}

double figure_nice_step(double span, int count)
{
    double raw = span / count, mag = pow(10.0, floor(log10(raw))), f = raw / mag;
    return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * mag;
}

/* Legend strip height for text scale ts. */
static int strip_height(int ts) { return 6 + 11 * ts + 8 * ts + 5 + 8 * ts + 6; }

static void legend(canvas *c, int y0, int ts, float lo, float hi, const figure_legend *lg)
{
    static const uint8_t ink[3] = {40, 40, 40}, grey[3] = {110, 110, 110}, paper[3] = {255, 255, 255};
    fill(c, 0, y0, c->w, c->h - y0, paper);
    char title[256];
    snprintf(title, sizeof title, "%s%s%s%s", lg->title ? lg->title : "", lg->unit ? " (" : "",
             lg->unit ? lg->unit : "", lg->unit ? ")" : "");
    text(c, 6, y0 + 6, ts, title, ink);
    int bx = 6 + 4 * ts, bw = c->w - 2 * bx, by = y0 + 6 + 11 * ts, bh = 8 * ts;
    for (int i = 0; i < bw; i++) {
        uint8_t col[3];
        figure_colormap(bw > 1 ? (float)i / (float)(bw - 1) : 0.0f, col);
        fill(c, bx + i, by, 1, bh, col);
    }
    if (!(hi > lo))
        return;
    double step = figure_nice_step(hi - lo, bw / (60 * ts) > 2 ? bw / (60 * ts) : 2);
    for (double t = ceil(lo / step - 1e-9) * step; t <= hi + 1e-9 * step; t += step) {
        int x = bx + (int)lround((t - lo) / (hi - lo) * (bw - 1));
        fill(c, x, by + bh, 1, 4, grey);
        char label[32];
        snprintf(label, sizeof label, "%g", fabs(t) < 1e-9 * step ? 0.0 : t);
        int tw = text_width(label, ts), tx = x - tw / 2;
        tx = tx < 0 ? 0 : tx + tw > c->w ? c->w - tw : tx;
        text(c, tx, by + bh + 5, ts, label, ink);
    }
}

vg_status figure_map_png(const char *path, const float *v, int w, int rows, int repeat, float lo, float hi,
                         const figure_legend *lg)
{
    int mh = rows * repeat, s = 1, ts = 1;
    if (lg) {
        s = w < 320 ? (320 + w - 1) / w : 1;
        ts = w * s >= 640 ? 2 : 1;
    }
    canvas c = {.w = w * s, .h = mh * s + (lg ? strip_height(ts) : 0)};
    uint8_t *map = malloc((size_t)w * (size_t)mh * 3);
    c.rgb = malloc((size_t)c.w * (size_t)c.h * 3);
    if (!map || !c.rgb) {
        free(map);
        free(c.rgb);
        return VG_ERR_NOMEM;
    }
    figure_map_rgb(v, w, rows, repeat, lo, hi, map);
    for (int y = 0; y < mh * s; y++)
        for (int x = 0; x < c.w; x++)
            memcpy(c.rgb + 3 * ((size_t)y * (size_t)c.w + (size_t)x), map + 3 * ((size_t)(y / s) * (size_t)w + (size_t)(x / s)),
                   3);
    if (lg)
        legend(&c, mh * s, ts, lo, hi, lg);
    vg_status st = vg_png_write(path, c.w, c.h, 3, c.rgb);
    free(map);
    free(c.rgb);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Videos                                                                    */
/* ------------------------------------------------------------------------- */

const char *figure_find_ffmpeg(char *buf, size_t cap)
{
    const char *path = getenv("PATH");
    while (path && *path) {
        const char *end = strchr(path, ':');
        size_t len = end ? (size_t)(end - path) : strlen(path);
        if (len > 0 && len + 8 < cap) {
            snprintf(buf, cap, "%.*s/ffmpeg", (int)len, path);
            if (access(buf, X_OK) == 0)
                return buf;
        }
        path = end ? end + 1 : NULL;
    }
    return NULL;
}

struct figure_video {
    FILE *pipe;
    int w, h;
    char path[4096];
};

figure_video *figure_video_open(const char *ffmpeg, const char *path, int w, int h, double fps)
{
    return figure_video_open_stereo(ffmpeg, path, w, h, fps, FIGURE_PACKING_NONE);
}

figure_video *figure_video_open_stereo(const char *ffmpeg, const char *path, int w, int h, double fps,
                                       figure_packing packing)
{
    if (!ffmpeg)
        return NULL;
    if (strchr(path, '\'') || strchr(ffmpeg, '\'') || strlen(path) >= 4096) {
        vg_warn("%s: a path ffmpeg cannot be given safely (a quote, or too long); no video", path);
        return NULL;
    }
    figure_video *v = calloc(1, sizeof *v);
    if (!v)
        return NULL;
    char cmd[9000];
    size_t n = strlen(path);
    bool mkv = n > 4 && !strcmp(path + n - 4, ".mkv");
    const char *sei = packing == FIGURE_PACKING_SBS ? "-x264-params frame-packing=3 "
                      : packing == FIGURE_PACKING_TB ? "-x264-params frame-packing=4 "
                                                     : "";
    const char *mode = !mkv || !packing                 ? ""
                       : packing == FIGURE_PACKING_SBS ? "-metadata:s:v:0 stereo_mode=left_right "
                                                       : "-metadata:s:v:0 stereo_mode=top_bottom ";
    /* H.264 in MP4 plays in every browser; even sizes for yuv420p. */
    snprintf(cmd, sizeof cmd,
             "'%s' -hide_banner -loglevel error -y -f rawvideo -pix_fmt rgb24 -s %dx%d -r %g -i - -an "
             "-vf 'pad=ceil(iw/2)*2:ceil(ih/2)*2' -c:v libx264 -preset veryfast -crf 20 -pix_fmt yuv420p %s%s%s'%s'",
             ffmpeg, w, h, fps, sei, mode, mkv ? "" : "-movflags +faststart ", path);
    v->pipe = popen(cmd, "w");
    if (!v->pipe) {
        vg_warn("%s: could not start ffmpeg; no video", path);
        free(v);
        return NULL;
    }
    v->w = w;
    v->h = h;
    snprintf(v->path, sizeof v->path, "%s", path);
    return v;
}

void figure_video_frame(figure_video **vp, const uint8_t *rgb)
{
    figure_video *v = *vp;
    if (!v)
        return;
    size_t px = (size_t)v->w * (size_t)v->h;
    if (fwrite(rgb, 3, px, v->pipe) != px) {
        vg_warn("%s: ffmpeg stopped reading; no video", v->path);
        pclose(v->pipe);
        free(v);
        *vp = NULL;
    }
}

bool figure_video_close(figure_video *v)
{
    if (!v)
        return false;
    bool ok = pclose(v->pipe) == 0;
    if (ok)
        ok = vg_write_watch_add(v->path) == VG_OK; /* ffmpeg wrote it, not core/io */
    if (!ok)
        vg_warn("%s: ffmpeg failed; no video", v->path);
    free(v);
    return ok;
}
