/* vergence demo — a small SVG line-chart writer: axes with round ticks, a
 * light grid, polylines broken at missing values, a legend. */
#include "demo_svg.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/io.h"
#include "figure/figure.h"

void demo_buf_printf(demo_buf *b, const char *fmt, ...)
{
    if (b->failed)
        return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
        va_end(ap);
        if (n < 0) {
            b->failed = true;
            return;
        }
        if (b->s && b->len + (size_t)n < b->cap) {
            b->len += (size_t)n;
            return;
        }
        size_t cap = b->cap ? 2 * b->cap : 8192;
        while (cap < b->len + (size_t)n + 1)
            cap *= 2;
        char *p = realloc(b->s, cap);
        if (!p) {
            b->failed = true;
            return;
        }
        b->s = p;
        b->cap = cap;
    }
}

static void data_range(const demo_chart *c, double *lo, double *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (int s = 0; s < c->count; s++)
        for (int i = 0; i < c->n; i++) {
            double v = c->series[s].y[i];
            if (isfinite(v)) {
                *lo = fmin(*lo, v);
                *hi = fmax(*hi, v);
            }
        }
    if (!isfinite(*lo)) {
        *lo = 0;
        *hi = 1;
    }
    double pad = (*hi - *lo) * 0.06;
    if (pad <= 0)
        pad = fmax(1e-3, fabs(*hi) * 0.05);
    *lo -= pad;
    *hi += pad;
}

vg_status demo_svg_chart(const char *dir, const char *name, const demo_chart *c)
{
    int W = c->width ? c->width : 560, H = c->height ? c->height : 300;
    double ml = 58, mr = 14, mt = c->title ? 34 : 14, mb = 44;
    double pw = W - ml - mr, ph = H - mt - mb;
    double y0, y1;
    if (c->ymin == 0 && c->ymax == 0)
        data_range(c, &y0, &y1);
    else {
        y0 = c->ymin;
        y1 = c->ymax;
    }
    double x0 = c->n ? c->x[0] : 0, x1 = c->n > 1 ? c->x[c->n - 1] : x0 + 1;
    if (x1 <= x0)
        x1 = x0 + 1;
#define PX(v) (ml + ((v) - x0) / (x1 - x0) * pw)
#define PY(v) (mt + (1.0 - ((v) - y0) / (y1 - y0)) * ph)

    demo_buf b = {0};
    demo_buf_printf(&b, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" viewBox=\"0 0 %d %d\" "
            "font-family=\"Helvetica, Arial, sans-serif\" font-size=\"12\">\n", W, H, W, H);
    demo_buf_printf(&b, "<rect width=\"%d\" height=\"%d\" fill=\"#fff\"/>\n", W, H);
    if (c->title)
        demo_buf_printf(&b, "<text x=\"%g\" y=\"20\" font-size=\"14\" font-weight=\"600\" fill=\"#222\">%s</text>\n", ml,
            c->title);
    /* Grid and ticks. */
    double ys = figure_nice_step(y1 - y0, 5), xs = figure_nice_step(x1 - x0, 8);
    for (double v = ceil(y0 / ys) * ys; v <= y1 + 1e-9 * ys; v += ys) {
        double y = PY(v);
        demo_buf_printf(&b, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#e6e6e6\"/>\n", ml, y, ml + pw, y);
        demo_buf_printf(&b, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\" fill=\"#555\">%g</text>\n", ml - 6, y + 4,
            fabs(v) < 1e-9 * ys ? 0.0 : v);
    }
    for (double v = ceil(x0 / xs) * xs; v <= x1 + 1e-9 * xs; v += xs) {
        double x = PX(v);
        demo_buf_printf(&b, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#f0f0f0\"/>\n", x, mt, x, mt + ph);
        demo_buf_printf(&b, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" fill=\"#555\">%g</text>\n", x, mt + ph + 16, v);
    }
    demo_buf_printf(&b, "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"none\" stroke=\"#999\"/>\n", ml, mt, pw, ph);
    if (c->xlabel)
        demo_buf_printf(&b, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\" fill=\"#333\">%s</text>\n", ml + pw / 2, H - 8,
            c->xlabel);
    if (c->ylabel)
        demo_buf_printf(&b, "<text transform=\"translate(14 %.1f) rotate(-90)\" text-anchor=\"middle\" fill=\"#333\">%s</text>\n",
            mt + ph / 2, c->ylabel);

    /* Lines, clipped to the plot. */
    demo_buf_printf(&b, "<clipPath id=\"plot\"><rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\"/></clipPath>\n", ml, mt, pw, ph);
    demo_buf_printf(&b, "<g clip-path=\"url(#plot)\" fill=\"none\" stroke-linejoin=\"round\" stroke-linecap=\"round\">\n");
    for (int s = 0; s < c->count; s++) {
        const demo_series *se = &c->series[s];
        demo_buf_printf(&b, "<path stroke=\"%s\" stroke-width=\"%g\"%s d=\"", se->color, se->width > 0 ? se->width : 2.0,
            se->dashed ? " stroke-dasharray=\"6 4\"" : "");
        bool pen = false;
        for (int i = 0; i < c->n; i++) {
            if (!isfinite(se->y[i])) {
                pen = false;
                continue;
            }
            demo_buf_printf(&b, "%c%.1f %.1f ", pen ? 'L' : 'M', PX(c->x[i]), PY(se->y[i]));
            pen = true;
        }
        demo_buf_printf(&b, "\"/>\n");
    }
    demo_buf_printf(&b, "</g>\n");

    /* Legend: one row per labelled series, in the corner of the plot that
     * covers the fewest data points. */
    int rows = 0;
    for (int s = 0; s < c->count; s++)
        rows += c->series[s].label != NULL;
    if (rows) {
        double lw = 150, lh = 16 * rows + 6, best_x = 0, best_y = 0;
        int best = -1;
        for (int corner = 0; corner < 4; corner++) {
            double lx = corner & 1 ? ml + 6 : ml + pw - lw - 6, ly = corner & 2 ? mt + ph - lh - 6 : mt + 6;
            int covered = 0;
            for (int s = 0; s < c->count; s++)
                for (int i = 0; i < c->n; i++) {
                    if (!isfinite(c->series[s].y[i]))
                        continue;
                    double x = PX(c->x[i]), y = PY(c->series[s].y[i]);
                    covered += x >= lx - 4 && x <= lx + lw + 4 && y >= ly - 4 && y <= ly + lh + 4;
                }
            if (best < 0 || covered < best) {
                best = covered;
                best_x = lx;
                best_y = ly;
            }
        }
        double lx = best_x, ly = best_y;
        demo_buf_printf(&b, "<rect x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" fill=\"#fff\" "
                            "fill-opacity=\"0.85\" stroke=\"#ddd\"/>\n", lx, ly, lw, lh);
        int r = 0;
        for (int s = 0; s < c->count; s++) {
            const demo_series *se = &c->series[s];
            if (!se->label)
                continue;
            double y = ly + 14 + 16 * r++;
            demo_buf_printf(&b, "<line x1=\"%g\" y1=\"%g\" x2=\"%g\" y2=\"%g\" stroke=\"%s\" stroke-width=\"%g\"%s/>\n",
                            lx + 8, y - 4, lx + 32, y - 4, se->color, se->width > 0 ? se->width : 2.0,
                            se->dashed ? " stroke-dasharray=\"6 4\"" : "");
            demo_buf_printf(&b, "<text x=\"%g\" y=\"%g\" fill=\"#333\">%s</text>\n", lx + 38, y, se->label);
        }
    }
    demo_buf_printf(&b, "</svg>\n");
#undef PX
#undef PY

    vg_status st = b.failed ? VG_ERR_NOMEM : VG_OK;
    char path[4096];
    if (st == VG_OK)
        st = vg_path_join(path, sizeof path, dir, name);
    if (st == VG_OK)
        st = vg_file_write_atomic(path, b.s, b.len);
    free(b.s);
    return st;
}
