/* vergence — `vergence optimize`'s inputs: the file patterns, every frame
 * read and checked against the first g (size, channels, plausible values;
 * one error naming the file), g's units, and the depth. Pass A reads each
 * input once so that a bad file stops the run before anything is written;
 * the later passes read the frames again through the same functions. */
#include "offline_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/clock.h"
#include "core/io.h"
#include "core/log.h"
#include "core/stats.h"
#include "footage/footage.h"

#define FLOW_REACH 4 /* frame widths a flow vector may span (plausibility) */

/* ------------------------------------------------------------------------- */
/* Patterns                                                                  */
/* ------------------------------------------------------------------------- */

vg_status offline_patterns_parse(offline_seq *s)
{
    const offline_desc *d = s->desc;
    struct { const char *text, *opt; disp_pattern *p; bool *has; } list[] = {
        {d->g, "--g", &s->g_pattern, NULL}, /* or from --depth */
        {d->h, "--h", &s->h_pattern, &s->has_h},
        {d->depth, "--depth", &s->depth_pattern, &s->has_depth},
        {d->flow_next, "--flow-next", &s->flow_next_pattern, &s->has_flow_next},
        {d->flow_prev, "--flow-prev", &s->flow_prev_pattern, &s->has_flow_prev},
        {d->saliency, "--saliency", &s->saliency_pattern, &s->has_saliency},
        {d->ids, "--ids", &s->ids_pattern, &s->has_ids},
        {d->image, "--image", &s->image_pattern, &s->has_image},
        {NULL, "--video", &s->image_pattern, &s->has_image},
        {NULL, "--depth-video", &s->depth_pattern, &s->has_depth},
    };
    size_t n = sizeof list / sizeof list[0];
    if (d->video_in || d->depth_video) {
        vg_status st = offline_video_prepare(s);
        if (st != VG_OK)
            return st;
        snprintf(s->video_pattern, sizeof s->video_pattern, "%s/frame_%%d.png", s->video_dir);
        snprintf(s->depth_video_pattern, sizeof s->depth_video_pattern, "%s/depth_%%d.png", s->video_dir);
        list[n - 2].text = d->video_in ? s->video_pattern : NULL;
        list[n - 1].text = d->depth_video ? s->depth_video_pattern : NULL;
    }
    s->g_from_depth = !d->g && (d->depth || d->depth_video);
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

vg_status offline_frame_path(const disp_pattern *p, int t, char *buf)
{
    if (disp_pattern_format(p, t, buf, OFFLINE_PATH_CAP) != VG_OK) {
        vg_error("'%s': file name of frame %d is too long", p->text, t);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

const char *offline_flow_name(offline_flow f)
{
    return f == OFFLINE_FLOW_GIVEN ? "given" : f == OFFLINE_FLOW_COMPUTED ? "computed" : f == OFFLINE_FLOW_NONE ? "none"
                                                                                                            : "auto";
}

/* Where the flows come from (--flow, or what was given), and the flows
 * given fit --flow-to: flows to the keyframes need both directions and a
 * range that ends on a keyframe. */
vg_status offline_check_flows(offline_seq *s)
{
    const offline_desc *d = s->desc;
    bool files = s->has_flow_next || s->has_flow_prev;
    s->flow = d->flow != OFFLINE_FLOW_AUTO ? d->flow
              : files                      ? OFFLINE_FLOW_GIVEN
              : s->has_image               ? OFFLINE_FLOW_COMPUTED
                                           : OFFLINE_FLOW_NONE;
    if (s->flow == OFFLINE_FLOW_GIVEN && !files) {
        vg_error("optimize: --flow given: no flow files named (--flow-next, --flow-prev)");
        return VG_ERR_ARG;
    }
    if (s->flow != OFFLINE_FLOW_GIVEN && files) {
        vg_error("optimize: --flow %s: --flow-next / --flow-prev are not read with it (give one or the other)",
                 offline_flow_name(s->flow));
        return VG_ERR_ARG;
    }
    if (s->flow == OFFLINE_FLOW_COMPUTED && !s->has_image) {
        vg_error("optimize: --flow computed: the flows are computed between consecutive colour frames: give them "
                 "with --image");
        return VG_ERR_ARG;
    }
    if (s->flow == OFFLINE_FLOW_NONE && (d->flow_to_keyframe || d->flow_to_frame)) {
        vg_error("optimize: --flow-to with --flow none: there are no flows");
        return VG_ERR_ARG;
    }
    /* Computed flows go straight to the keyframes: chained frame to frame,
     * the error of each step (a compressed video's noise) adds up. */
    s->flow_direct = d->flow_to_keyframe || (s->flow == OFFLINE_FLOW_COMPUTED && !d->flow_to_frame);
    if (s->flow == OFFLINE_FLOW_GIVEN && d->flow_to_keyframe && (!s->has_flow_next || !s->has_flow_prev)) {
        vg_error("optimize: flows to the keyframes need both --flow-next and --flow-prev (one is not the other "
                 "negated across a keyframe interval)");
        return VG_ERR_ARG;
    }
    if (s->flow == OFFLINE_FLOW_GIVEN && d->flow_to_keyframe && (s->frames - 1) % s->keyframe_stride) {
        vg_error("optimize: flows to the keyframes: --frames %d:%d must end on a keyframe (%d + a multiple of "
                 "--keyframe-stride %d, e.g. %d:%d)", d->first, d->last, d->first, s->keyframe_stride, d->first,
                 d->first + (s->frames - 1) / s->keyframe_stride * s->keyframe_stride);
        return VG_ERR_ARG;
    }
    if (s->flow == OFFLINE_FLOW_NONE) {
        vg_warn("optimize: %s: assuming a static camera and scene (zero flow)%s",
                d->flow == OFFLINE_FLOW_NONE ? "--flow none" : "no --flow-next, --flow-prev or --image",
                d->flow == OFFLINE_FLOW_NONE ? "" : "; give --image to compute the flows from the colour frames");
    } else if (s->flow == OFFLINE_FLOW_COMPUTED) {
        flow_set_threads(d->threads); /* --threads holds for OpenCV's workers too */
        vg_info("optimize: flows computed from the colour frames (DIS optical flow, preset %s, forward-backward "
                "checked), from each frame %s", flow_preset_name(d->flow_preset),
                s->flow_direct ? "to its keyframes" : "to the next and previous frame");
    } else if (!s->has_flow_next || !s->has_flow_prev) {
        vg_info("optimize: approximating %s by the other flow negated",
                s->has_flow_next ? "--flow-prev" : "--flow-next");
    }
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Frames                                                                    */
/* ------------------------------------------------------------------------- */

static bool is_png(const char *path)
{
    size_t n = strlen(path);
    return n > 4 && !strcasecmp(path + n - 4, ".png");
}

/* One float plane of a PFM, or of an OpenEXR or HDF5 file (engine/footage),
 * whose NaN (Spring's unknown) reads as +inf, unknown, as Middlebury's. */
static vg_status read_float_plane(const char *path, vg_imagef *img)
{
    bool exr = footage_is_exr(path), hdf5 = footage_is_hdf5(path);
    if (!exr && !hdf5)
        return vg_pfm_read(path, img);
    vg_status st = exr ? footage_exr_read(path, NULL, img) : footage_hdf5_read(path, NULL, img);
    for (int i = 0; st == VG_OK && i < img->width * img->height; i++)
        if (isnan(img->data[i]))
            img->data[i] = INFINITY;
    return st;
}

/* A depth file's values in metres (offline_desc.depth_scale, depth_inverse):
 * a 16-bit grey PNG (0: unknown, +inf) or a PFM. Each depth must lie in
 * front of the camera (> 0; +inf is unknown or infinitely far). */
static vg_status read_depth(offline_seq *s, const char *path, vg_imagef *img)
{
    const offline_desc *d = s->desc;
    double scale = d->depth_scale > 0 ? d->depth_scale : 1.0;
    bool png = is_png(path);
    vg_status st;
    if (png && !(d->depth_scale > 0)) {
        vg_error("%s: a %s holds depth in integer units: give --depth-scale (metres per unit, e.g. 0.001 for "
                 "millimetres; with --depth-inverse, 1/metres per unit)", d->depth_video ? d->depth_video : path,
                 d->depth_video ? "video" : "PNG");
        return VG_ERR_ARG;
    }
    if (png) {
        if ((st = vg_grey16_png_read(path, img)) != VG_OK)
            return st;
        for (int i = 0; i < img->width * img->height; i++)
            img->data[i] = img->data[i] > 0 ? img->data[i] : INFINITY; /* 0: unknown */
    } else if ((st = read_float_plane(path, img)) != VG_OK)
        return st;
    for (int i = 0; img->channels == 1 && i < img->width * img->height; i++) {
        float v = img->data[i];
        if (isinf(v) && v > 0)
            continue;
        if (!(v > 0) || !isfinite(v)) {
            vg_error("%s: depth %g at pixel (%d, %d): depths must be > 0 (%s)", path, v, i % img->width,
                     i / img->width, d->depth_inverse ? "inverse depth, 1/metres" : "metres in front of the camera");
            vg_imagef_free(img);
            return VG_ERR_FORMAT;
        }
        img->data[i] = (float)(d->depth_inverse ? 1.0 / (v * scale) : v * scale);
    }
    return VG_OK;
}

/* Reads one frame of a single- or two-channel sequence and checks its size
 * against the first g frame: every frame of every input must match. */
static vg_status read_frame(offline_seq *s, const disp_pattern *p, int t, int channels, const char *what,
                            vg_imagef *img, bool inf_unknown)
{
    char path[OFFLINE_PATH_CAP];
    vg_status st = offline_frame_path(p, t, path);
    if (st != VG_OK)
        return st;
    const char *encoding = NULL;
    st = channels == 2                        ? vg_flo_read(path, img)
         : p == &s->g_pattern && is_png(path) ? vg_disparity_png_read(path, img, &encoding)
         : p == &s->depth_pattern             ? read_depth(s, path, img)
                                              : read_float_plane(path, img);
    if (st == VG_OK && p == &s->g_pattern && footage_is_spring(path))
        encoding = "Spring";
    if (st != VG_OK)
        return st;
    if (encoding && !s->g_dataset_png) {
        s->g_dataset_png = encoding;
        vg_info("optimize: %s: %s disparity %s, pixels (x_left - x_right)%s", path, encoding,
                strcmp(encoding, "Spring") ? "PNG" : "HDF5", s->desc->g_units == DISP_G_PX ? "" : ": read as --g-units px");
    }
    if (img->channels != channels) {
        vg_error("%s: %s has %d channels, expected %d", path, what, img->channels, channels);
        vg_imagef_free(img);
        return VG_ERR_FORMAT;
    }
    if (s->width && (img->width != s->width || img->height != s->height)) {
        vg_error("%s: %s is %dx%d but the sequence is %dx%d (all frames must have the same size)", path,
                 what, img->width, img->height, s->width, s->height);
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
static int fill_unknown(offline_seq *s, float *v)
{
    int w = s->width, h = s->height, count = 0, known_row = -1;
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

/* g of a frame as vergence in arcmin (converted from dataset pixels if asked).
 * Without out (pass A) it also counts the unknown pixels and the range of g
 * as read, for the units warning. */
vg_status offline_read_g(offline_seq *s, int t, float *out)
{
    vg_imagef img = {0};
    const disp_pattern *src = s->g_from_depth ? &s->depth_pattern : &s->g_pattern;
    vg_status st = read_frame(s, src, t, 1, s->g_from_depth ? "depth" : "g", &img, true);
    if (st != VG_OK)
        return st;
    /* Without --g: the vergence the display gives the depth through the rig. */
    for (int i = 0; s->g_from_depth && i < img.width * img.height; i++)
        if (!isinf(img.data[i]))
            img.data[i] = (float)stereo_camera_vergence(&s->rig, &s->display, img.data[i]);
    if (!s->width) {
        s->width = img.width;
        s->height = img.height;
        if (!(s->unknown = malloc((size_t)s->width * s->height))) {
            vg_imagef_free(&img);
            return VG_ERR_NOMEM;
        }
    }
    int n = s->width * s->height, bad = 0, unknown = fill_unknown(s, img.data);
    double frame_lo = INFINITY, frame_hi = -INFINITY;
    if (unknown < 0) {
        char path[OFFLINE_PATH_CAP];
        offline_frame_path(src, t, path);
        vg_error("%s: g is unknown (inf) at every pixel", path);
        vg_imagef_free(&img);
        return VG_ERR_FORMAT;
    }
    if (!out)
        s->unknown_total += unknown;
    if (!out && t == s->desc->first) {
        double *known = malloc((size_t)n * sizeof *known);
        size_t k = 0;
        for (int i = 0; known && i < n; i++)
            if (!s->unknown[i])
                known[k++] = img.data[i];
        s->g_raw_median = known && k ? vg_median(known, k, 1) : NAN;
        free(known);
    }
    for (int i = 0; i < n; i++) {
        double v = img.data[i];
        if (!out && !s->unknown[i]) {
            s->g_raw_min = fmin(s->g_raw_min, v);
            s->g_raw_max = fmax(s->g_raw_max, v);
        }
        /* Plausibility: a pixel disparity within the frame's width, a
         * vergence angle below 180 degrees. */
        bool px = offline_g_in_px(s);
        if (!s->unknown[i] && (px ? fabs(v) > s->width : v >= OFFLINE_VERGENCE_MAX)) {
            char path[OFFLINE_PATH_CAP];
            offline_frame_path(src, t, path);
            if (px)
                vg_error("%s: g is %g pixels at pixel (%d, %d), more than the frame's width (%d): not a disparity of "
                         "these frames%s", path, v, i % s->width, i / s->width, s->width,
                         !s->g_dataset_png && v > 0 ? " (it looks like vergence in arcmin, not pixel disparity: "
                                                      "drop --g-units px if it is)" : "");
            else
                vg_error("%s: g is %g arcmin at pixel (%d, %d): a vergence angle lies in (0, %.0f) arcmin (0 to "
                         "180 degrees)", path, v, i % s->width, i / s->width, OFFLINE_VERGENCE_MAX);
            vg_imagef_free(&img);
            return VG_ERR_FORMAT;
        }
        if (px)
            v = stereo_vergence_from_dataset_px(&s->display, v, s->desc->px_zero, s->width);
        /* Vergence is positive (DESIGN.md); a divergent value is clamped. */
        if (!(v > 0.5)) {
            v = 0.5;
            bad++;
        }
        if (out)
            out[i] = (float)v;
        s->g_min = fmin(s->g_min, v);
        s->g_max = fmax(s->g_max, v);
        if (!s->unknown[i])
            frame_lo = fmin(frame_lo, v), frame_hi = fmax(frame_hi, v);
    }
    if (!out && s->desc->ema && (st = offline_ema_record(s, t, frame_lo, frame_hi)) != VG_OK) {
        vg_imagef_free(&img);
        return st;
    }
    if (bad) {
        char path[OFFLINE_PATH_CAP];
        offline_frame_path(src, t, path);
        vg_warn("%s: %d pixels beyond infinity for this display (vergence <= 0), clamped to 0.5 arcmin", path, bad);
    }
    vg_imagef_free(&img);
    return VG_OK;
}

/* A single-channel PFM of the sequence (h or depth) with its plausibility
 * test; without out, only checked. */
static vg_status read_plane(offline_seq *s, const disp_pattern *p, int t, const char *what, float *out)
{
    vg_imagef img = {0};
    bool depth = p == &s->depth_pattern;
    vg_status st = read_frame(s, p, t, 1, what, &img, depth);
    /* Unknown depth (+inf, a PNG's 0) is taken as the background: twice
     * the frame's farthest known depth, for the occlusion tests' ratios. */
    float far = 0;
    for (int i = 0; st == VG_OK && depth && i < img.width * img.height; i++)
        far = isinf(img.data[i]) ? far : fmaxf(far, img.data[i]);
    for (int i = 0; st == VG_OK && depth && i < img.width * img.height; i++)
        if (isinf(img.data[i]))
            img.data[i] = far > 0 ? 2 * far : 1e3f;
    /* h is vergence, as g. */
    for (int i = 0; st == VG_OK && p == &s->h_pattern && i < img.width * img.height; i++)
        if (!(img.data[i] > 0 && img.data[i] < OFFLINE_VERGENCE_MAX)) {
            char path[OFFLINE_PATH_CAP];
            offline_frame_path(p, t, path);
            vg_error("%s: h is %g arcmin at pixel (%d, %d): a vergence angle lies in (0, %.0f) arcmin (0 to 180 "
                     "degrees)", path, img.data[i], i % img.width, i / img.width, OFFLINE_VERGENCE_MAX);
            st = VG_ERR_FORMAT;
        }
    if (st == VG_OK && out)
        memcpy(out, img.data, (size_t)s->width * s->height * sizeof(float));
    vg_imagef_free(&img);
    return st;
}

/* h of frame t from --h. */
vg_status offline_read_h(offline_seq *s, int t, float *out)
{
    return read_plane(s, &s->h_pattern, t, "h", out);
}

/* Depth from --depth, else the perceived distance of g (only depth ratios
 * are used, by the occlusion tests). */
vg_status offline_read_depth(offline_seq *s, int t, const float *g, float *z)
{
    if (s->has_depth)
        return read_plane(s, &s->depth_pattern, t, "depth", z);
    for (int i = 0; i < s->width * s->height; i++)
        z[i] = (float)stereo_distance_from_vergence(&s->display, g[i]);
    return VG_OK;
}

/* An 8-bit PNG of frame t with `comp` channels, of the sequence's size;
 * *out (freed with free()) or, without out, only checked. */
static vg_status read_png_frame(offline_seq *s, const disp_pattern *p, int t, int comp, const char *what,
                                uint8_t **out)
{
    char path[OFFLINE_PATH_CAP];
    vg_status st = offline_frame_path(p, t, path);
    int w, h;
    uint8_t *px = NULL;
    if (st == VG_OK)
        st = vg_png_read(path, &w, &h, comp, &px);
    if (st == VG_OK && (w != s->width || h != s->height)) {
        vg_error("%s: %s is %dx%d but the sequence is %dx%d (all frames must have the same size)", path, what, w, h,
                 s->width, s->height);
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
static vg_status read_png_floats(offline_seq *s, const disp_pattern *p, int t, int comp, const char *what,
                                 float *out)
{
    uint8_t *px;
    vg_status st = read_png_frame(s, p, t, comp, what, out ? &px : NULL);
    for (int i = 0; st == VG_OK && out && i < s->width * s->height; i++)
        out[i] = comp == 1 ? px[i] / 255.0f : (float)(px[3 * i] | px[3 * i + 1] << 8 | px[3 * i + 2] << 16);
    if (st == VG_OK && out)
        free(px);
    return st;
}

vg_status offline_read_saliency(offline_seq *s, int t, float *out)
{
    return read_png_floats(s, &s->saliency_pattern, t, 1, "saliency", out);
}

vg_status offline_read_ids(offline_seq *s, int t, float *out)
{
    return read_png_floats(s, &s->ids_pattern, t, 3, "ids", out);
}

/* The view of frame t (--image), RGB; *out is freed with free(). */
vg_status offline_read_image(offline_seq *s, int t, uint8_t **out)
{
    return read_png_frame(s, &s->image_pattern, t, 3, "the image", out);
}

/* ------------------------------------------------------------------------- */
/* Computed flows                                                            */
/* ------------------------------------------------------------------------- */

#define FLOW_CACHE_BYTES (1024.0 * 1024.0 * 1024.0) /* at most this much held */

void offline_flow_free(offline_seq *s)
{
    for (int k = 0; k < s->flow_slots; k++) {
        free(s->flow_fwd[k]);
        free(s->flow_bwd[k]);
    }
    free(s->flow_fwd);
    free(s->flow_bwd);
    free(s->flow_pair);
    free(s->flow_pair_b);
    free(s->flow_used);
    s->flow_fwd = s->flow_bwd = NULL;
    s->flow_pair = s->flow_pair_b = NULL;
    s->flow_used = NULL;
    s->flow_slots = 0;
}

/* The slots: the pairs of one keyframe interval and one more (direct: each
 * frame's two, 2 stride + 1), so that pass B computes each pair once and
 * pass C once again (1 GiB at most). */
static vg_status flow_slots_alloc(offline_seq *s)
{
    size_t bytes = (size_t)s->width * s->height * 2 * sizeof(float);
    int slots = s->flow_direct ? 2 * s->keyframe_stride + 1 : s->keyframe_stride + 1;
    if (!s->flow_direct && slots > s->frames - 1)
        slots = s->frames - 1 > 0 ? s->frames - 1 : 1;
    while (slots > 2 && 2.0 * bytes * slots > FLOW_CACHE_BYTES)
        slots--;
    s->flow_fwd = calloc((size_t)slots, sizeof *s->flow_fwd);
    s->flow_bwd = calloc((size_t)slots, sizeof *s->flow_bwd);
    s->flow_pair = malloc((size_t)slots * sizeof *s->flow_pair);
    s->flow_pair_b = malloc((size_t)slots * sizeof *s->flow_pair_b);
    s->flow_used = calloc((size_t)slots, sizeof *s->flow_used);
    if (!s->flow_fwd || !s->flow_bwd || !s->flow_pair || !s->flow_pair_b || !s->flow_used)
        return VG_ERR_NOMEM;
    s->flow_slots = slots;
    for (int k = 0; k < slots; k++) {
        s->flow_pair[k] = -1;
        if (!(s->flow_fwd[k] = malloc(bytes)) || !(s->flow_bwd[k] = malloc(bytes)))
            return VG_ERR_NOMEM;
    }
    return VG_OK;
}

/* Flows of the pair (a, b), a < b, into slot k: DIS both ways on the
 * colour frames; where the forward-backward check fails (occluded, or the
 * flow wrong) a pixel takes the flow of the nearest consistent pixel of
 * its row, and the window's own occlusion tests (ids, depth, the round
 * trip: mid_window.c) decide its links. NaN there instead (no link: the
 * advection loses a point when any of its four taps is NaN, at any of the
 * frames to the keyframe) cut the tracks of a small moving object: on a
 * balloon capture f's MID distortion was 7.25 JND against 5.06 filled and
 * 4.92 with the exact flows (docs/formats.md). */
static vg_status flow_compute(offline_seq *s, int a_frame, int b_frame, int k)
{
    size_t np = (size_t)s->width * s->height;
    uint8_t *a = NULL, *b = NULL, *occ = malloc(2 * np);
    float *fwd = s->flow_fwd[k], *bwd = s->flow_bwd[k];
    vg_status st = occ ? VG_OK : VG_ERR_NOMEM;
    s->flow_pair[k] = s->flow_pair_b[k] = -1;
    if (st == VG_OK)
        st = offline_read_image(s, a_frame, &a);
    if (st == VG_OK)
        st = offline_read_image(s, b_frame, &b);
    double t0 = vg_now_ms();
    char what[64];
    snprintf(what, sizeof what, "colour frames %d and %d", a_frame, b_frame);
    if (st == VG_OK)
        st = flow_dis(&(flow_image){a, s->width, s->height, 3}, &(flow_image){b, s->width, s->height, 3},
                      s->desc->flow_preset, what, fwd, bwd);
    if (st == VG_OK) { /* both directions checked before either is masked */
        s->flow_occluded += (double)flow_occlusions(fwd, bwd, s->width, s->height, occ);
        s->flow_occluded += (double)flow_occlusions(bwd, fwd, s->width, s->height, occ + np);
        flow_fill_occluded(fwd, occ, s->width, s->height);
        flow_fill_occluded(bwd, occ + np, s->width, s->height);
        s->flow_pair[k] = a_frame;
        s->flow_pair_b[k] = b_frame;
        s->flow_computed++;
        s->flow_ms += vg_now_ms() - t0;
    }
    free(a);
    free(b);
    free(occ);
    return st;
}

int offline_flow_target(const offline_seq *s, int t, bool next)
{
    if (!s->flow_direct || !s->keyframe_numbers)
        return next ? t + 1 : t - 1;
    const int *key = s->keyframe_numbers;
    if (next) {
        for (int k = 0; k < s->keyframes; k++)
            if (key[k] > t)
                return key[k];
        return t + 1; /* past the last keyframe: none */
    }
    for (int k = s->keyframes - 1; k >= 0; k--)
        if (key[k] < t)
            return key[k];
    return t - 1;
}

/* Computed flow of frame t to the frame offline_flow_target names. */
static vg_status computed_flow(offline_seq *s, int t, bool next, float *out)
{
    const offline_desc *d = s->desc;
    int u = offline_flow_target(s, t, next), a = next ? t : u, b = next ? u : t;
    if (a < d->first || b > d->last) {
        vg_error("optimize: no flow of frame %d to frame %d: --frames is %d:%d", t, u, d->first, d->last);
        return VG_ERR_ARG;
    }
    vg_status st = s->flow_slots ? VG_OK : flow_slots_alloc(s);
    if (st != VG_OK)
        return st;
    int k = -1, lru = 0;
    for (int i = 0; i < s->flow_slots && k < 0; i++) {
        if (s->flow_pair[i] == a && s->flow_pair_b[i] == b)
            k = i;
        else if (s->flow_used[i] < s->flow_used[lru])
            lru = i;
    }
    if (k < 0 && (st = flow_compute(s, a, b, k = lru)) != VG_OK)
        return st;
    s->flow_used[k] = ++s->flow_clock;
    if (out)
        memcpy(out, next ? s->flow_fwd[k] : s->flow_bwd[k], (size_t)s->width * s->height * 2 * sizeof(float));
    return VG_OK;
}

/* Flow of frame t to t+1 (next) or t-1 (prev): computed (NaN where a
 * pixel has no link), none (zero), or given. A missing direction is
 * approximated by the other one negated at the same pixel (docs/method.md). */
vg_status offline_read_flow(offline_seq *s, int t, bool next, float *out)
{
    size_t n = (size_t)s->width * s->height * 2;
    if (s->flow == OFFLINE_FLOW_COMPUTED)
        return computed_flow(s, t, next, out);
    bool have = next ? s->has_flow_next : s->has_flow_prev, other = next ? s->has_flow_prev : s->has_flow_next;
    int tt = have ? t : (next ? t + 1 : t - 1);
    if (s->flow == OFFLINE_FLOW_NONE || (!have && !other)) {
        if (out)
            memset(out, 0, n * sizeof(float));
        return VG_OK;
    }
    const disp_pattern *p = have ? (next ? &s->flow_next_pattern : &s->flow_prev_pattern)
                                 : (next ? &s->flow_prev_pattern : &s->flow_next_pattern);
    vg_imagef img = {0};
    vg_status st = read_frame(s, p, tt, 2, "flow", &img, false);
    if (st != VG_OK)
        return st;
    for (size_t i = 0; out && i < n; i++)
        out[i] = have ? img.data[i] : -img.data[i];
    vg_imagef_free(&img);
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Pass A                                                                    */
/* ------------------------------------------------------------------------- */

/* Values that look like the other unit: vergence is positive and, for
 * content made for the display, mostly near the screen's (a point 4x
 * farther than the screen has about a quarter of it); dataset pixels are
 * small against the image width and may be 0 or negative. */
static void warn_units(const offline_seq *s)
{
    if (s->g_raw_min > s->g_raw_max || s->g_from_depth)
        return; /* nothing known, or g made here from depth */
    double screen = s->display.screen_vergence;
    if (!offline_g_in_px(s) && (s->g_raw_min <= 0 || s->g_raw_median < 0.25 * screen))
        vg_warn("optimize: g runs from %.4g to %.4g: that looks like pixel disparity, not vergence in arcmin "
                "(positive, mostly near %.0f, the screen's, for this display): give --g-units px if it is",
                s->g_raw_min, s->g_raw_max, screen);
    else if (offline_g_in_px(s) && s->g_raw_median > 0.25 * s->width)
        vg_warn("optimize: g runs from %.4g to %.4g pixels on %d-pixel-wide frames: that looks like vergence in "
                "arcmin, not pixel disparity: drop --g-units px if it is", s->g_raw_min, s->g_raw_max, s->width);
}

/* A: every input read once, so that a bad file fails the run before any output. */
vg_status offline_validate(offline_seq *s)
{
    const offline_desc *d = s->desc;
    vg_status st = offline_cuts_begin(s);
    for (int t = d->first; t <= d->last && st == VG_OK; t++) {
        vg_progress("optimize: checking inputs", t - d->first, s->frames);
        st = offline_read_g(s, t, NULL);
        if (st == VG_OK && s->has_h)
            st = read_plane(s, &s->h_pattern, t, "h", NULL);
        if (st == VG_OK && s->has_depth)
            st = read_plane(s, &s->depth_pattern, t, "depth", NULL);
        if (st == VG_OK && s->has_flow_next && t < d->last)
            st = offline_read_flow(s, t, true, NULL);
        if (st == VG_OK && s->has_flow_prev && t > d->first)
            st = offline_read_flow(s, t, false, NULL);
        if (st == VG_OK && s->has_saliency)
            st = offline_read_saliency(s, t, NULL);
        if (st == VG_OK && s->has_ids)
            st = offline_read_ids(s, t, NULL);
        if (st == VG_OK && s->has_image) {
            uint8_t *rgb = NULL;
            st = offline_read_image(s, t, s->cut_hist ? &rgb : NULL);
            if (st == VG_OK)
                st = offline_cuts_feed(s, t, rgb);
            free(rgb);
        }
    }
    offline_cuts_end(s);
    if (st == VG_OK)
        vg_progress("optimize: checking inputs", s->frames, s->frames);
    if (st == VG_OK && s->unknown_total)
        vg_info("optimize: %ld pixels of unknown g (inf, or KITTI's 0): left out of the costs and the metrics, "
                "inf in f, grey in the previews", s->unknown_total);
    if (st == VG_OK && d->row >= s->height) {
        vg_error("optimize: --row %d: the frames have %d rows (0 to %d)", d->row, s->height, s->height - 1);
        st = VG_ERR_ARG;
    }
    if (st == VG_OK && s->flow == OFFLINE_FLOW_COMPUTED && (s->width < FLOW_MIN_SIDE || s->height < FLOW_MIN_SIDE)) {
        vg_error("optimize: --flow computed: the --image frames are %dx%d; the flow needs %d pixels a side (give the "
                 "flows, or --flow none)", s->width, s->height, FLOW_MIN_SIDE);
        st = VG_ERR_ARG;
    }
    if (st == VG_OK)
        warn_units(s);
    /* Motion in depth is measured by its acceleration: the change of velocity
     * between keyframes, so three keyframes at least. */
    s->keyframes = offline_keyframes(s, NULL);
    if (st == VG_OK && s->keyframes < 3) {
        int stride = s->keyframe_stride;
        vg_error("optimize: --frames %d:%d is %d frame(s): %d keyframe(s) at --keyframe-stride %d, and the "
                 "acceleration in depth needs 3 (give %d frames or more, or a smaller --keyframe-stride)",
                 d->first, d->last, s->frames, s->keyframes, stride,
                 s->flow == OFFLINE_FLOW_GIVEN && d->flow_to_keyframe ? 2 * stride + 1 : stride > 1 ? stride + 2 : 3);
        st = VG_ERR_ARG;
    }
    return st;
}
