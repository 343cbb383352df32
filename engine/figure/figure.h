/* vergence — figures for people, on the CPU: the colour map every figure
 * uses, a float map as a colour PNG with a legend (a colour bar with
 * labelled ticks, the unit and a title, in stb_easy_font), and videos
 * written through Debian's ffmpeg. Used by `vergence optimize` (previews,
 * x-t slices) and `vergence demo`. */
#pragma once
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

/* The colour map (viridis-like: ordered in lightness, readable in grey) at
 * t in [0, 1], clamped. */
void figure_colormap(float t, uint8_t rgb[3]);

/* A map of w x rows floats through the colour map on [lo, hi] (NAN or inf:
 * grey), each row repeated `repeat` times: rgb holds w x rows x repeat x 3. */
void figure_map_rgb(const float *v, int w, int rows, int repeat, float lo, float hi, uint8_t *rgb);

typedef struct figure_legend {
    const char *title;   /* above the bar, e.g. "f, frame 12: vergence" */
    const char *unit;    /* after the title in parentheses, e.g. "arcmin" */
} figure_legend;

/* The map as an RGB PNG at path, each row repeated `repeat` times; with a
 * legend, enlarged by a whole factor to at least 320 px wide (nearest
 * pixel) and a legend strip below it. Written atomically (core/io). */
vg_status figure_map_png(const char *path, const float *v, int w, int rows, int repeat, float lo, float hi,
                         const figure_legend *legend);

/* A round tick step (1, 2 or 5 times a power of ten) giving about `count`
 * ticks over `span` (every figure's axes). */
double figure_nice_step(double span, int count);

/* ffmpeg on PATH (buf receives its path), or NULL. */
const char *figure_find_ffmpeg(char *buf, size_t cap);

/* A video of RGB frames: H.264 in MP4 (yuv420p, every browser plays it).
 * figure_video_open returns NULL (with a warning) when ffmpeg cannot start;
 * a frame that ffmpeg does not take closes the video (a warning, no error:
 * a video is an extra). figure_video_close returns true when the file is
 * complete, and adds it to core/io's write watch (a result's manifest). */
typedef struct figure_video figure_video;
figure_video *figure_video_open(const char *ffmpeg, const char *path, int w, int h, double fps);

/* How a stereo video packs its two eyes into each frame, as the file says
 * it for players: an H.264 frame-packing SEI in every stream (x264's
 * frame-packing: 3 side by side, 4 top-bottom; ITU-T H.264 Table D-8) and,
 * in a .mkv, the Matroska StereoMode of the track (left_right,
 * top_bottom). Left first either way. */
typedef enum figure_packing {
    FIGURE_PACKING_NONE = 0,
    FIGURE_PACKING_SBS,
    FIGURE_PACKING_TB,
} figure_packing;
/* figure_video_open for a stereo video: MP4 or, when path ends in .mkv, Matroska. */
figure_video *figure_video_open_stereo(const char *ffmpeg, const char *path, int w, int h, double fps,
                                       figure_packing packing);
void figure_video_frame(figure_video **v, const uint8_t *rgb);
bool figure_video_close(figure_video *v);
