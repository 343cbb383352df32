/* vergence — command-line pieces shared by `play` and `study`: the physical
 * display (DESIGN.md: all overridable), the operator, finding the arena. */
#pragma once
#include <stddef.h>

#include "core/cli.h"
#include "disparity/disp_operator.h"
#include "stereo/stereo_display.h"

typedef struct game_display_cli {
    double screen_width_m;      /* visible panel width, 0 = the paper's 24" 16:9 */
    double distance_m;          /* viewing distance, 0 = 0.80 */
    double ipd_m;               /* interocular distance, 0 = 0.065 */
} game_display_cli;

#define GAME_DISPLAY_OPTIONS(d)                                                                        \
    {"--screen-width-m", VG_OPT_FLOAT, &(d).screen_width_m, "M", "visible width of the display "       \
     "(default 0.531: the paper's 24\" 16:9 panel)", NULL, 0.05, 20},                                   \
    {"--distance-m", VG_OPT_FLOAT, &(d).distance_m, "M", "viewing distance (default 0.80, paper Sec. 5)", \
     NULL, 0.1, 50},                                                                                   \
    {"--ipd-m", VG_OPT_FLOAT, &(d).ipd_m, "M", "interocular distance of the viewer (default 0.065)",   \
     NULL, 0.03, 0.09}

/* The display model of the flags (panel aspect 16:9 and 1920x1080 kept). */
stereo_display_desc game_display_desc(const game_display_cli *d);


/* The scene to play in: `given`, else content/arena.gltf in the working
 * folder or beside the executable's build tree. Returns NULL (with one
 * error line) when none is found. */
const char *game_scene_path(const char *given, char *buf, size_t cap);
