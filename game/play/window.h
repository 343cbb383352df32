/* vergence — a game window: GLFW, the Vulkan context and swapchain, input,
 * and scripted input (record / replay).
 *
 * Input arrives as window_event values stamped with a tick: a fixed time
 * step of 1 / fps. Live, ticks follow the wall clock (whole ticks, at most 6
 * per frame, so a stall is no jump); with a replay file every frame is one
 * tick, so a replayed session runs at a fixed time step and does the same
 * thing every time (docs/game.md "Scripted input"). Game time advances by
 * window_tick_seconds() = the frame's ticks / fps in both cases, so a
 * recording (live events stamped with their tick) replays as it was played.
 *
 * Replay / record file, one event per line ('#' starts a comment):
 *   TICK key NAME          NAME: A-Z, 0-9, SPACE, ESCAPE, ENTER, TAB, LEFT, RIGHT, UP, DOWN
 *   TICK click X Y         X, Y: fractions of the window's width and height (0 = left / top)
 */
#pragma once
#include <stdbool.h>

#include "gpu/swapchain.h"
#include "options/gpu_cli.h"
#include "frame/frame.h"

typedef struct window_desc {
    const char *title;
    int width, height;          /* 0 = 1280 x 720; fullscreen: the monitor's mode */
    bool fullscreen;
    const gpu_cli *gpu;
    const char *replay;         /* events from a file at a fixed time step */
    const char *record;         /* write live events to a file */
    double fps;                 /* tick rate, 0 = 60 */
    int frame_ticks;            /* replay: ticks per frame, 0 = 1 (more: a slower device's frames) */
} window_desc;

typedef enum window_event_kind {
    WINDOW_EVENT_DEFAULT = 0,
    WINDOW_EVENT_KEY,           /* key: GLFW_KEY_* */
    WINDOW_EVENT_CLICK,         /* x, y: fractions of the window */
} window_event_kind;

typedef struct window_event {
    window_event_kind kind;
    int key;
    double x, y;
    long tick;
} window_event;

typedef struct window window;

/* One error line and a status when there is no display, no Vulkan surface
 * support, or the replay file is bad. */
vg_status window_create(const window_desc *desc, window **out);
void window_destroy(window *w);

gpu *window_gpu(window *w);
VkFormat window_format(const window *w);
VkExtent2D window_extent(const window *w);
bool window_replaying(const window *w);   /* replay events left to deliver */
bool window_closed(window *w);            /* the user closed the window */

/* Handles window-system events without advancing the tick (long work in
 * between frames); live input stays queued for the next tick. */
void window_pump(window *w);
/* Advances one tick (waits for events when minimised), returns the events
 * of this tick: live ones and replayed ones. */
long window_tick(window *w, window_event *events, int cap, int *count);
/* Seconds of game time the last window_tick covered: its ticks / fps
 * (0 when the frame came within the same tick, 1 / fps replaying). */
double window_tick_seconds(const window *w);

/* Acquires the next image. *stale: the swapchain no longer fits the window;
 * drop every frame that presents to it, call window_rebuild, try again. */
vg_status window_acquire(window *w, frame_target *target, bool *stale);
vg_status window_present(window *w, bool *stale);
vg_status window_rebuild(window *w);

/* Key names of the replay format (NULL for keys it has no name for). */
const char *window_key_name(int key);
