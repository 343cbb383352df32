/* vergence demo — line charts as SVG files (the disparity-over-time plots). */
#pragma once
#include <stdbool.h>

#include <stddef.h>

#include "core/status.h"

/* A growing text buffer (the SVG and HTML writers). */
typedef struct demo_buf {
    char *s;
    size_t len, cap;
    bool failed;             /* out of memory: later calls do nothing */
} demo_buf;

void demo_buf_printf(demo_buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

typedef struct demo_series {
    const float *y;          /* n values, NAN breaks the line */
    const char *label;       /* legend text, NULL = not in the legend */
    const char *color;       /* CSS colour */
    bool dashed;
    float width;             /* stroke width, 0 = 2 */
} demo_series;

typedef struct demo_chart {
    const char *title, *xlabel, *ylabel;
    const float *x;          /* n values, increasing */
    int n;
    const demo_series *series;
    int count;
    int width, height;       /* pixels, 0 = 560 x 300 */
    float ymin, ymax;        /* both 0 = from the data */
} demo_chart;

/* Writes DIR/NAME as a standalone SVG. */
vg_status demo_svg_chart(const char *dir, const char *name, const demo_chart *c);
