/* vergence demo — index.html: one self-contained page (inline CSS, no
 * scripts) over the run's files. Every number cell carries where it came
 * from (data-src: a capture.json, data-key: its dotted key, data-value: the
 * exact value), so a test can check the table against the files. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "capture/capture_image.h"
#include "core/io.h"
#include "demo.h"
#include "shared.h"
#include "demo_image.h"
#include "figure/figure.h"
#include "demo_svg.h"
#include "stereo/stereo_perception.h"

#define P(...) demo_buf_printf(b, __VA_ARGS__)

/* What to look for in each of the paper's scenes. */
typedef struct scene_text {
    const char *name, *title, *about, *look;
} scene_text;

static const scene_text k_scenes[] = {
    {"balloon", "Balloon &mdash; paper Fig. 1",
     "A red balloon flies from 25&nbsp;m away up to 3&nbsp;m from the viewer, through the 3&nbsp;m gap between a "
     "cottage and a tree. The manipulation squeezes the empty depth between the landmarks and the horizon into the "
     "comfort range around the screen.",
     "In <b>h</b> the balloon's vergence jumps where the manipulation compresses the gap between house and tree: it "
     "crosses the compressed depth quickly and then slows down, although it really flies at a constant 5.5&nbsp;m/s. "
     "<b>f</b> smooths that change back toward the steady approach of <b>g</b>, while the house and the tree keep "
     "the disparity the manipulation gave them; the table says how much distortion is left."},
    {"cubes", "Cubes &mdash; paper Fig. 2",
     "A small red cube flies away from the viewer, from 3&nbsp;m to 25&nbsp;m, right past a group of static cubes "
     "at 8&ndash;13&nbsp;m.",
     "In <b>h</b> the flying cube's vergence bends where it passes the static cubes (the histogram operator gives "
     "their depth range more room than the empty space around it); <b>f</b> brings the cube's acceleration back "
     "toward that of the original <b>g</b>, so it recedes more steadily."},
    {"bird", "Bird &mdash; deforming objects and camera motion, like paper Fig. 8",
     "A bird flaps its skinned wings as it flies from far behind the windmill toward the viewer, while the camera "
     "dollies forward; a flag waves in the wind (morph targets).",
     "The bird's track in <b>h</b> changes speed as it crosses the depth range the operator compresses between the "
     "windmill and the tree line; <b>f</b> brings back more of its steady approach, while the camera's own motion "
     "moves everything else in depth too."},
};

static const scene_text *scene_text_for(const char *name)
{
    for (size_t i = 0; i < sizeof k_scenes / sizeof k_scenes[0]; i++)
        if (!strcmp(k_scenes[i].name, name))
            return &k_scenes[i];
    return NULL;
}

static const char *const k_mode_text[DEMO_MODES] = {
    "original <b>g</b>: the stereo camera", "manipulated <b>h</b>: the operator", "optimized <b>f</b>: motion in depth restored"};

/* ------------------------------------------------------------------------- */
/* Numbers                                                                   */
/* ------------------------------------------------------------------------- */

/* A table cell showing v (times scale) with `digits` decimals, traceable to
 * SRC/capture.json at KEY. */
static void cell(demo_buf *b, const char *src, const char *key, double v, double scale, int digits, const char *unit)
{
    P("<td data-src=\"%s/capture.json\" data-key=\"%s\" data-scale=\"%g\" data-value=\"", src, key, scale);
    if (isfinite(v))
        P("%.9g\">%.*f%s</td>", v, digits, v * scale, unit);
    else
        P("null\">%s</td>", isinf(v) ? "&infin;" : "&mdash;");
}

static void empty_cells(demo_buf *b, int n)
{
    for (int i = 0; i < n; i++)
        P("<td class=\"na\">&mdash;</td>");
}

static const demo_run *analysis_run(const demo_scene *sc)
{
    for (int m = 0; m < DEMO_MODES; m++)
        if (sc->runs[m].available && sc->runs[m].analysis)
            return &sc->runs[m];
    return NULL;
}

/* Motion in depth of h and f over the clip's keyframes (the analysis run). */
static void mid_table(demo_buf *b, const demo_scene *sc)
{
    const demo_run *r = analysis_run(sc);
    if (!r || !r->has_mid) {
        P("<p class=\"note\">No motion-in-depth figures: the frames carried no h and f maps in this build.</p>\n");
        return;
    }
    char src[DEMO_NAME * 2 + 2];
    snprintf(src, sizeof src, "%s/%s", sc->name, frame_mode_names[r->mode]);
    P("<table class=\"metrics\"><thead><tr><th>map</th><th>MID distortion (JND)</th><th>out of range (%% of "
      "pixels)</th><th>static RMS (arcmin)</th><th>static gradient RMS (arcmin/px)</th><th>moving samples "
      "(pixel-keyframes)</th></tr></thead><tbody>\n");
    static const char *const maps[2] = {"h", "f"};
    static const char *const what[2] = {"h &mdash; manipulated", "f &mdash; optimized"};
    for (int k = 0; k < 2; k++) {
        char key[64];
        P("<tr><th>%s</th>", what[k]);
        snprintf(key, sizeof key, "metrics.%s.mid_distortion_jnd", maps[k]);
        cell(b, src, key, r->mid[k].mid_distortion_jnd, 1, 3, "");
        snprintf(key, sizeof key, "metrics.%s.range_violation", maps[k]);
        cell(b, src, key, r->range_violation[k], 100, 2, "&thinsp;%");
        if (k == 0) /* the static terms measure x - h: zero for h itself */
            P("<td class=\"na\" colspan=\"2\">0 by definition (the reference)</td>");
        else {
            snprintf(key, sizeof key, "metrics.%s.static_rms", maps[k]);
            cell(b, src, key, r->mid[k].static_rms, 1, 3, "");
            snprintf(key, sizeof key, "metrics.%s.static_grad_rms", maps[k]);
            cell(b, src, key, r->mid[k].static_grad_rms, 1, 3, "");
        }
        snprintf(key, sizeof key, "metrics.%s.moving_samples", maps[k]);
        cell(b, src, key, r->mid[k].moving_measured, 1, 0, "");
        P("</tr>\n");
    }
    P("</tbody></table>\n");
}

/* The stereo pair of every mode at the middle still, against two cameras. */
static void warp_table(demo_buf *b, const demo_scene *sc)
{
    P("<table class=\"metrics\"><thead><tr><th rowspan=\"2\">mode</th><th colspan=\"2\">warp disparity error (px)"
      "</th><th colspan=\"2\">holes</th><th colspan=\"2\">PSNR vs two cameras (dB)</th></tr>"
      "<tr><th>median</th><th>p99</th><th>tessellated warp</th><th>image warping</th><th>left</th><th>right</th>"
      "</tr></thead><tbody>\n");
    for (int m = 0; m < DEMO_MODES; m++) {
        const demo_run *r = &sc->runs[m];
        const char *mode = frame_mode_names[r->mode];
        P("<tr><th>%s</th>", mode);
        if (!r->available) {
            P("<td colspan=\"6\" class=\"na\">not rendered in this build</td></tr>\n");
            continue;
        }
        char src[DEMO_NAME * 2 + 2];
        snprintf(src, sizeof src, "%s/%s", sc->name, mode);
        cell(b, src, "warp_error_px.median", r->warp.error_median, 1, 4, "");
        cell(b, src, "warp_error_px.p99", r->warp.error_p99, 1, 3, "");
        cell(b, src, "hole_fraction", r->warp.hole_fraction, 100, 3, "&thinsp;%");
        cell(b, src, "imagewarp.hole_fraction", r->imagewarp.hole_fraction, 100, 3, "&thinsp;%");
        cell(b, src, "psnr_db.left", r->warp.psnr[0], 1, 1, "");
        cell(b, src, "psnr_db.right", r->warp.psnr[1], 1, 1, "");
        P("</tr>\n");
    }
    P("</tbody></table>\n");
}

static void passes_table(demo_buf *b, const demo_scene *sc)
{
    /* The passes of the richest run, in frame order; other runs by name. */
    const demo_run *base = NULL;
    for (int m = 0; m < DEMO_MODES; m++)
        if (sc->runs[m].available && (!base || sc->runs[m].pass_count > base->pass_count))
            base = &sc->runs[m];
    if (!base)
        return;
    P("<table class=\"passes\"><thead><tr><th>pass (ms, median; host: the CPU's part)</th>");
    for (int m = 0; m < DEMO_MODES; m++)
        if (sc->runs[m].available)
            P("<th>%s</th>", frame_mode_names[sc->runs[m].mode]);
    P("</tr></thead><tbody>\n");
    for (uint32_t p = 0; p < base->pass_count; p++) {
        /* Passes that take no measurable time in any mode are left out. */
        bool shown = false;
        for (int m = 0; m < DEMO_MODES; m++)
            for (uint32_t q = 0; sc->runs[m].available && q < sc->runs[m].pass_count; q++)
                shown |= !strcmp(sc->runs[m].pass_names[q], base->pass_names[p]) && sc->runs[m].pass_ms[q] >= 0.05;
        if (!shown)
            continue;
        P("<tr><th>%s</th>", base->pass_names[p]);
        for (int m = 0; m < DEMO_MODES; m++) {
            const demo_run *r = &sc->runs[m];
            if (!r->available)
                continue;
            uint32_t q = 0;
            while (q < r->pass_count && strcmp(r->pass_names[q], base->pass_names[p]))
                q++;
            if (q == r->pass_count) {
                empty_cells(b, 1);
                continue;
            }
            char src[DEMO_NAME * 2 + 2], key[DEMO_NAME + 32];
            snprintf(src, sizeof src, "%s/%s", sc->name, frame_mode_names[r->mode]);
            snprintf(key, sizeof key, "passes[%s].ms_median", r->pass_names[q]);
            cell(b, src, key, r->pass_ms[q], 1, 2, "");
        }
        P("</tr>\n");
    }
    P("<tr class=\"total\"><th>frame (CPU wall time)</th>");
    for (int m = 0; m < DEMO_MODES; m++)
        if (sc->runs[m].available) {
            char src[DEMO_NAME * 2 + 2];
            snprintf(src, sizeof src, "%s/%s", sc->name, frame_mode_names[sc->runs[m].mode]);
            cell(b, src, "frame_ms_median", sc->runs[m].frame_ms, 1, 1, "");
        }
    P("</tr></tbody></table>\n");
}

/* ------------------------------------------------------------------------- */
/* Figures                                                                   */
/* ------------------------------------------------------------------------- */

static void img(demo_buf *b, const char *src, const char *alt, const char *caption)
{
    P("<figure><img src=\"%s\" alt=\"%s\" loading=\"eager\"><figcaption>%s</figcaption></figure>\n", src, alt,
      caption);
}

static void stills(demo_buf *b, const demo_scene *sc, const demo_opts *o)
{
    const demo_run *any = NULL;
    for (int m = 0; m < DEMO_MODES; m++)
        if (sc->runs[m].available)
            any = any ? any : &sc->runs[m];
    if (!any)
        return;
    P("<h3>Stereo frames</h3><p class=\"explain\">Red&ndash;cyan anaglyphs (Dubois) of each mode at the same "
      "instants: wear red&ndash;cyan glasses, or read the width of the colour fringes, which is the disparity. "
      "Below them, the eye pairs side by side (left | right) for parallel free viewing.</p>\n");
    for (int k = 0; k < any->still_count; k++) {
        P("<div class=\"grid3\">\n");
        for (int m = 0; m < DEMO_MODES; m++) {
            const demo_run *r = &sc->runs[m];
            const char *mode = frame_mode_names[r->mode];
            if (!r->available) {
                P("<figure class=\"missing\"><div>%s: not rendered</div><figcaption>%s</figcaption></figure>\n",
                  mode, r->note);
                continue;
            }
            char src[256], alt[160], cap[256];
            snprintf(src, sizeof src, "%s/%s/still_%d_anaglyph.png", sc->name, mode, k);
            snprintf(alt, sizeof alt, "%s, %s, frame %ld, anaglyph", sc->name, mode, r->still_frames[k]);
            snprintf(cap, sizeof cap, "%s &middot; t = %.2f s", k_mode_text[m], r->still_frames[k] / sc->fps);
            img(b, src, alt, cap);
        }
        P("</div>\n");
    }
    P("<div class=\"grid3 small\">\n");
    int mid = any->still_count / 2;
    for (int m = 0; m < DEMO_MODES; m++) {
        const demo_run *r = &sc->runs[m];
        if (!r->available)
            continue;
        char src[256], alt[160], cap[160];
        snprintf(src, sizeof src, "%s/%s/still_%d_sbs.png", sc->name, frame_mode_names[r->mode], mid);
        snprintf(alt, sizeof alt, "%s, %s, side by side", sc->name, frame_mode_names[r->mode]);
        snprintf(cap, sizeof cap, "%s, left | right eye", frame_mode_names[r->mode]);
        img(b, src, alt, cap);
    }
    P("</div>\n");
    (void)o;
}

static void videos(demo_buf *b, const demo_scene *sc, const demo_opts *o)
{
    bool any = false;
    for (int m = 0; m < DEMO_MODES; m++)
        any |= sc->runs[m].video;
    if (!any)
        return;
    P("<h3>Videos</h3><p class=\"explain\">The clip in each mode (anaglyph), every frame the mode rendered "
      "(1 in %d) at %g&nbsp;fps, so it plays at the real speed.</p><div class=\"grid3\">\n", o->step,
      sc->fps / o->step);
    for (int m = 0; m < DEMO_MODES; m++) {
        const demo_run *r = &sc->runs[m];
        if (!r->video)
            continue;
        P("<figure><video src=\"%s/%s/video.mp4\" controls loop muted autoplay playsinline></video>"
          "<figcaption>%s</figcaption></figure>\n", sc->name, frame_mode_names[r->mode], k_mode_text[m]);
    }
    P("</div>\n");
}

/* Tick labels along [lo, hi], each at its place in percent of the axis. */
static void ticks(demo_buf *b, const char *cls, const char *side, double lo, double hi, int count, bool flip)
{
    if (!(hi > lo))
        return;
    double step = figure_nice_step(hi - lo, count);
    for (double v = ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step) {
        double at = 100.0 * (v - lo) / (hi - lo);
        P("<span class=\"%s\" style=\"%s:%.2f%%\">%g</span>", cls, side, flip ? 100.0 - at : at,
          fabs(v) < 1e-9 * step ? 0.0 : v);
    }
}

/* The report's colour map as a CSS gradient (figure_colormap's stops). */
static void gradient(demo_buf *b)
{
    P("background:linear-gradient(90deg");
    for (int i = 0; i <= 8; i++) {
        uint8_t c[3];
        figure_colormap(i / 8.0f, c);
        P(",#%02x%02x%02x", c[0], c[1], c[2]);
    }
    P(")");
}

static void colorbar(demo_buf *b, float lo, float hi, const char *unit)
{
    P("<div class=\"cbar\"><i style=\"");
    gradient(b);
    P("\"></i>");
    ticks(b, "tk", "left", lo, hi, 5, false);
    P("<b>%s</b></div>", unit);
}

/* A colour-mapped image with its axes: x along the columns (0..xmax),
 * y down the rows (ylo at the top .. yhi at the bottom), and a colour bar. */
typedef struct map_fig {
    const char *src, *alt, *caption, *xlabel, *ylabel, *unit;
    double xmax, ylo, yhi;
    float lo, hi;
    bool pixelated;
} map_fig;

static void map_figure(demo_buf *b, const map_fig *m)
{
    P("<figure><div class=\"map\"><img%s src=\"%s\" alt=\"%s\">", m->pixelated ? " class=\"xt\"" : "", m->src,
      m->alt);
    ticks(b, "tk tx", "left", 0, m->xmax, 4, false);
    ticks(b, "tk ty", "top", m->ylo, m->yhi, 4, false);
    P("<span class=\"xl\">%s</span><span class=\"yl\">%s</span></div>", m->xlabel, m->ylabel);
    colorbar(b, m->lo, m->hi, m->unit);
    P("<figcaption>%s</figcaption></figure>\n", m->caption);
}

static void slices(demo_buf *b, const demo_scene *sc, const scene_text *tx)
{
    bool any = false;
    for (int m = 0; m < DEMO_MAPS; m++)
        any |= sc->xt[m] != NULL;
    if (!any)
        return;
    double t_end = sc->frames[sc->samples - 1] / sc->fps;
    P("<h3>x&ndash;t slices of g, h and f</h3><p class=\"explain\">Image row y&nbsp;=&nbsp;%d of every frame "
      "stacked from top (t&nbsp;=&nbsp;0) to bottom (t&nbsp;=&nbsp;%.1f&nbsp;s); colour is vergence in arcmin "
      "(brighter is nearer). h and f share one colour scale. %s</p><div class=\"grid3\">\n", sc->row, t_end,
      tx ? tx->look : "");
    static const char *const what[DEMO_MAPS] = {"original g", "manipulated h", "optimized f"};
    for (int m = 0; m < DEMO_MAPS; m++) {
        if (!sc->xt[m]) {
            P("<figure class=\"missing\"><div>%s: not produced in this build</div></figure>\n", what[m]);
            continue;
        }
        char src[160], alt[64];
        snprintf(src, sizeof src, "%s/xt_%s.png", sc->name, demo_map_names[m]);
        snprintf(alt, sizeof alt, "x-t slice of %s", demo_map_names[m]);
        map_figure(b, &(map_fig){.src = src, .alt = alt, .caption = what[m], .xlabel = "x (px)",
                                 .ylabel = "t (s)", .unit = "vergence (arcmin)", .xmax = sc->width, .ylo = 0,
                                 .yhi = t_end, .lo = sc->xt_lo[m], .hi = sc->xt_hi[m], .pixelated = true});
    }
    P("</div>\n");
}

static void tracks(demo_buf *b, const demo_scene *sc)
{
    if (!sc->track_count || !sc->tracks[0].v[0])
        return;
    P("<h3>Vergence of each object over time</h3><p class=\"explain\">The mean vergence of each object's pixels "
      "in every frame (gaps: out of view or hidden). Left: the original g. Right: h dashed and f solid, in the "
      "compressed range. The first object, %s, is the one that moves in depth: its h curve bends where the "
      "manipulation compresses depth; f stays in the comfort range and bends less.</p>"
      "<div class=\"grid2\">\n", sc->tracks[0].name);
    char src[160];
    snprintf(src, sizeof src, "%s/tracks_g.svg", sc->name);
    img(b, src, "vergence of the objects in g", "original g");
    bool hf = false;
    for (int m = 1; m < DEMO_MAPS; m++)
        hf |= sc->tracks[0].v[m] != NULL;
    if (hf) {
        snprintf(src, sizeof src, "%s/tracks_hf.svg", sc->name);
        img(b, src, "vergence of the objects in h and f", "manipulated h and optimized f");
    } else
        P("<figure class=\"missing\"><div>h and f: not produced in this build</div></figure>\n");
    P("</div>\n");
}

/* The paper's quantity for the moving object, and where f departs from h. */
static void motion(demo_buf *b, const demo_scene *sc, const demo_opts *o)
{
    if (sc->motion_points < 3 && !sc->fh_diff)
        return;
    P("<h3>Perceived motion in depth of %s</h3><p class=\"explain\">What the method optimises (paper Sec. 4.2): "
      "the object's vergence velocity over each keyframe interval (every %d frames, %.2f&nbsp;s) through the "
      "perceptual scale p(v)&nbsp;=&nbsp;sign(v)&nbsp;ln(1&nbsp;+&nbsp;|v|)&nbsp;/&nbsp;k (JND, k&nbsp;=&nbsp;%.2f), "
      "and its change from one interval to the next, the perceived acceleration in depth. h (dashed) departs "
      "from g's shape where the operator compresses depth; f should follow g's shape, offset by the smaller range "
      "it lives in. The MID distortion in the table is the RMS of the acceleration's difference from g over every "
      "moving pixel; these curves are one object's mean.</p><div class=\"grid2\">\n", sc->tracks[0].name,
      o->keyframe_stride, o->keyframe_stride / sc->fps, STEREO_WEBER_K);
    if (sc->motion_points >= 3) {
        char src[160];
        snprintf(src, sizeof src, "%s/motion_v.svg", sc->name);
        img(b, src, "perceived velocity in depth of g, h and f", "perceived velocity in depth (JND)");
        snprintf(src, sizeof src, "%s/motion_a.svg", sc->name);
        img(b, src, "perceived acceleration in depth of g, h and f", "perceived acceleration in depth (JND)");
    }
    P("</div>\n");
    if (sc->fh_diff) {
        char src[160], cap[256];
        snprintf(src, sizeof src, "%s/fh_diff.png", sc->name);
        snprintf(cap, sizeof cap, "|f &minus; h| at t&nbsp;=&nbsp;%.2f&nbsp;s (frame %ld), up to %.3f&nbsp;arcmin: "
                 "where, and by how much, f changes the manipulation (its static RMS in the table: the change "
                 "where nothing moves)", sc->fh_frame / sc->fps, sc->fh_frame, sc->fh_max);
        P("<div class=\"grid2\">");
        map_figure(b, &(map_fig){.src = src, .alt = "|f - h|", .caption = cap, .xlabel = "x (px)",
                                 .ylabel = "y (px)", .unit = "|f &minus; h| (arcmin)", .xmax = sc->width,
                                 .ylo = 0, .yhi = o->height, .lo = 0, .hi = sc->fh_max});
        P("</div>\n");
    }
}

static void cascade(demo_buf *b, const demo_scene *sc)
{
    const demo_run *r = NULL;
    for (int m = DEMO_MODES - 1; m >= 0 && !r; m--)
        if (sc->runs[m].available)
            r = &sc->runs[m];
    if (!r)
        return;
    const char *mode = frame_mode_names[r->mode];
    int k = r->still_count / 2;
    /* The swatches in the colours of the cascade view itself. */
    static const char *const stage_text[5] = {"", "direct fetch", "3&times;3 neighbourhood", "64 Halton samples",
                                              "global curve"};
    P("<h3>The warp: cascade and holes</h3><p class=\"explain\">Left: which stage of the cascade (paper Fig. 5) "
      "gave each pixel's vertices their disparity, in the %s mode at t&nbsp;=&nbsp;%.2f&nbsp;s: ", mode,
      r->still_frames[k] / sc->fps);
    for (int st = 1; st <= VGX_STAGE_CURVE; st++) {
        const float *t = capture_cascade_tint[st];
        P("<span class=\"sw\" style=\"background:#%02x%02x%02x\"></span>%s%s", (unsigned)lroundf(255 * t[0]),
          (unsigned)lroundf(255 * t[1]), (unsigned)lroundf(255 * t[2]), stage_text[st],
          st < VGX_STAGE_CURVE ? ", " : ". ");
    }
    P("Middle: the tessellated warp's left eye. "
      "Right: the image-warping baseline's left eye, <span class=\"sw\" style=\"background:#ff00c8\"></span>magenta "
      "where it has nothing to show (disocclusions); the tessellated warp has next to none (table below).</p>"
      "<div class=\"grid3\">\n");
    char src[256];
    snprintf(src, sizeof src, "%s/%s/still_%d_cascade.png", sc->name, mode, k);
    img(b, src, "cascade stages", "cascade stages");
    snprintf(src, sizeof src, "%s/%s/warp_%d_left.png", sc->name, mode, k);
    img(b, src, "tessellated warp, left eye", "tessellated warp (this engine)");
    snprintf(src, sizeof src, "%s/%s/imagewarp_%d_left.png", sc->name, mode, k);
    img(b, src, "image warping, left eye", "image warping: holes in magenta");
    P("</div>\n");
}

/* Every scene in one table, each cell traced to its capture.json. */
static void summary(demo_buf *b, const demo_scene *scenes, int count)
{
    P("<h2 id=\"summary\">Summary</h2><p class=\"explain\">Per scene: the motion-in-depth distortion of the "
      "moving objects under the manipulation h and under the optimisation f (lower is better; f&nbsp;/&nbsp;h "
      "below 1 means motion in depth is restored), the share of pixels outside the comfort range, the optimized "
      "stereo pair's disparity error and holes against two real cameras, and the median frame time on this "
      "run's device.</p>\n<table class=\"metrics summary\"><thead><tr><th rowspan=\"2\">scene</th>"
      "<th colspan=\"3\">MID distortion</th><th colspan=\"2\">out of range (%% of pixels)</th>"
      "<th rowspan=\"2\">warp error p99 (px)</th><th colspan=\"2\">holes (%% of pixels)</th>"
      "<th colspan=\"2\">frame (ms)</th></tr><tr><th>h (JND)</th><th>f (JND)</th><th>f / h</th><th>h</th>"
      "<th>f</th><th>tessellated warp</th><th>image warping</th><th>original</th><th>optimized</th></tr>"
      "</thead><tbody>\n");
    for (int i = 0; i < count; i++) {
        const demo_scene *sc = &scenes[i];
        const demo_run *a = analysis_run(sc), *opt = NULL, *orig = NULL;
        for (int m = 0; m < DEMO_MODES; m++) {
            if (!sc->runs[m].available)
                continue;
            if (sc->runs[m].mode == FRAME_MODE_OPTIMIZED)
                opt = &sc->runs[m];
            if (sc->runs[m].mode == FRAME_MODE_ORIGINAL)
                orig = &sc->runs[m];
        }
        P("<tr data-scene=\"%s\"><th><a href=\"#%s\">%s</a></th>", sc->name, sc->name, sc->name);
        char src[DEMO_NAME * 2 + 2];
        if (a && a->has_mid) {
            snprintf(src, sizeof src, "%s/%s", sc->name, frame_mode_names[a->mode]);
            double h = a->mid[0].mid_distortion_jnd, f = a->mid[1].mid_distortion_jnd;
            cell(b, src, "metrics.h.mid_distortion_jnd", h, 1, 2, "");
            cell(b, src, "metrics.f.mid_distortion_jnd", f, 1, 2, "");
            cell(b, src, "metrics.mid_ratio", h > 0 ? f / h : NAN, 1, 2, "");
            cell(b, src, "metrics.h.range_violation", a->range_violation[0], 100, 2, "");
            cell(b, src, "metrics.f.range_violation", a->range_violation[1], 100, 2, "");
        } else
            empty_cells(b, 5);
        if (opt) {
            snprintf(src, sizeof src, "%s/%s", sc->name, frame_mode_names[opt->mode]);
            cell(b, src, "warp_error_px.p99", opt->warp.error_p99, 1, 3, "");
            cell(b, src, "hole_fraction", opt->warp.hole_fraction, 100, 3, "");
            cell(b, src, "imagewarp.hole_fraction", opt->imagewarp.hole_fraction, 100, 2, "");
        } else
            empty_cells(b, 3);
        const demo_run *t[2] = {orig, opt};
        for (int k = 0; k < 2; k++) {
            if (!t[k]) {
                empty_cells(b, 1);
                continue;
            }
            snprintf(src, sizeof src, "%s/%s", sc->name, frame_mode_names[t[k]->mode]);
            cell(b, src, "frame_ms_median", t[k]->frame_ms, 1, 0, "");
        }
        P("</tr>\n");
    }
    P("</tbody></table>\n");
}

/* ------------------------------------------------------------------------- */
/* Page                                                                      */
/* ------------------------------------------------------------------------- */

static const char k_style[] =
    "body{font:16px/1.55 -apple-system,'Segoe UI',Helvetica,Arial,sans-serif;color:#1d1d1f;background:#fafaf8;"
    "margin:0}main{max-width:1240px;margin:0 auto;padding:32px 28px 64px}"
    "h1{font-size:34px;font-weight:650;letter-spacing:-.02em;margin:0 0 4px}"
    "h2{font-size:26px;font-weight:620;letter-spacing:-.01em;margin:56px 0 8px;padding-top:20px;"
    "border-top:1px solid #ddd}h3{font-size:18px;font-weight:620;margin:32px 0 6px}"
    ".sub{color:#666;margin:0 0 20px}.explain{color:#444;max-width:920px;margin:4px 0 14px}"
    ".note{background:#fff6d6;border:1px solid #f0d98a;border-radius:6px;padding:10px 14px;margin:14px 0}"
    ".grid3{display:grid;grid-template-columns:repeat(3,1fr);gap:14px;margin:0 0 14px}"
    ".grid2{display:grid;grid-template-columns:repeat(2,1fr);gap:14px}"
    "figure{margin:0}figure img,figure video{width:100%;display:block;border-radius:4px;background:#eee;"
    "box-shadow:0 1px 3px rgba(0,0,0,.12)}img.xt{image-rendering:pixelated}"
    "figcaption{font-size:13px;color:#555;margin-top:6px}"
    ".missing div{aspect-ratio:16/9;display:flex;align-items:center;justify-content:center;background:#f0f0ee;"
    "border:1px dashed #ccc;border-radius:4px;color:#888;font-size:14px;text-align:center;padding:8px}"
    ".map{position:relative;margin:0 0 34px 42px}.map img{box-shadow:none;border-radius:0;outline:1px solid #999}"
    ".tk{position:absolute;font-size:11px;color:#555;white-space:nowrap;line-height:1}"
    ".tx{top:100%;transform:translate(-50%,6px)}.ty{left:0;transform:translate(calc(-100% - 6px),-50%)}"
    ".tx::before{content:'';position:absolute;left:50%;top:-6px;height:4px;border-left:1px solid #777}"
    ".ty::after{content:'';position:absolute;right:-6px;top:50%;width:4px;border-top:1px solid #777}"
    ".xl,.yl{position:absolute;font-size:12px;color:#333;white-space:nowrap}.xl{top:100%;left:50%;"
    "transform:translate(-50%,19px)}.yl{left:-38px;top:50%;transform:translate(-50%,-50%) rotate(-90deg)}"
    ".cbar{position:relative;margin:0 0 30px 42px;height:10px}.cbar i{display:block;height:10px;"
    "border-radius:2px}.cbar .tk{top:14px;transform:translateX(-50%)}.cbar b{position:absolute;top:28px;"
    "left:50%;transform:translateX(-50%);font-weight:400;font-size:12px;color:#333;white-space:nowrap}"
    "table.summary td,table.summary th{padding:5px 8px}table.summary a{color:#1f6fb4;text-decoration:none}"
    ".sw{display:inline-block;width:11px;height:11px;border-radius:2px;margin:0 4px -1px 2px}"
    "table{border-collapse:collapse;font-size:14px;margin:8px 0 4px;font-variant-numeric:tabular-nums}"
    "th,td{padding:5px 10px;border-bottom:1px solid #e4e4e4;text-align:right}thead th{font-weight:600;"
    "color:#333;background:#f0f0ec;text-align:center}tbody th{text-align:left;font-weight:600}"
    "td.na{color:#999;text-align:center}table.inner td{border:0;padding:0 4px}tr.total th,tr.total td{"
    "border-top:2px solid #ccc}"
    "nav a{margin-right:14px;color:#1f6fb4;text-decoration:none}dl{max-width:920px}dt{font-weight:600}"
    "dd{margin:0 0 8px 0;color:#444}code{font:13px ui-monospace,Menlo,monospace;background:#efefeb;"
    "padding:1px 4px;border-radius:3px}"
    "@media(max-width:800px){.grid3,.grid2{grid-template-columns:1fr}}";

static void scene_section(demo_buf *b, const demo_scene *sc, const demo_opts *o)
{
    const scene_text *tx = scene_text_for(sc->name);
    P("<section id=\"%s\"><h2>%s</h2><p class=\"explain\">%s</p>\n", sc->name, tx ? tx->title : sc->name,
      tx ? tx->about : sc->path);
    for (int m = 0; m < DEMO_MODES; m++)
        if (!sc->runs[m].available)
            P("<p class=\"note\">%s: %s.</p>\n", frame_mode_names[sc->runs[m].mode], sc->runs[m].note);
    stills(b, sc, o);
    videos(b, sc, o);
    slices(b, sc, tx);
    tracks(b, sc);
    motion(b, sc, o);
    cascade(b, sc);
    P("<h3>Metrics</h3><p class=\"explain\">Motion in depth over the keyframes of the clip, computed from the "
      "optimized run's frames: <b>MID distortion</b> is the RMS error of the perceived acceleration in depth "
      "against g (JND) over moving pixels; <b>out of range</b> the share of pixels, over every frame, outside the "
      "operator's target range; <b>static RMS</b> and its gradient tell how far the map strays from h where "
      "nothing moves. f should have a smaller MID distortion than h, no pixel out of range, and a small "
      "static change.</p>\n");
    mid_table(b, sc);
    P("<p class=\"explain\">The stereo pair of each mode at the middle still against two real cameras: how far "
      "the disparity the warp produced is from its target (pixels), the share of pixels left empty by the "
      "tessellated warp and by image warping, and each eye's PSNR against the cameras. The cameras show g, so "
      "the PSNR measures accuracy in the original mode only; for h and f it measures how much the "
      "manipulation changed the picture.</p>\n");
    warp_table(b, sc);
    P("<h3>Time per pass</h3><p class=\"explain\">GPU time of the passes of the frame graph (median over the "
      "frames each mode rendered, %ux%u per eye, on this run's device; passes under 0.05&nbsp;ms in every mode "
      "are left out). The MID passes run in every mode (the modes switch on any frame); the solve is spread "
      "over the frames of a keyframe interval, and a frame after skipped ones does their shares too, so the "
      "modes rendered every %d frames show about %d times the optimized run's <code>mid.solve</code>. The warp "
      "tessellates each edge until the disparity along it is within %g&nbsp;px of linear, so a map that bends "
      "more inside the scene's triangles costs more warp time: f where the camera moves (every pixel then "
      "moves in depth and carries f's upsampled correction; docs/demo.md).</p>\n", (unsigned)o->width,
      (unsigned)o->height, o->step, o->step, o->tess_error);
    passes_table(b, sc);
    P("</section>\n");
}

vg_status demo_html_write(const demo_opts *o, const demo_scene *scenes, int count, double seconds,
                          const char *device, const vg_manifest *m)
{
    /* The report is the manifest of the whole result: the files it lists. */
    vg_json files = {.compact = true};
    vg_json_object_begin(&files, NULL);
    vg_status fst = vg_manifest_files(m, &files);
    vg_json_object_end(&files);
    if (fst != VG_OK || files.failed) {
        vg_json_free(&files);
        return fst != VG_OK ? fst : VG_ERR_NOMEM;
    }
    demo_buf buf = {0}, *b = &buf;
    stereo_display disp;
    stereo_display_init(&disp, &o->display);
    P("<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
      "<meta name=\"viewport\" content=\"width=device-width,initial-scale=1\">"
      "<title>vergence &mdash; motion in depth, kept</title><style>%s</style></head><body><main>\n", k_style);
    P("<h1>vergence &mdash; motion in depth, kept</h1><p class=\"sub\">A run of <code>vergence demo</code>: "
      "%d scene%s, %ux%u per eye, %g&nbsp;Hz with a keyframe every %d frames, on %s, in %.0f&nbsp;s, for a "
      "%.3g&nbsp;m wide %dx%d display seen from %.2f&nbsp;m with eyes %.1f&nbsp;mm apart. After "
      "Kellnhofer, Ritschel, Myszkowski and Seidel, &ldquo;Optimizing Disparity for Motion in Depth&rdquo;.</p>\n",
      count, count == 1 ? "" : "s", (unsigned)o->width, (unsigned)o->height, o->fps, o->keyframe_stride, device,
      seconds, disp.width_m, disp.res_x, disp.res_y, disp.distance_m, 1000 * disp.ipd_m);
    P("<p class=\"explain\">Stereo 3D is compressed for comfort, and the compression distorts motion in depth: an "
      "object flying toward you speeds up and slows down as it crosses compressed depth ranges. Each scene is "
      "shown three ways: <b>g</b>, the disparity of the original stereo camera; <b>h</b>, after a disparity "
      "operator has fitted it into the comfort range; <b>f</b>, the optimisation of the paper, which keeps h "
      "where nothing moves and gives moving objects back the acceleration in depth they have in g, in "
      "perceptual units. Every pair is rendered by moving tessellated vertices, so the image has exactly the "
      "disparity asked for.</p>\n");
    if (!o->ffmpeg && o->video)
        P("<p class=\"note\">ffmpeg is not installed (Debian package <code>ffmpeg</code>): no videos.</p>\n");
    P("<nav><a href=\"#summary\">summary</a>");
    for (int i = 0; i < count; i++)
        P("<a href=\"#%s\">%s</a>", scenes[i].name, scenes[i].name);
    P("</nav>\n");
    summary(b, scenes, count);
    for (int i = 0; i < count; i++)
        scene_section(b, &scenes[i], o);
    P("<h2>Reproduce</h2><p class=\"explain\"><code>vergence demo --out %s --size %ux%u --step %d</code>. "
      "Each scene and mode has a <code>capture.json</code> with the figures above; see "
      "<code>docs/demo.md</code>.</p>\n</main>" VG_MANIFEST_HTML_OPEN "%.*s" VG_MANIFEST_HTML_CLOSE
      "</body></html>\n", o->out, (unsigned)o->width,
      (unsigned)o->height, o->step, (int)files.len, files.buf);
    vg_json_free(&files);

    vg_status st = buf.failed ? VG_ERR_NOMEM : VG_OK;
    char path[4096];
    if (st == VG_OK)
        st = vg_path_join(path, sizeof path, o->out, "index.html");
    if (st == VG_OK)
        st = vg_file_write_atomic(path, buf.s, buf.len);
    free(buf.s);
    return st;
}
