/* vergence — one display calibration for every command that renders or
 * converts disparity: the same flags everywhere and `--display FILE`, a
 * JSON profile (docs/formats.md "Display profile"; the "display" object of
 * a capture.json is one). Flags override the file; what neither gives keeps
 * the paper's setup (24" 16:9, 1920x1080, 0.80 m, 0.065 m). */
#pragma once
#include "core/cli.h"
#include "core/status.h"
#include "stereo/stereo_display.h"

typedef struct display_cli {
    const char *file;           /* --display FILE, NULL = none */
    double screen_width_m;      /* visible panel width (16:9), 0 = unset */
    double diagonal_in;         /* panel diagonal (16:9), 0 = unset */
    int resolution[2];          /* panel pixels, 0 = unset */
    double distance_m;          /* viewing distance, 0 = unset */
    double ipd_m;               /* interocular distance, 0 = unset */
} display_cli;

#define DISPLAY_CLI_OPTIONS(d)                                                                                \
    {"--display", VG_OPT_STRING, &(d).file, "FILE",                                                            \
     "display profile, JSON (docs/formats.md; a capture.json's \"display\" works); the flags below override it", \
     NULL, 0, 0},                                                                                              \
    {"--screen-width-m", VG_OPT_FLOAT, &(d).screen_width_m, "M",                                               \
     "visible width of the 16:9 panel (default 0.531: the paper's 24\" panel)", NULL, 0.05, 20},              \
    {"--screen-diagonal-in", VG_OPT_FLOAT, &(d).diagonal_in, "IN", "or its diagonal in inches (default 24)",   \
     NULL, 1, 1000},                                                                                           \
    {"--screen-resolution", VG_OPT_SIZE, (d).resolution, "WxH", "panel pixels (default 1920x1080)", NULL, 0, 0}, \
    {"--distance-m", VG_OPT_FLOAT, &(d).distance_m, "M", "viewing distance (default 0.80, paper Sec. 5)", NULL,  \
     0.05, 100},                                                                                               \
    {"--ipd-m", VG_OPT_FLOAT, &(d).ipd_m, "M", "interocular distance of the viewer (default 0.065)", NULL, 0.03, \
     0.09}

/* The old spellings of `vergence optimize` (--display-diagonal,
 * --display-resolution, --display-distance, --display-ipd): renamed in argv
 * to the flags above, with one deprecation line each. Before vg_cli_parse. */
void display_cli_renames(const char *cmd, int argc, char **argv);
/* Reads --display FILE into what the flags left unset, and checks the
 * whole: one error line naming the file or flag. */
vg_status display_cli_load(display_cli *c);
/* The display model of loaded options (pure). */
stereo_display_desc display_cli_desc(const display_cli *c);
