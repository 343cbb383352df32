/* vergence — a throw's visible flight, rendered ahead and shown
 * frame-exactly: the hit study's stimulus (issue 18) does not depend on how
 * fast the device renders.
 *
 * flight_render renders frames first .. first + count - 1 of a headless
 * frame (readback, with its HUD drawn in: desc.overlay) and keeps each
 * composed image in memory. flight_show then shows one of them per 1/60 s
 * refresh through the window's FIFO swapchain, waiting for each refresh's
 * deadline where presentation itself does not wait, and records when each
 * was presented: a frame presented 1.5 refreshes or more after the one
 * before it is a missed presentation (the one before stayed up twice).
 * Each stored image is scaled to the window by nearest pixel (the composed
 * image already places the eyes; interleaved layouts render 1:1). */
#pragma once
#include <stdbool.h>

#include "frame/frame.h"
#include "window.h"

#define FLIGHT_HZ 60.0

typedef struct flight_record {
    int frames;                  /* frames of the flight (its visible interval at 60 Hz) */
    int shown;                   /* presented */
    int missed;                  /* presented late by half a refresh or more */
    double shown_s;              /* first presentation to the end of the last one's refresh */
    double worst_ms;             /* longest interval between two presentations */
} flight_record;

typedef struct flight flight;

vg_status flight_create(window *w, flight **out);
void flight_destroy(flight *fl);

/* Renders and keeps the frames; progress(user, done, count) after each
 * (it may draw in the window: nothing is in flight then). */
typedef vg_status (*flight_progress_fn)(void *user, int done, int count);
vg_status flight_render(flight *fl, frame *fr, long first, int count, flight_progress_fn progress, void *user);

/* Shows the kept frames, one per refresh; *quit on Q or Escape (the rest
 * of the flight is not shown). Advances the window one tick a frame, as a
 * replay expects. */
vg_status flight_show(flight *fl, flight_record *rec, bool *quit);

/* Whether the window holds the rate: shows the first kept frame (or a
 * blank picture) `count` times as flight_show would. */
vg_status flight_rate_check(flight *fl, int count, flight_record *rec);
