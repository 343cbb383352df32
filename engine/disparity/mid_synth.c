/* vergence — the benchmark window (mid_synth.h). */
#include "mid_synth.h"

#include "disp_operator.h"
#include "stereo/stereo_display.h"

#define NX MID_SYNTH_NX
#define NY MID_SYNTH_NY
#define NT MID_SYNTH_NT
#define BALLS 6

/* Static layers at several depths and balls crossing them in depth while
 * moving sideways; h from the lang operator per keyframe. */
mid_window *mid_synth_window(void)
{
    stereo_display d;
    stereo_display_init(&d, &(stereo_display_desc){0});
    mid_window *w;
    if (mid_window_create(&(mid_window_desc){.width = NX, .height = NY, .keyframes = NT,
                                             .range_lo = (float)(d.screen_vergence - 60),
                                             .range_hi = (float)(d.screen_vergence + 60)},
                          &w) != VG_OK)
        return NULL;
    for (int k = 0; k < NT; k++)
        for (int p = 0; p < w->ns; p++) {
            int x = p % NX, y = p / NX, i = k * w->ns + p;
            double z = y < NY / 4 ? 3.0 : (y >= NY - NY / 4 ? 1.5 : (x >= NX - 20 ? 0.9 : 10.0));
            double a = stereo_vergence_from_distance(&d, z), fx = 0, bx = 0;
            for (int b = 0; b < BALLS; b++) {
                double u = (double)k / (NT - 1), speed = 0.6 + 0.15 * b;
                double cx = 10.0 + 25.0 * b + 40.0 * speed * u, cy = 20.0 + 12.0 * b;
                double dx = x - cx, dy = y - cy;
                if (dx * dx + dy * dy > 36.0)
                    continue;
                /* Alternating constant speed and constant acceleration in depth. */
                a = b % 2 ? 35.0 + 195.0 * u : 35.0 + 195.0 * u * u;
                fx = k + 1 < NT ? 40.0 * speed / (NT - 1) : 0;
                bx = k > 0 ? -40.0 * speed / (NT - 1) : 0;
            }
            w->g[i] = (float)a;
            w->depth[i] = (float)stereo_distance_from_vergence(&d, a);
            w->flow_fwd[2 * i] = (float)fx;
            w->flow_bwd[2 * i] = (float)bx;
        }
    disp_operator *op;
    if (disp_operator_create(&(disp_operator_desc){.kind = DISP_OPERATOR_LANG, .screen_vergence = d.screen_vergence,
                                                    .in_min = 20, .in_max = 260},
                             &op) != VG_OK) {
        mid_window_destroy(w);
        return NULL;
    }
    for (int k = 0; k < NT; k++)
        disp_operator_apply(op, w->g + (size_t)k * w->ns, NULL, w->ns, w->h + (size_t)k * w->ns, NULL);
    disp_operator_destroy(op);
    if (mid_window_build(w, NULL) != VG_OK) {
        mid_window_destroy(w);
        return NULL;
    }
    return w;
}
