#include "offline.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/io.h"
#include "core/json.h"
#include "core/log.h"
#include "core/manifest.h"
#include "core/parallel.h"
#include "core/srgb.h"
#include "core/stats.h"
#include "disparity/disp_metrics.h"
#include "disparity/mid_causal.h"
#include "disparity/mid_shared.h"
#include "disparity/disp_pattern.h"
#include "disparity/disp_upsample.h"
#include "figure/figure.h"
#include "warp/image_warp.h"

#define PATH_CAP 4096
#define FLOW_REACH 4          /* frame widths a flow vector may span (plausibility) */
#define VERGENCE_MAX 10800.0  /* arcmin: a vergence angle is below 180 degrees */

/* ------------------------------------------------------------------------- */
/* Run state                                                                 */
/* ------------------------------------------------------------------------- */

typedef struct seq {
    const offline_desc *d;
    disp_pattern pg, ph, pz, pfn, pfp, ps, pid, pim;
    bool has_h, has_z, has_fn, has_fp, has_s, has_id, has_im;
    int w, h, frames, stride, nt;
    int *key;             /* frame number of each keyframe */
    double fps, lo, hi, g_min, g_max;
    stereo_display disp;
    disp_grid grid;
    disp_operator *op;
    vg_pool *pool;
    float *sal;           /* scratch: saliency of one frame */
    uint8_t *unknown;     /* scratch: the last frame read's pixels of unknown g (inf) */
    vg_manifest man;      /* the result in out_dir: metrics.json lists its files */
    long unknown_total;   /* over the sequence, counted when checking the inputs */
    long holes;           /* of the new pair before the fill, both eyes over the sequence */
    const char *g_png;    /* g from dataset PNGs: "KITTI" or "Sintel" (pixels), else NULL */
    double raw_min, raw_max; /* known g as read, before any unit conversion */
    double raw_median;    /* of the first frame's known g, as read */
    int past, future, windows; /* the causal window (desc.causal) */
    float *f_ungated;          /* ... and its f before the gate (the solve's own; mid_causal_desc.ungated) */
    bool computed_sal;    /* no --saliency, --h or --uniform-saliency: computed_saliency() */
    float *sal_scratch;   /* 3 planes: depth and flow of one frame (computed saliency) */
} seq;

/* g in pixels: --g-units px, or a dataset's PNGs. */
static bool g_in_px(const seq *s) { return s->d->g_units == DISP_G_PX || s->g_png; }

/* The view of --image is the left camera's. */
static bool image_left(const seq *s)
{
    return s->d->image_view == OFFLINE_VIEW_LEFT || (s->d->image_view == OFFLINE_VIEW_AUTO && g_in_px(s));
}

static bool is_png(const char *path)
{
    size_t n = strlen(path);
    return n > 4 && !strcasecmp(path + n - 4, ".png");
}

static vg_status frame_path(const disp_pattern *p, int t, char *buf)
{
    if (disp_pattern_format(p, t, buf, PATH_CAP) != VG_OK) {
        vg_error("'%s': file name of frame %d is too long", p->text, t);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

/* Reads one frame of a single- or two-channel sequence and checks its size
 * against the first g frame: every frame of every input must match. */
static vg_status read_frame(seq *s, const disp_pattern *p, int t, int channels, const char *what,
                            vg_imagef *img, bool inf_unknown)
{
    char path[PATH_CAP];
    vg_status st = frame_path(p, t, path);
    if (st != VG_OK)
        return st;
    const char *encoding = NULL;
    st = channels == 2                ? vg_flo_read(path, img)
         : p == &s->pg && is_png(path) ? vg_disparity_png_read(path, img, &encoding)
                                       : vg_pfm_read(path, img);
    if (st != VG_OK)
        return st;
    if (encoding && !s->g_png) {
        s->g_png = encoding;
        vg_info("optimize: %s: %s disparity PNG, pixels (x_left - x_right)%s", path, encoding,
                s->d->g_units == DISP_G_PX ? "" : ": read as --g-units px");
    }
    if (img->channels != channels) {
        vg_error("%s: %s has %d channels, expected %d", path, what, img->channels, channels);
        vg_imagef_free(img);
        return VG_ERR_FORMAT;
    }
    if (s->w && (img->width != s->w || img->height != s->h)) {
        vg_error("%s: %s is %dx%d but the sequence is %dx%d (all frames must have the same size)", path,
                 what, img->width, img->height, s->w, s->h);
        vg_imagef_free(img);
        return VG_ERR_FORMAT;
    }
    int n = img->width * img->height * channels;
    for (int i = 0; i < n; i++)
        if (!isfinite(img->data[i]) && !(inf_unknown && isinf(img->data[i]))) {
            vg_error("%s: %s has a non-finite value at pixel %d", path, what, i / channels);
            vg_imagef_free(img);
            return VG_ERR_FORMAT;
        }
    /* A flow moves a pixel within reach of the frame: a few widths at most
     * (Middlebury's "unknown", above 1e9, is not supported either). */
    float reach = (float)(FLOW_REACH * (img->width > img->height ? img->width : img->height));
    for (int i = 0; channels == 2 && i < n; i++)
        if (fabsf(img->data[i]) > reach) {
            int px = i / 2;
            vg_error("%s: flow (%g, %g) at pixel (%d, %d) moves farther than %d frame widths (%g px): not a flow "
                     "of these %dx%d frames", path, img->data[2 * px], img->data[2 * px + 1], px % img->width,
                     px / img->width, FLOW_REACH, reach, img->width, img->height);
            vg_imagef_free(img);
            return VG_ERR_FORMAT;
        }
    return VG_OK;
}

/* Pixels of unknown disparity (inf, as Middlebury writes them; KITTI's 0
 * reads as inf) are marked in s->unknown: their samples are left out of
 * the costs and the metrics, and f is written as inf there. They take the
 * value of the nearest known pixel of their row (of the nearest row with
 * one), so that the operator and the upsampling see a plausible surface.
 * Returns how many, -1 when no pixel is known. */
static int fill_unknown(seq *s, float *v)
{
    int w = s->w, h = s->h, count = 0, known_row = -1;
    for (int i = 0; i < w * h; i++) {
        s->unknown[i] = isinf(v[i]) != 0;
        count += s->unknown[i];
    }
    if (!count)
        return 0;
    for (int y = 0; y < h; y++) {
        float *row = v + (size_t)y * w;
        const uint8_t *u = s->unknown + (size_t)y * w;
        int last = -1;
        for (int x = 0; x < w; x++)
            if (!u[x]) {
                for (int k = last + 1; k < x; k++) /* a gap: its nearer end */
                    row[k] = last < 0 || x - k <= k - last ? row[x] : row[last];
                last = x;
            }
        if (last < 0)
            continue;
        for (int k = last + 1; k < w; k++)
            row[k] = row[last];
        known_row = y;
    }
    if (known_row < 0)
        return -1;
    /* Rows with no known pixel: the nearest row that has one (filled above). */
    for (int pass = 0; pass < 2; pass++)
        for (int y = pass ? h - 2 : 1; pass ? y >= 0 : y < h; y += pass ? -1 : 1) {
            int from = pass ? y + 1 : y - 1;
            bool empty = true;
            for (int x = 0; x < w && empty; x++)
                empty = isinf(v[(size_t)y * w + x]);
            if (empty && !isinf(v[(size_t)from * w]))
                memcpy(v + (size_t)y * w, v + (size_t)from * w, (size_t)w * sizeof(float));
        }
    return count;
}

/* g of a frame as vergence in arcmin (converted from dataset pixels if asked). */
static vg_status read_g(seq *s, int t, float *out)
{
    vg_imagef img = {0};
    vg_status st = read_frame(s, &s->pg, t, 1, "g", &img, true);
    if (st != VG_OK)
        return st;
    if (!s->w) {
        s->w = img.width;
        s->h = img.height;
        if (!(s->unknown = malloc((size_t)s->w * s->h))) {
            vg_imagef_free(&img);
            return VG_ERR_NOMEM;
        }
    }
    int n = s->w * s->h, bad = 0, unknown = fill_unknown(s, img.data);
    if (unknown < 0) {
        char path[PATH_CAP];
        frame_path(&s->pg, t, path);
        vg_error("%s: g is unknown (inf) at every pixel", path);
        vg_imagef_free(&img);
        return VG_ERR_FORMAT;
    }
    if (!out)
        s->unknown_total += unknown;
    if (!out && t == s->d->first) {
        double *known = malloc((size_t)n * sizeof *known);
        size_t k = 0;
        for (int i = 0; known && i < n; i++)
            if (!s->unknown[i])
                known[k++] = img.data[i];
        s->raw_median = known && k ? vg_median(known, k, 1) : NAN;
        free(known);
    }
    for (int i = 0; i < n; i++) {
        double v = img.data[i];
        if (!out && !s->unknown[i]) {
            s->raw_min = fmin(s->raw_min, v);
            s->raw_max = fmax(s->raw_max, v);
        }
        /* Plausibility: a pixel disparity within the frame's width, a
         * vergence angle below 180 degrees. */
        bool px = g_in_px(s);
        if (!s->unknown[i] && (px ? fabs(v) > s->w : v >= VERGENCE_MAX)) {
            char path[PATH_CAP];
            frame_path(&s->pg, t, path);
            if (px)
                vg_error("%s: g is %g pixels at pixel (%d, %d), more than the frame's width (%d): not a disparity of "
                         "these frames%s", path, v, i % s->w, i / s->w, s->w,
                         !s->g_png && v > 0 ? " (it looks like vergence in arcmin, not pixel disparity: drop "
                                              "--g-units px if it is)" : "");
            else
                vg_error("%s: g is %g arcmin at pixel (%d, %d): a vergence angle lies in (0, %.0f) arcmin (0 to "
                         "180 degrees)", path, v, i % s->w, i / s->w, VERGENCE_MAX);
            vg_imagef_free(&img);
            return VG_ERR_FORMAT;
        }
        if (px)
            v = stereo_vergence_from_dataset_px(&s->disp, v, s->d->px_zero, s->w);
        /* Vergence is positive (DESIGN.md); a divergent value is clamped. */
        if (!(v > 0.5)) {
            v = 0.5;
            bad++;
        }
        if (out)
            out[i] = (float)v;
        s->g_min = fmin(s->g_min, v);
        s->g_max = fmax(s->g_max, v);
    }
    if (bad) {
        char path[PATH_CAP];
        frame_path(&s->pg, t, path);
        vg_warn("%s: %d pixels beyond infinity for this display (vergence <= 0), clamped to 0.5 arcmin", path, bad);
    }
    vg_imagef_free(&img);
    return VG_OK;
}

static vg_status read_plane(seq *s, const disp_pattern *p, int t, const char *what, float *out)
{
    vg_imagef img = {0};
    vg_status st = read_frame(s, p, t, 1, what, &img, false);
    /* A depth is a distance in front of the camera. */
    for (int i = 0; st == VG_OK && p == &s->pz && i < img.width * img.height; i++)
        if (!(img.data[i] > 0)) {
            char path[PATH_CAP];
            frame_path(p, t, path);
            vg_error("%s: depth %g at pixel (%d, %d): depths must be > 0 (metres in front of the camera)", path,
                     img.data[i], i % img.width, i / img.width);
            st = VG_ERR_FORMAT;
        }
    /* h is vergence, as g. */
    for (int i = 0; st == VG_OK && p == &s->ph && i < img.width * img.height; i++)
        if (!(img.data[i] > 0 && img.data[i] < VERGENCE_MAX)) {
            char path[PATH_CAP];
            frame_path(p, t, path);
            vg_error("%s: h is %g arcmin at pixel (%d, %d): a vergence angle lies in (0, %.0f) arcmin (0 to 180 "
                     "degrees)", path, img.data[i], i % img.width, i / img.width, VERGENCE_MAX);
            st = VG_ERR_FORMAT;
        }
    if (st == VG_OK && out)
        memcpy(out, img.data, (size_t)s->w * s->h * sizeof(float));
    vg_imagef_free(&img);
    return st;
}

/* An 8-bit PNG of frame t with `comp` channels, of the sequence's size;
 * *out (freed with free()) or, without out, only checked. */
static vg_status read_png_frame(seq *s, const disp_pattern *p, int t, int comp, const char *what, uint8_t **out)
{
    char path[PATH_CAP];
    vg_status st = frame_path(p, t, path);
    int w, h;
    uint8_t *px = NULL;
    if (st == VG_OK)
        st = vg_png_read(path, &w, &h, comp, &px);
    if (st == VG_OK && (w != s->w || h != s->h)) {
        vg_error("%s: %s is %dx%d but the sequence is %dx%d (all frames must have the same size)", path, what, w, h,
                 s->w, s->h);
        st = VG_ERR_FORMAT;
    }
    if (st == VG_OK && out)
        *out = px;
    else
        free(px);
    return st;
}

/* An 8-bit PNG of a frame as floats: grey saliency in [0, 1] (comp 1), or
 * instance ids as capture writes them (comp 3: 24-bit RGB, R the low byte). */
static vg_status read_png_floats(seq *s, const disp_pattern *p, int t, int comp, const char *what, float *out)
{
    uint8_t *px;
    vg_status st = read_png_frame(s, p, t, comp, what, out ? &px : NULL);
    for (int i = 0; st == VG_OK && out && i < s->w * s->h; i++)
        out[i] = comp == 1 ? px[i] / 255.0f : (float)(px[3 * i] | px[3 * i + 1] << 8 | px[3 * i + 2] << 16);
    if (st == VG_OK && out)
        free(px);
    return st;
}

static vg_status read_saliency(seq *s, int t, float *out) { return read_png_floats(s, &s->ps, t, 1, "saliency", out); }
static vg_status read_ids(seq *s, int t, float *out) { return read_png_floats(s, &s->pid, t, 3, "ids", out); }

/* The view of frame t (--image), RGB; *out is freed with free(). */
static vg_status read_image(seq *s, int t, uint8_t **out)
{
    return read_png_frame(s, &s->pim, t, 3, "the image", out);
}

/* Flow of frame t to t+1 (next) or t-1 (prev). A missing direction is
 * approximated by the other one negated at the same pixel (docs/method.md);
 * no flow at all means a static camera and scene. */
static vg_status read_flow(seq *s, int t, bool next, float *out)
{
    size_t n = (size_t)s->w * s->h * 2;
    bool have = next ? s->has_fn : s->has_fp, other = next ? s->has_fp : s->has_fn;
    int tt = have ? t : (next ? t + 1 : t - 1);
    if (!have && !other) {
        if (out)
            memset(out, 0, n * sizeof(float));
        return VG_OK;
    }
    vg_imagef img = {0};
    vg_status st = read_frame(s, have ? (next ? &s->pfn : &s->pfp) : (next ? &s->pfp : &s->pfn), tt, 2,
                              "flow", &img, false);
    if (st != VG_OK)
        return st;
    for (size_t i = 0; out && i < n; i++)
        out[i] = have ? img.data[i] : -img.data[i];
    vg_imagef_free(&img);
    return VG_OK;
}

static vg_status frame_depth(seq *s, int t, const float *g, float *z);

static float srgb_linear(uint8_t v) { return vg_srgb_to_linear(v / 255.0f); }

/* Saliency of frame t when none is given: the engine's formula
 * (disp_saliency_computed, docs/method.md section 3) from what the sequence
 * has: the colour contrast of --image to the frame's mean colour (0 without
 * it), the speed of the flow to the next frame (or keyframe) per keyframe
 * interval, and the nearness of the depth against its mean. */
static vg_status computed_saliency(seq *s, int t, const float *g, float *out)
{
    size_t np = (size_t)s->w * s->h;
    float *z = s->sal_scratch, *flow = s->sal_scratch + np;
    uint8_t *rgb = NULL;
    vg_status st = frame_depth(s, t, g, z);
    if (st == VG_OK) /* the last frame has no next one: its flow to the previous */
        st = read_flow(s, t, t < s->d->last, flow);
    if (st == VG_OK && s->has_im)
        st = read_image(s, t, &rgb);
    if (st != VG_OK)
        return st;
    double zs = 0, mean[3] = {0, 0, 0};
    long known = 0;
    for (size_t i = 0; i < np; i++) {
        if (!isfinite(g[i]) || !(z[i] > 0))
            continue;
        zs += z[i];
        for (int k = 0; rgb && k < 3; k++)
            mean[k] += srgb_linear(rgb[3 * i + (size_t)k]);
        known++;
    }
    float zc = known ? (float)(zs / known) : 1.0f, m[3];
    for (int k = 0; k < 3; k++)
        m[k] = known ? (float)(mean[k] / known) : 0.0f;
    /* Flows to the keyframe span the frames to it; frame flows one. */
    int phase = (t - s->d->first) % s->stride, to_key = t < s->d->last ? s->stride - phase : (phase ? phase : s->stride);
    float per_interval = (float)s->stride / (float)(s->d->flow_to_keyframe ? to_key : 1) / (float)s->w;
    for (size_t i = 0; i < np; i++) {
        if (!isfinite(g[i]) || !(z[i] > 0)) {
            out[i] = 0.0f;
            continue;
        }
        float de = rgb ? disp_delta_e(srgb_linear(rgb[3 * i]), srgb_linear(rgb[3 * i + 1]), srgb_linear(rgb[3 * i + 2]),
                                      m[0], m[1], m[2])
                       : 0.0f;
        float speed = sqrtf(flow[2 * i] * flow[2 * i] + flow[2 * i + 1] * flow[2 * i + 1]) * per_interval;
        out[i] = disp_saliency_computed(de, speed, z[i], zc);
    }
    free(rgb);
    return VG_OK;
}

/* h of frame t: from --h, or the operator (called in frame order). */
static vg_status frame_h(seq *s, int t, const float *g, float *h)
{
    if (s->has_h)
        return read_plane(s, &s->ph, t, "h", h);
    const float *sal = NULL;
    if (s->has_s || s->computed_sal) {
        vg_status st = s->has_s ? read_saliency(s, t, s->sal) : computed_saliency(s, t, g, s->sal);
        if (st != VG_OK)
            return st;
        sal = s->sal;
    }
    disp_operator_apply(s->op, g, sal, s->w * s->h, h, s->pool);
    return VG_OK;
}

/* Depth from --depth, else the perceived distance of g (only depth ratios
 * are used, by the occlusion tests). */
static vg_status frame_depth(seq *s, int t, const float *g, float *z)
{
    if (s->has_z)
        return read_plane(s, &s->pz, t, "depth", z);
    for (int i = 0; i < s->w * s->h; i++)
        z[i] = (float)stereo_distance_from_vergence(&s->disp, g[i]);
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Passes                                                                    */
/* ------------------------------------------------------------------------- */

/* A: every input read once, so that a bad file fails the run before any output. */
/* Values that look like the other unit: vergence is positive and, for
 * content made for the display, mostly near the screen's (a point 4x
 * farther than the screen has about a quarter of it); dataset pixels are
 * small against the image width and may be 0 or negative. */
static void warn_units(const seq *s)
{
    if (s->raw_min > s->raw_max)
        return; /* nothing known */
    double screen = s->disp.screen_vergence;
    if (!g_in_px(s) && (s->raw_min <= 0 || s->raw_median < 0.25 * screen))
        vg_warn("optimize: g runs from %.4g to %.4g: that looks like pixel disparity, not vergence in arcmin "
                "(positive, mostly near %.0f, the screen's, for this display): give --g-units px if it is",
                s->raw_min, s->raw_max, screen);
    else if (g_in_px(s) && s->raw_median > 0.25 * s->w)
        vg_warn("optimize: g runs from %.4g to %.4g pixels on %d-pixel-wide frames: that looks like vergence in "
                "arcmin, not pixel disparity: drop --g-units px if it is", s->raw_min, s->raw_max, s->w);
}

static vg_status pass_validate(seq *s)
{
    const offline_desc *d = s->d;
    vg_status st = VG_OK;
    for (int t = d->first; t <= d->last && st == VG_OK; t++) {
        vg_progress("optimize: checking inputs", t - d->first, s->frames);
        st = read_g(s, t, NULL);
        if (st == VG_OK && s->has_h)
            st = read_plane(s, &s->ph, t, "h", NULL);
        if (st == VG_OK && s->has_z)
            st = read_plane(s, &s->pz, t, "depth", NULL);
        if (st == VG_OK && s->has_fn && t < d->last)
            st = read_flow(s, t, true, NULL);
        if (st == VG_OK && s->has_fp && t > d->first)
            st = read_flow(s, t, false, NULL);
        if (st == VG_OK && s->has_s)
            st = read_saliency(s, t, NULL);
        if (st == VG_OK && s->has_id)
            st = read_ids(s, t, NULL);
        if (st == VG_OK && s->has_im)
            st = read_image(s, t, NULL);
    }
    if (st == VG_OK)
        vg_progress("optimize: checking inputs", s->frames, s->frames);
    if (st == VG_OK && s->unknown_total)
        vg_info("optimize: %ld pixels of unknown g (inf, or KITTI's 0): left out of the costs and the metrics, "
                "inf in f, grey in the previews", s->unknown_total);
    if (st == VG_OK && d->row >= s->h) {
        vg_error("optimize: --row %d: the frames have %d rows (0 to %d)", d->row, s->h, s->h - 1);
        st = VG_ERR_ARG;
    }
    if (st == VG_OK)
        warn_units(s);
    /* Motion in depth is measured by its acceleration: the change of velocity
     * between keyframes, so three keyframes at least. */
    if (st == VG_OK && s->nt < 3) {
        vg_error("optimize: --frames %d:%d is %d frame(s): %d keyframe(s) at --keyframe-stride %d, and the "
                 "acceleration in depth needs 3 (give %d frames or more, or a smaller --keyframe-stride)",
                 d->first, d->last, s->frames, s->nt, s->stride,
                 d->flow_to_keyframe ? 2 * s->stride + 1 : s->stride > 1 ? s->stride + 2 : 3);
        st = VG_ERR_ARG;
    }
    return st;
}

/* Keyframe positions tracked through the per-frame flows from frame a to b
 * (forward when b > a), as coarse-pixel flows of the window. */
static vg_status keyframe_flow(seq *s, int a, int b, float *flow_c, float *scratch, float *pos)
{
    int nc = s->grid.nx * s->grid.ny;
    disp_grid_positions(&s->grid, pos);
    /* Flows to the keyframes hold the whole interval in one step. */
    for (int t = a; t != b; t = s->d->flow_to_keyframe ? b : t + (b > a ? 1 : -1)) {
        vg_status st = read_flow(s, t, b > a, scratch);
        if (st != VG_OK)
            return st;
        disp_flow_advect(scratch, s->w, s->h, pos, nc);
    }
    float half = (float)(s->grid.stride / 2), inv = 1.0f / (float)s->grid.stride;
    for (int q = 0; q < nc; q++) {
        /* Coarse coordinates of the uniform grid; lost points leave the frame. */
        bool lost = isnan(pos[2 * q]);
        flow_c[2 * q] = lost ? 1e6f : (pos[2 * q] - half) * inv - (float)(q % s->grid.nx);
        flow_c[2 * q + 1] = lost ? 1e6f : (pos[2 * q + 1] - half) * inv - (float)(q / s->grid.nx);
    }
    return VG_OK;
}

/* B: h per frame, keyframe samples and keyframe flows into the window. */
static vg_status pass_keyframes(seq *s, mid_window *w, float *g, float *h, float *z, float *scratch, float *pos)
{
    /* Only lang-smoothed has state that needs the frames between keyframes. */
    bool every_frame = !s->has_h && s->d->op == DISP_OPERATOR_LANG_SMOOTHED;
    disp_operator_reset(s->op);
    for (int k = 0; k < s->nt; k++) {
        vg_progress("optimize: keyframes", k, s->nt);
        int t0 = s->key[k], t_end = k + 1 < s->nt ? s->key[k + 1] : t0 + 1;
        for (int t = t0; t < t_end; t++) {
            if (t != t0 && !every_frame)
                continue;
            vg_status st = read_g(s, t, g);
            if (st == VG_OK)
                st = frame_h(s, t, g, h);
            if (st == VG_OK && t == t0)
                st = frame_depth(s, t, g, z);
            if (st != VG_OK)
                return st;
            if (t == t0) {
                size_t o = (size_t)k * w->ns;
                disp_grid_sample(&s->grid, g, 1, w->g + o);
                disp_grid_sample(&s->grid, h, 1, w->h + o);
                disp_grid_sample(&s->grid, z, 1, w->depth + o);
                if (s->has_id) { /* z is free again */
                    vg_status st = read_ids(s, t, z);
                    if (st != VG_OK)
                        return st;
                    disp_grid_sample(&s->grid, z, 1, w->id + o);
                }
                /* Samples on unknown g: out of the costs and the metrics. */
                for (int q = 0; q < w->ns; q++)
                    w->unknown[o + q] = s->unknown[(size_t)disp_grid_py(&s->grid, q / s->grid.nx) * s->w +
                                                   disp_grid_px(&s->grid, q % s->grid.nx)];
            }
        }
        if (k + 1 < s->nt) {
            w->dt[k] = (float)((s->key[k + 1] - t0) / s->fps);
            vg_status st = keyframe_flow(s, t0, s->key[k + 1], w->flow_fwd + (size_t)2 * k * w->ns, scratch, pos);
            if (st == VG_OK)
                st = keyframe_flow(s, s->key[k + 1], t0, w->flow_bwd + (size_t)2 * (k + 1) * w->ns, scratch, pos);
            if (st != VG_OK)
                return st;
        }
    }
    vg_progress("optimize: keyframes", s->nt, s->nt);
    return VG_OK;
}

/* Output buffers of pass C. */
typedef struct outputs {
    float *slice_g, *slice_h, *slice_f; /* frames x width */
    float *f_key;                       /* coarse samples of the written f at keyframes (n) */
    long h_out, f_out;                  /* full-resolution samples outside the range */
} outputs;

/* The colour scale of a map: g its own range, h and f the target range. */
static void map_scale(const seq *s, int m, float *lo, float *hi)
{
    *lo = (float)(m == 0 ? s->g_min : s->lo);
    *hi = (float)(m == 0 ? s->g_max : s->hi);
}

static const char *const k_maps[3] = {"g", "h", "f"};

/* The middle frame of each map as a colour PNG with a legend. */
static vg_status write_previews(const seq *s, int t, const float *const maps[3])
{
    vg_status st = VG_OK;
    for (int m = 0; m < 3 && st == VG_OK; m++) {
        char name[32], path[PATH_CAP], title[96];
        float lo, hi;
        map_scale(s, m, &lo, &hi);
        snprintf(name, sizeof name, "preview_%s.png", k_maps[m]);
        snprintf(title, sizeof title, "%s, frame %d: vergence", k_maps[m], t);
        st = vg_path_join(path, sizeof path, s->d->out_dir, name);
        if (st == VG_OK)
            st = figure_map_png(path, maps[m], s->w, s->h, 1, lo, hi, &(figure_legend){.title = title, .unit = "arcmin"});
    }
    /* The operator's saliency of that frame (frame_h just filled it). */
    if (st == VG_OK && (s->has_s || s->computed_sal)) {
        char path[PATH_CAP], title[96];
        snprintf(title, sizeof title, "saliency (%s), frame %d", s->has_s ? "--saliency" : "computed", t);
        st = vg_path_join(path, sizeof path, s->d->out_dir, "preview_saliency.png");
        if (st == VG_OK)
            st = figure_map_png(path, s->sal, s->w, s->h, 1, 0.0f, 1.0f, &(figure_legend){.title = title, .unit = ""});
    }
    return st;
}

/* One video per map (g.mp4, h.mp4, f.mp4) when ffmpeg is installed. */
static void videos_open(const seq *s, figure_video *v[3])
{
    char ffmpeg[PATH_CAP];
    const char *exe = s->d->video ? figure_find_ffmpeg(ffmpeg, sizeof ffmpeg) : NULL;
    for (int m = 0; m < 3; m++) {
        char name[16], path[PATH_CAP];
        snprintf(name, sizeof name, "%s.mp4", k_maps[m]);
        v[m] = exe && vg_path_join(path, sizeof path, s->d->out_dir, name) == VG_OK
                   ? figure_video_open(exe, path, s->w, s->h, s->fps)
                   : NULL;
    }
    if (s->d->video && !exe)
        vg_info("optimize: ffmpeg is not installed (Debian package ffmpeg): previews without videos");
}

static void videos_frame(const seq *s, figure_video *v[3], const float *const maps[3], uint8_t *rgb)
{
    for (int m = 0; m < 3; m++) {
        if (!v[m])
            continue;
        float lo, hi;
        map_scale(s, m, &lo, &hi);
        figure_map_rgb(maps[m], s->w, s->h, 1, lo, hi, rgb);
        figure_video_frame(&v[m], rgb);
    }
}

/* The new stereo pair of frame t from f: the image's pixels move to where
 * f puts them in each eye, the engine's image warping (warp/image_warp.h,
 * the pass imagewarp.left/right), then the hole fill. With P(a) the image
 * parallax of vergence a (x_right - x_left, pixels of this image across the
 * panel width) and the image at s on the baseline (0 the centre view, -1/2
 * the left), a pixel at x moves to x - s P(g) + e P(f), e = -1/2 left, +1/2
 * right. Writes left_NNNN.png, right_NNNN.png and a side-by-side video frame. */
static vg_status write_pair(seq *s, int t, const float *g, const float *f, const float *z, figure_video **video)
{
    size_t np = (size_t)s->w * s->h;
    uint8_t *src = NULL, *eye = malloc(np * 3), *hole = malloc(np), *sbs = *video ? malloc(2 * np * 3) : NULL;
    float *shift = malloc(np * sizeof(float)), *zo = malloc(np * sizeof(float));
    double *pf = malloc(np * sizeof(double)), *pg = malloc(np * sizeof(double));
    vg_status st = eye && hole && shift && zo && pf && pg && (sbs || !*video) ? read_image(s, t, &src) : VG_ERR_NOMEM;
    double to_px = (double)s->w / s->disp.width_m, at = image_left(s) ? -0.5 : 0.0;
    for (size_t i = 0; st == VG_OK && i < np; i++) { /* once for both eyes */
        pf[i] = stereo_parallax_from_vergence(&s->disp, f[i]);
        pg[i] = at * stereo_parallax_from_vergence(&s->disp, g[i]);
    }
    for (int e = 0; e < 2 && st == VG_OK; e++) {
        double side = e ? 0.5 : -0.5;
        for (size_t i = 0; i < np; i++)
            shift[i] = (float)(to_px * (side * pf[i] - pg[i]));
        long holes = image_warp(src, s->w, s->h, 3, shift, z, eye, zo, hole);
        if (holes < 0) {
            st = VG_ERR_NOMEM;
            break;
        }
        s->holes += holes;
        image_warp_fill(eye, s->w, s->h, 3, zo, hole);
        char name[64], path[PATH_CAP];
        snprintf(name, sizeof name, "%s_%04d.png", e ? "right" : "left", t);
        st = vg_path_join(path, sizeof path, s->d->out_dir, name);
        if (st == VG_OK)
            st = vg_png_write(path, s->w, s->h, 3, eye);
        for (int y = 0; sbs && y < s->h; y++)
            memcpy(sbs + ((size_t)y * 2 * s->w + (size_t)e * s->w) * 3, eye + (size_t)y * s->w * 3, (size_t)s->w * 3);
    }
    if (st == VG_OK && sbs)
        figure_video_frame(video, sbs);
    free(src); free(eye); free(hole); free(sbs); free(shift); free(zo); free(pf); free(pg);
    return st;
}

/* C: upsample the keyframe correction to every frame and write f (and the
 * previews and videos of g, h and f). */
static vg_status pass_output(seq *s, const mid_window *w, const float *f_sol, outputs *o)
{
    const offline_desc *d = s->d;
    size_t np = (size_t)s->w * s->h, nf2 = 2 * np;
    int nc = w->ns, row = d->row >= 0 && d->row < s->h ? d->row : s->h / 2;
    float *g = malloc(np * sizeof(float)), *h = malloc(np * sizeof(float)), *z = malloc(np * sizeof(float));
    float *f = malloc(np * sizeof(float)), *ratio = malloc((size_t)w->n * sizeof(float));
    float *slope = malloc((size_t)w->n * sizeof(float));
    float *zc = malloc(nc * sizeof(float)), *rt = malloc(nc * sizeof(float)), *idc = malloc(nc * sizeof(float));
    float *gc = malloc(nc * sizeof(float)), *hc = malloc(nc * sizeof(float));
    float *pos0 = malloc(2 * (size_t)nc * sizeof(float)), *pos1 = malloc(2 * (size_t)nc * sizeof(float));
    float *prev = malloc((size_t)s->stride * nf2 * sizeof(float)), *next = malloc((size_t)s->stride * nf2 * sizeof(float));
    uint8_t *rgb = malloc(np * 3);
    figure_video *video[3] = {NULL, NULL, NULL}, *pair_video = NULL;
    vg_status st = VG_OK;
    if (!g || !h || !z || !f || !ratio || !slope || !zc || !rt || !idc || !gc || !hc || !pos0 || !pos1 || !prev ||
        !next || !rgb) {
        st = VG_ERR_NOMEM;
        goto done;
    }
    videos_open(s, video);
    if (video[0] && s->has_im) { /* ffmpeg is there: the new pair side by side */
        char ffmpeg[PATH_CAP], path[PATH_CAP];
        if (figure_find_ffmpeg(ffmpeg, sizeof ffmpeg) &&
            vg_path_join(path, sizeof path, d->out_dir, "stereo.mp4") == VG_OK)
            pair_video = figure_video_open(ffmpeg, path, 2 * s->w, s->h, s->fps);
    }
    /* Fig. 4: the correction is the ratio f / g (vergence is never 0),
     * applied to each frame's g (mid_ratio_to_h); under the causal gate
     * f / h, applied to h, so that a closed gate shows h at every frame. */
    bool of_h = d->causal;
    for (int i = 0; i < w->n; i++)
        ratio[i] = f_sol[i] / (of_h ? w->h[i] : w->g[i]);
    mid_window_ratio_slopes(w, ratio, slope);
    disp_upsample_desc ud = {.grid = s->grid, .occlusion_tolerance = d->occlusion_tolerance,
                             .range_lo = (float)s->lo, .range_hi = (float)s->hi};
    disp_operator_reset(s->op);
    for (int k = 0; k < s->nt && st == VG_OK; k++) {
        int t0 = s->key[k], t1 = k + 1 < s->nt ? s->key[k + 1] : t0;
        int t_end = k + 1 < s->nt ? t1 : t0 + 1;
        /* The segment's per-frame flows, held for the tracking of each frame
         * (with flows to the keyframes, each frame's own). */
        for (int t = t0 + 1; t < t1 && st == VG_OK; t++) {
            st = read_flow(s, t, false, prev + (size_t)(t - t0) * nf2);
            if (st == VG_OK)
                st = read_flow(s, t, true, next + (size_t)(t - t0) * nf2);
        }
        size_t ko = (size_t)k * nc;
        disp_keyframe_view k0 = {pos0, ratio + ko, slope + ko, w->depth + ko, w->id + ko, w->flow_fwd + 2 * ko,
                                 of_h ? NULL : w->g + ko, of_h ? NULL : w->h + ko};
        disp_keyframe_view k1 = {pos1, ratio + ko + nc, slope + ko + nc, w->depth + ko + nc, w->id + ko + nc,
                                 w->flow_bwd + 2 * (ko + nc), of_h ? NULL : w->g + ko + nc, of_h ? NULL : w->h + ko + nc};
        bool has1 = k + 1 < s->nt;
        float span = has1 && w->inv_dt_f[k] > 0 ? 1.0f / w->inv_dt_f[k] : 0.0f;
        for (int t = t0; t < t_end && st == VG_OK; t++) {
            vg_progress("optimize: writing", t - d->first, s->frames);
            st = read_g(s, t, g);
            if (st == VG_OK)
                st = frame_h(s, t, g, h);
            if (st == VG_OK)
                st = frame_depth(s, t, g, z);
            if (st != VG_OK)
                break;
            disp_grid_sample(&s->grid, z, 1, zc);
            disp_grid_sample(&s->grid, g, 1, gc);
            disp_grid_sample(&s->grid, h, 1, hc);
            if (s->has_id) { /* f is free until the upsampling */
                if ((st = read_ids(s, t, f)) != VG_OK)
                    break;
                disp_grid_sample(&s->grid, f, 1, idc);
            }
            /* Where frame t's coarse samples are in the two keyframes. */
            bool direct = d->flow_to_keyframe;
            disp_grid_positions(&s->grid, pos0);
            for (int m = t; m > t0; m = direct ? t0 : m - 1)
                disp_flow_advect(prev + (size_t)(m - t0) * nf2, s->w, s->h, pos0, nc);
            disp_grid_positions(&s->grid, pos1);
            for (int m = t; m < t1 && t > t0; m = direct ? t1 : m + 1) /* at a keyframe only k0 counts */
                disp_flow_advect(next + (size_t)(m - t0) * nf2, s->w, s->h, pos1, nc);
            float tau = t1 > t0 ? (float)(t - t0) / (float)(t1 - t0) : 0.0f;
            disp_upsample_temporal(&ud, tau, span, zc, s->has_id ? idc : NULL, of_h ? NULL : gc, of_h ? NULL : hc,
                                   &k0, has1 ? &k1 : NULL, rt, s->pool);
            disp_upsample_spatial(&ud, h, rt, f, s->pool);
            /* A result is a vergence at every known pixel: never a map of
             * NaN or zeros written as if it were one (issue 44). */
            for (size_t i = 0; i < np; i++)
                if (!s->unknown[i] && !(f[i] > 0 && f[i] < VERGENCE_MAX)) {
                    vg_error("optimize: f of frame %d is %g at pixel (%d, %d) (g %g, h %g arcmin): the solver failed "
                             "on these inputs; nothing more is written", t, f[i], (int)(i % (size_t)s->w),
                             (int)(i / (size_t)s->w), g[i], h[i]);
                    st = VG_ERR_UNSUPPORTED;
                    break;
                }
            if (st != VG_OK)
                break;
            if (t == t0)
                disp_grid_sample(&s->grid, f, 1, o->f_key + (size_t)k * nc);
            for (size_t i = 0; i < np; i++) {
                if (s->unknown[i])
                    continue;
                o->h_out += !disp_metrics_in_range(h[i], (float)s->lo, (float)s->hi);
                o->f_out += !disp_metrics_in_range(f[i], (float)s->lo, (float)s->hi);
            }
            if (s->has_im && (st = write_pair(s, t, g, f, z, &pair_video)) != VG_OK)
                break;
            /* Unknown g stays unknown: inf in f as written, grey in every picture. */
            for (size_t i = 0; i < np; i++)
                if (s->unknown[i])
                    g[i] = h[i] = f[i] = INFINITY;
            char path[PATH_CAP], name[64];
            snprintf(name, sizeof name, "f_%04d.pfm", t);
            st = vg_path_join(path, sizeof path, d->out_dir, name);
            vg_imagef img = {.width = s->w, .height = s->h, .channels = 1, .data = f};
            if (st == VG_OK)
                st = vg_pfm_write(path, &img);
            const float *const maps[3] = {g, h, f};
            videos_frame(s, video, maps, rgb);
            if (st == VG_OK && t == d->first + (d->last - d->first) / 2)
                st = write_previews(s, t, maps);
            size_t r = (size_t)(t - d->first) * s->w, src = (size_t)row * s->w;
            memcpy(o->slice_g + r, g + src, s->w * sizeof(float));
            memcpy(o->slice_h + r, h + src, s->w * sizeof(float));
            memcpy(o->slice_f + r, f + src, s->w * sizeof(float));
        }
    }
    if (st == VG_OK)
        vg_progress("optimize: writing", s->frames, s->frames);
done:
    for (int m = 0; m < 3; m++)
        figure_video_close(video[m]);
    figure_video_close(pair_video);
    free(rgb);
    free(g); free(h); free(z); free(f); free(ratio); free(slope); free(zc); free(rt); free(idc); free(gc); free(hc);
    free(pos0); free(pos1); free(prev); free(next);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Results                                                                   */
/* ------------------------------------------------------------------------- */

/* An x-t slice (time runs down) in colour with a legend. */
static vg_status write_slice(const seq *s, int m, const float *v, float lo, float hi)
{
    char name[32], path[PATH_CAP], title[128];
    const offline_desc *d = s->d;
    snprintf(name, sizeof name, "xt_%s.png", k_maps[m]);
    snprintf(title, sizeof title, "%s at row %d, frames %d-%d down: vergence", k_maps[m],
             d->row >= 0 && d->row < s->h ? d->row : s->h / 2, d->first, d->last);
    vg_status st = vg_path_join(path, sizeof path, d->out_dir, name);
    int repeat = s->frames < 60 ? (60 + s->frames - 1) / s->frames : 1; /* a short clip still reads */
    return st == VG_OK ? figure_map_png(path, v, s->w, s->frames, repeat, lo, hi,
                                        &(figure_legend){.title = title, .unit = "arcmin"})
                       : st;
}

static void json_metrics(vg_json *j, const char *key, const disp_metrics *m, double range_violation)
{
    vg_json_object_begin(j, key);
    vg_json_num(j, "mid_distortion_jnd", m->mid_distortion_jnd);
    vg_json_num(j, "range_violation", range_violation);
    vg_json_num(j, "static_rms", m->static_rms);
    vg_json_num(j, "static_grad_rms", m->static_grad_rms);
    vg_json_int(j, "moving_samples", m->moving_measured);
    vg_json_object_end(j);
}

static vg_status write_results(seq *s, const mid_window *w, const float *f_sol, const outputs *o,
                               const mid_solve_stats *ss)
{
    disp_metrics mh, mf, ms;
    disp_metrics_window(w, w->h, NULL, &mh);
    disp_metrics_window(w, o->f_key, NULL, &mf);
    disp_metrics_window(w, f_sol, NULL, &ms);
    double np = (double)s->w * s->h * s->frames - (double)s->unknown_total; /* pixels of known g */
    if (np < 1)
        np = 1;
    /* g on its own scale; h and f on one, so the two compare pixel for pixel. */
    float lo[2] = {FLT_MAX, FLT_MAX}, hi[2] = {-FLT_MAX, -FLT_MAX};
    size_t n = (size_t)s->w * s->frames;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(o->slice_g[i]))
            continue; /* unknown g */
        lo[0] = fminf(lo[0], o->slice_g[i]), hi[0] = fmaxf(hi[0], o->slice_g[i]);
        lo[1] = fminf(lo[1], fminf(o->slice_h[i], o->slice_f[i]));
        hi[1] = fmaxf(hi[1], fmaxf(o->slice_h[i], o->slice_f[i]));
    }
    const float *slice[3] = {o->slice_g, o->slice_h, o->slice_f};
    vg_status st = VG_OK;
    for (int m = 0; m < 3 && st == VG_OK; m++)
        st = write_slice(s, m, slice[m], lo[m > 0], hi[m > 0]);
    if (st != VG_OK)
        return st;
    vg_json j = {0};
    vg_json_object_begin(&j, NULL);
    json_metrics(&j, "h", &mh, o->h_out / np);
    json_metrics(&j, "f", &mf, o->f_out / np);
    json_metrics(&j, "f_solver", &ms, ms.range_violation);
    if (s->f_ungated) { /* the causal window's f before its gate: what it would show without one */
        disp_metrics mu;
        disp_metrics_window(w, s->f_ungated, NULL, &mu);
        json_metrics(&j, "f_ungated", &mu, mu.range_violation);
        vg_json_num(&j, "ungated_mid_ratio", mh.mid_distortion_jnd > 0 ? mu.mid_distortion_jnd / mh.mid_distortion_jnd : NAN);
    }
    vg_json_num(&j, "mid_reduction", mh.mid_distortion_jnd > 0 ? 1.0 - mf.mid_distortion_jnd / mh.mid_distortion_jnd : 0.0);
    vg_json_num(&j, "mid_ratio", mh.mid_distortion_jnd > 0 ? mf.mid_distortion_jnd / mh.mid_distortion_jnd : NAN);
    vg_json_object_begin(&j, "solve");
    vg_json_str(&j, "solver", s->d->solver == MID_SOLVER_DESCENT ? "descent" : "gauss-newton");
    vg_json_str(&j, "look_ahead", s->d->causal ? "causal" : "foresight");
    vg_json_str(&j, "edge_norm", (const char *[]){"range", "arcmin", "pixel"}[s->d->edge_norm]);
    vg_json_str(&j, "velocity_unit", s->d->velocity_per_keyframe ? "keyframe" : "second");
    if (s->d->causal) { /* cost_h / cost_f: the last window's */
        vg_json_int(&j, "windows", s->windows);
        vg_json_int(&j, "keyframes_behind", s->past);
        vg_json_int(&j, "keyframes_ahead", s->future);
    }
    vg_json_int(&j, "iterations", ss->iterations);
    vg_json_int(&j, "cg_steps", ss->cg_steps);
    vg_json_num(&j, "cost_h", ss->cost_initial);
    vg_json_num(&j, "cost_f", ss->cost_final);
    vg_json_num(&j, "ms", ss->ms);
    vg_json_object_end(&j);
    vg_json_object_begin(&j, "input");
    vg_json_int(&j, "first", s->d->first);
    vg_json_int(&j, "last", s->d->last);
    vg_json_int(&j, "width", s->w);
    vg_json_int(&j, "height", s->h);
    vg_json_int(&j, "keyframes", s->nt);
    vg_json_int(&j, "coarse_width", s->grid.nx);
    vg_json_int(&j, "coarse_height", s->grid.ny);
    vg_json_str(&j, "operator", s->has_h ? "given" : disp_operator_kind_name(s->d->op));
    vg_json_str(&j, "saliency", s->has_s ? "file" : s->computed_sal ? "computed" : "uniform");
    vg_json_str(&j, "g_units", g_in_px(s) ? "px" : "arcmin");
    vg_json_str(&j, "g_file", s->g_png ? s->g_png : "PFM");
    vg_json_num(&j, "g_min", s->g_min);
    vg_json_num(&j, "g_max", s->g_max);
    vg_json_num(&j, "range_lo", s->lo);
    vg_json_num(&j, "range_hi", s->hi);
    vg_json_object_end(&j);
    if (s->has_im) {
        vg_json_object_begin(&j, "stereo_pair");
        vg_json_str(&j, "image_view", image_left(s) ? "left" : "centre");
        vg_json_num(&j, "hole_fraction", s->holes / (2.0 * s->w * s->h * s->frames));
        vg_json_str(&j, "hole_fill", "each run of holes in a row takes its farther neighbour's colour");
        vg_json_object_end(&j);
    }
    stereo_display_json(&j, &s->d->display);
    /* metrics.json is the manifest of the result, written last. */
    st = vg_manifest_files(&s->man, &j);
    vg_json_object_end(&j);
    char path[PATH_CAP];
    if (st == VG_OK)
        st = vg_path_join(path, sizeof path, s->d->out_dir, "metrics.json");
    if (st == VG_OK)
        st = vg_json_write_file(&j, path);
    vg_json_free(&j);
    if (st == VG_OK)
        vg_info("optimize: MID distortion %.3f -> %.3f JND (%.1f %% less), f range violation %.4f, static RMS %.3f arcmin",
                mh.mid_distortion_jnd, mf.mid_distortion_jnd,
                mh.mid_distortion_jnd > 0 ? 100.0 * (1.0 - mf.mid_distortion_jnd / mh.mid_distortion_jnd) : 0.0,
                o->f_out / np, mf.static_rms);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Run                                                                       */
/* ------------------------------------------------------------------------- */

/* What optimize writes into --out: f_NNNN.pfm, the x-t slices, the
 * previews, the videos, metrics.json. */
static bool writes(const char *name)
{
    size_t n = strlen(name);
    for (int m = 0; m < 3; m++) {
        char x[32];
        const char *forms[3] = {"xt_%s.png", "preview_%s.png", "%s.mp4"};
        for (int k = 0; k < 3; k++) {
            snprintf(x, sizeof x, forms[k], k_maps[m]);
            if (!strcmp(name, x))
                return true;
        }
    }
    bool png = n > 4 && !strcmp(name + n - 4, ".png");
    return (!strncmp(name, "f_", 2) && n > 6 && !strcmp(name + n - 4, ".pfm")) || !strcmp(name, "metrics.json") ||
           !strcmp(name, "preview_saliency.png") ||
           (png && (!strncmp(name, "left_", 5) || !strncmp(name, "right_", 6))) || !strcmp(name, "stereo.mp4");
}

static vg_status check_outputs(seq *s)
{
    const offline_desc *d = s->d;
    vg_inputs in = {0};
    struct { const disp_pattern *p; bool has; const char *label; } seqs[] = {
        {&s->pg, true, "--g"}, {&s->ph, s->has_h, "--h"}, {&s->pz, s->has_z, "--depth"},
        {&s->pfn, s->has_fn, "--flow-next"}, {&s->pfp, s->has_fp, "--flow-prev"}, {&s->ps, s->has_s, "--saliency"},
        {&s->pid, s->has_id, "--ids"}, {&s->pim, s->has_im, "--image"}};
    vg_status st = VG_OK;
    /* Each frame is found before the next is named: a range far past the
     * files (--frames 0:99999999) stops at the first missing one, bounded
     * by what exists rather than by the number given; pass A then reports
     * it, in frame order, before anything is written. The flow to the next
     * frame is not read at the last frame, nor the previous at the first. */
    for (size_t k = 0; k < sizeof seqs / sizeof seqs[0] && st == VG_OK; k++)
        for (int t = d->first; seqs[k].has && t <= d->last && st == VG_OK; t++) {
            char path[PATH_CAP];
            bool read = !((seqs[k].p == &s->pfn && t == d->last) || (seqs[k].p == &s->pfp && t == d->first));
            struct stat sb;
            if ((st = frame_path(seqs[k].p, t, path)) != VG_OK)
                break;
            if (read && stat(path, &sb) != 0)
                break;
            st = vg_inputs_add(&in, seqs[k].label, path);
        }
    if (st == VG_OK)
        st = vg_inputs_check_dir(&in, "--out", d->out_dir, "metrics.json", writes);
    vg_inputs_free(&in);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Run                                                                       */
/* ------------------------------------------------------------------------- */

static vg_status parse_patterns(seq *s)
{
    const offline_desc *d = s->d;
    struct { const char *text, *opt; disp_pattern *p; bool *has; } list[] = {
        {d->g, "--g", &s->pg, NULL},          {d->h, "--h", &s->ph, &s->has_h},
        {d->depth, "--depth", &s->pz, &s->has_z}, {d->flow_next, "--flow-next", &s->pfn, &s->has_fn},
        {d->flow_prev, "--flow-prev", &s->pfp, &s->has_fp}, {d->saliency, "--saliency", &s->ps, &s->has_s},
        {d->ids, "--ids", &s->pid, &s->has_id}, {d->image, "--image", &s->pim, &s->has_im},
    };
    for (size_t i = 0; i < sizeof list / sizeof list[0]; i++) {
        if (!list[i].text)
            continue;
        vg_status st = disp_pattern_parse(list[i].text, list[i].opt, list[i].p);
        if (st != VG_OK)
            return st;
        if (list[i].has)
            *list[i].has = true;
    }
    return VG_OK;
}

/* Keyframes every stride frames from the first; the last frame is always one
 * (its interval may be shorter: dt is per interval). Counted before pass A,
 * placed after it: nothing proportional to --frames is allocated before
 * every frame was found. */
static int keyframe_count(const seq *s)
{
    return (s->frames - 1) / s->stride + 1 + ((s->frames - 1) % s->stride != 0);
}

static vg_status place_keyframes(seq *s)
{
    int count = (s->frames - 1) / s->stride + 1;
    bool extra = (s->frames - 1) % s->stride != 0;
    s->nt = count + extra;
    s->key = malloc((size_t)s->nt * sizeof(int));
    if (!s->key)
        return VG_ERR_NOMEM;
    for (int k = 0; k < count; k++)
        s->key[k] = s->d->first + k * s->stride;
    if (extra)
        s->key[s->nt - 1] = s->d->last;
    return VG_OK;
}

vg_status offline_run(const offline_desc *d)
{
    seq s = {.d = d, .g_min = DBL_MAX, .g_max = -DBL_MAX, .raw_min = DBL_MAX, .raw_max = -DBL_MAX};
    mid_window *w = NULL;
    float *g = NULL, *h = NULL, *z = NULL, *scratch = NULL, *pos = NULL, *f_sol = NULL;
    outputs o = {0};
    mid_solve_stats ss = {0};
    if (!d->g || !d->out_dir) {
        vg_error("optimize: --g and --out are required");
        return VG_ERR_ARG;
    }
    if (d->first < 0 || d->last < d->first) {
        vg_error("optimize: --frames %d:%d is not a range of frame numbers >= 0", d->first, d->last);
        return VG_ERR_ARG;
    }
    vg_status st = parse_patterns(&s);
    if (st != VG_OK)
        return st;
    /* Nothing it writes or removes may be an input. */
    if ((st = check_outputs(&s)) != VG_OK)
        return st;
    s.frames = d->last - d->first + 1;
    s.stride = d->keyframe_stride > 0 ? d->keyframe_stride : 10;
    if (d->flow_to_keyframe && (!s.has_fn || !s.has_fp)) {
        vg_error("optimize: flows to the keyframes need both --flow-next and --flow-prev (one is not the other "
                 "negated across a keyframe interval)");
        return VG_ERR_ARG;
    }
    if (d->flow_to_keyframe && (s.frames - 1) % s.stride) {
        vg_error("optimize: flows to the keyframes: --frames %d:%d must end on a keyframe (%d + a multiple of "
                 "--keyframe-stride %d, e.g. %d:%d)", d->first, d->last, d->first, s.stride, d->first,
                 d->first + (s.frames - 1) / s.stride * s.stride);
        return VG_ERR_ARG;
    }
    if (!s.has_fn && !s.has_fp)
        vg_warn("optimize: no --flow-next or --flow-prev: assuming a static camera and scene (zero flow)");
    else if (!s.has_fn || !s.has_fp)
        vg_info("optimize: approximating %s by the other flow negated", s.has_fn ? "--flow-prev" : "--flow-next");
    s.fps = d->fps > 0 ? d->fps : 60.0;
    stereo_display_init(&s.disp, &d->display);
    s.nt = keyframe_count(&s);
    if ((st = vg_pool_create(&(vg_pool_desc){.threads = d->threads}, &s.pool)) != VG_OK ||
        (st = pass_validate(&s)) != VG_OK || (st = place_keyframes(&s)) != VG_OK)
        goto done;
    /* The inputs hold: the earlier result in --out goes (metrics.json first,
     * then its files). */
    if ((st = vg_manifest_begin(&s.man, d->out_dir, "metrics.json")) != VG_OK)
        goto done;
    disp_grid_init(&s.grid, s.w, s.h, d->coarse > 0 ? d->coarse : 5);
    if (s.grid.nx < 2 || s.grid.ny < 2) {
        vg_error("optimize: %dx%d frames give a %dx%d coarse grid; use a smaller --coarse", s.w, s.h, s.grid.nx, s.grid.ny);
        st = VG_ERR_ARG;
        goto done;
    }
    /* The operator's domain is the range of g over the whole sequence. */
    if ((st = disp_operator_create(&(disp_operator_desc){.kind = d->op, .preset = d->preset,
                                                         .screen_vergence = s.disp.screen_vergence,
                                                         .range = d->target_range, .in_min = s.g_min,
                                                         .in_max = s.g_max > s.g_min ? s.g_max : s.g_min + 1e-3,
                                                         .frame_seconds = 1.0 / s.fps},
                                    &s.op)) != VG_OK)
        goto done;
    disp_operator_range(s.op, &s.lo, &s.hi);
    size_t np = (size_t)s.w * s.h;
    g = malloc(np * sizeof(float));
    h = malloc(np * sizeof(float));
    z = malloc(np * sizeof(float));
    s.sal = malloc(np * sizeof(float));
    s.computed_sal = !s.has_s && !s.has_h && !d->uniform_saliency &&
                     (d->op == DISP_OPERATOR_LANG || d->op == DISP_OPERATOR_LANG_SMOOTHED);
    s.sal_scratch = s.computed_sal ? malloc(3 * np * sizeof(float)) : NULL;
    scratch = malloc(2 * np * sizeof(float));
    pos = malloc(2 * (size_t)s.grid.nx * s.grid.ny * sizeof(float));
    if (!g || !h || !z || !s.sal || !scratch || !pos || (s.computed_sal && !s.sal_scratch)) {
        st = VG_ERR_NOMEM;
        goto done;
    }
    float edge_scale = d->edge_norm == OFFLINE_EDGE_ARCMIN  ? 1.0f
                       : d->edge_norm == OFFLINE_EDGE_PIXEL ? 1.0f / (float)s.grid.stride
                                                            : 0.0f;
    if ((st = mid_window_create(&(mid_window_desc){.width = s.grid.nx, .height = s.grid.ny, .keyframes = s.nt,
                                                   .range_lo = (float)s.lo, .range_hi = (float)s.hi,
                                                   .occlusion_tolerance = d->occlusion_tolerance,
                                                   .edge_scale = edge_scale,
                                                   .time_unit = d->velocity_per_keyframe ? (float)(s.stride / s.fps)
                                                                                         : 0.0f},
                                &w)) != VG_OK ||
        (st = pass_keyframes(&s, w, g, h, z, scratch, pos)) != VG_OK ||
        (st = mid_window_build(w, s.pool)) != VG_OK)
        goto done;
    f_sol = malloc((size_t)w->n * sizeof(float));
    o.f_key = malloc((size_t)w->n * sizeof(float));
    o.slice_g = malloc((size_t)s.w * s.frames * sizeof(float));
    o.slice_h = malloc((size_t)s.w * s.frames * sizeof(float));
    o.slice_f = malloc((size_t)s.w * s.frames * sizeof(float));
    if (!f_sol || !o.f_key || !o.slice_g || !o.slice_h || !o.slice_f) {
        st = VG_ERR_NOMEM;
        goto done;
    }
    vg_info("optimize: %d frames of %dx%d, %d keyframes of %dx%d, target range [%.2f, %.2f] arcmin, %d threads",
            s.frames, s.w, s.h, s.nt, s.grid.nx, s.grid.ny, s.lo, s.hi, vg_pool_threads(s.pool));
    mid_solve_desc sd = {.solver = d->solver, .iterations = d->iterations, .cg_iterations = d->cg_iterations,
                         .weights = d->weights, .pool = s.pool};
    if (d->causal) {
        mid_causal_stats cs = {0};
        mid_window_split(MID_WINDOW_SECONDS, s.stride / s.fps, MID_WINDOW_FUTURE, &s.past, &s.future);
        if (!(s.f_ungated = malloc((size_t)w->n * sizeof(float)))) {
            st = VG_ERR_NOMEM;
            goto done;
        }
        if ((st = mid_causal_solve(w, &(mid_causal_desc){.past = s.past, .future = s.future, .solve = sd,
                                                         .keyframe_seconds = (float)(s.stride / s.fps), .gate = true,
                                                         .ungated = s.f_ungated},
                                   f_sol, &cs)) != VG_OK)
            goto done;
        s.windows = cs.windows;
        ss = (mid_solve_stats){.ms = cs.ms, .cost_initial = cs.cost_initial, .cost_final = cs.cost_final};
        vg_info("optimize: causal: %d windows of %d keyframes behind and %d predicted ahead solved in %.1f ms",
                cs.windows, s.past, s.future, cs.ms);
    } else {
        if ((st = mid_solve(w, &sd, f_sol, &ss)) != VG_OK)
            goto done;
        vg_info("optimize: solved in %.1f ms: cost %.5g -> %.5g (%d iterations, %d CG steps)", ss.ms,
                ss.cost_initial, ss.cost_final, ss.iterations, ss.cg_steps);
    }
    if ((st = pass_output(&s, w, f_sol, &o)) == VG_OK)
        st = write_results(&s, w, f_sol, &o, &ss);
done:
    free(g); free(h); free(z); free(scratch); free(pos); free(f_sol); free(s.f_ungated);
    free(o.f_key); free(o.slice_g); free(o.slice_h); free(o.slice_f);
    free(s.sal);
    free(s.sal_scratch);
    free(s.unknown);
    free(s.key);
    mid_window_destroy(w);
    disp_operator_destroy(s.op);
    vg_pool_destroy(s.pool);
    vg_manifest_end(&s.man);
    return st;
}
