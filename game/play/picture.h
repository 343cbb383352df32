/* vergence — a picture drawn on the CPU and shown in the window: the
 * preference study's three side-by-side clips (played back from memory),
 * its labels and progress. A two-pass-free graph: one transfer pass copies
 * the host buffer into the acquired swapchain image (engine/graph derives
 * the layout transitions, as for every other pass). */
#pragma once
#include <stdint.h>

#include "gpu/gpu.h"
#include "pass/frame_types.h"

typedef struct picture picture;

vg_status picture_create(gpu *g, VkFormat format, VkExtent2D extent, picture **out);
void picture_destroy(picture *p);

/* The pixels to draw into (width x height, 4 bytes each, top row first),
 * once the GPU is done with the previous picture. */
uint8_t *picture_begin(picture *p);
/* Byte offsets of red, green and blue in a pixel (the swapchain's order). */
void picture_channels(const picture *p, int *r, int *g, int *b);
VkExtent2D picture_extent(const picture *p);
/* Copies the pixels into the target image and submits. */
vg_status picture_present(picture *p, const frame_target *target);

/* In a window (window.h): *p made again when the window's extent is no
 * longer its own (a resize since it was made)... */
typedef struct window window;
vg_status picture_fit(picture **p, window *w);
/* ... and shown: acquire, copy, present. A stale swapchain is rebuilt and
 * the picture made again at the new size; *rebuilt then says nothing was
 * shown (the caller draws again). */
vg_status picture_show(picture **p, window *w, bool *rebuilt);

/* Drawing helpers. */
void picture_fill(picture *p, int x, int y, int w, int h, const uint8_t rgb[3]);
/* Text with stb_easy_font at an integer scale; returns the width in pixels. */
int picture_text(picture *p, int x, int y, int scale, const char *text, const uint8_t rgb[3]);
int picture_text_width(const char *text, int scale);
