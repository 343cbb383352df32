/* vergence bench --game — the game's frame rate in each mode at its defaults
 * (issue 17): the arena, the eye size and layout `vergence play` picks for
 * its default window on this device, each mode's frame made as play makes
 * it (game_frame_desc), and the same replay every run: throws drawn from
 * seed 1 as play draws them, one every 3 s, each launched on a keyframe
 * and shown for its first 0.6 s, the keyframe window restarted at each
 * throw as the game does, the clock advanced a fixed number of 1/60 s ticks
 * a frame (3: a 20 fps game). The modes render frame by frame in turn, so
 * all see the same load; even frames with the pass clock on (the per-pass
 * means), odd ones with it off (the frame rate, as played). Headless: the
 * window's acquire and present are not counted. bench_ball then measures
 * the ball itself under h and f, throw by throw (issue 39). */
#include "bench_game.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/log.h"
#include "core/stats.h"
#include "frame/frame.h"
#include "observer/ball_measure.h"
#include "rules/game.h"

#define THROW_EVERY_S 3.0
#define READY_S 1.0 /* the ball rests at its start for a second before a throw, as in play */
#define MODES 4 /* original, manipulated, optimized (full solve), optimized (budgeted solve: play's) */
#define FULL 2
#define BUDGETED 3
#define MAX_PASSES 64

typedef struct replay {
    game_ball ball;              /* first: the pose hook's user */
    int throw_no;
    vg_camera cam;
} replay;

/* Throw k: launched at 1 s + 3 k s (frame 60 + 180 k: a keyframe). */
static void throw_make(replay *r, int k)
{
    game_throw_free_play(1, k, GAME_VISIBLE_S, &r->cam, &r->ball.th);
    r->ball.t_launch = READY_S + THROW_EVERY_S * k;
    r->throw_no = k;
}

typedef struct mode_samples {
    double *wall;              /* untimed frames */
    int n_wall;
    double pass_sum[MAX_PASSES];
    char pass_name[MAX_PASSES][48];
    int passes, n_timed;
    double timed_wall, timed_passes;
} mode_samples;

vg_status bench_game(gpu *g, scene *sc, const char *scene_path, stereo_display_desc display, int frames, int ticks,
                     bench_report *rep)
{
    static const frame_mode modes[MODES] = {FRAME_MODE_ORIGINAL, FRAME_MODE_MANIPULATED, FRAME_MODE_OPTIMIZED,
                                            FRAME_MODE_OPTIMIZED};
    static const char *const labels[MODES] = {"original g", "manipulated h", "optimized f, full solve",
                                              "optimized f, budgeted (play)"};
    vg_status st = VG_OK;
    replay r = {0};
    if (!game_ball_attach(sc, &r.ball, &r.cam)) {
        vg_error("--scene %s: no node named 'ball' to throw (see docs/content.md)", scene_path);
        return VG_ERR_FORMAT;
    }
    throw_make(&r, 0);

    uint32_t w, h;
    game_render_size(g, GAME_LAYOUT, GAME_WINDOW_W, GAME_WINDOW_H, &w, &h);
    frame *f[MODES] = {0};
    mode_samples ms[MODES] = {0};
    for (int m = 0; m < MODES && st == VG_OK; m++) {
        frame_desc fd = game_frame_desc(g, 0, modes[m], w, h, GAME_LAYOUT, DISP_OPERATOR_DEFAULT, false, &r.cam);
        fd.display = display;
        fd.budgeted_solve = m == BUDGETED;
        st = frame_create(g, sc, &fd, &f[m]);
        if (st == VG_OK && !(ms[m].wall = calloc((size_t)frames, sizeof(double))))
            st = VG_ERR_NOMEM;
    }
    const frame_desc *d0 = st == VG_OK ? frame_get_desc(f[0]) : NULL;
    if (st == VG_OK)
        vg_info("bench --game: %s, %ux%u per eye, %s, tessellation %.2g px, %u px shadows, %d ticks a frame, "
                "%d frames a mode", scene_path, w, h, frame_compose_names[GAME_LAYOUT], d0->tess_error,
                d0->shadow_size, ticks, frames);
    /* Frame 0 solves the whole first window (the game's first frame does
     * too): rendered, not counted. */
    for (int i = 0; i <= frames && st == VG_OK; i++) {
        long tick = (long)i * ticks;
        double t = tick / 60.0;
        /* Throw k comes (and the window restarts) at 3 k s, a second before
         * its launch; it flies until 3 k + 1.6 s. */
        int k = (int)floor(t / THROW_EVERY_S);
        if (k > r.throw_no) {
            throw_make(&r, k);
            for (int m = 0; m < MODES; m++)
                frame_restart(f[m]); /* the ball's future changed, as in play */
        }
        bool timed = i % 2 == 0;
        for (int m = 0; m < MODES && st == VG_OK; m++) {
            frame_time_passes(f[m], timed);
            double t0 = vg_now_ms();
            st = frame_render(f[m], tick);
            double wall = vg_now_ms() - t0;
            if (st != VG_OK || i == 0)
                continue;
            mode_samples *s = &ms[m];
            if (!timed) {
                s->wall[s->n_wall++] = wall;
                continue;
            }
            const char *names[MAX_PASSES];
            double p[MAX_PASSES];
            uint32_t n = frame_pass_timings(f[m], names, p, MAX_PASSES);
            s->passes = (int)n;
            s->n_timed++;
            s->timed_wall += wall;
            for (uint32_t q = 0; q < n; q++) {
                snprintf(s->pass_name[q], sizeof s->pass_name[q], "%s", names[q]);
                s->pass_sum[q] += p[q];
                s->timed_passes += p[q];
            }
        }
        vg_progress("bench --game", i, frames);
    }

    if (st == VG_OK) {
        char title[256], cells[4][32];
        snprintf(title, sizeof title,
                 "The game at its defaults: %s, %ux%u per eye, %s, %.2g px tessellation, %u px shadows; %d ticks a "
                 "frame (a %.0f fps game), throws every %.0f s",
                 scene_path, w, h, frame_compose_names[GAME_LAYOUT], d0->tess_error, d0->shadow_size, ticks,
                 60.0 / ticks, THROW_EVERY_S);
        bench_heading(rep, title);
        for (int m = 0; m < MODES; m++)
            snprintf(cells[m], sizeof cells[m], "%s", labels[m]);
        bench_row(rep, true, "measure", MODES, cells);
        double v[MODES], fps[MODES];
        for (int m = 0; m < MODES; m++) {
            double sum = 0;
            for (int i = 0; i < ms[m].n_wall; i++)
                sum += ms[m].wall[i];
            fps[m] = v[m] = ms[m].n_wall ? 1000.0 * ms[m].n_wall / sum : NAN;
        }
        bench_row_values(rep, "fps (frames / wall seconds)", MODES, v, "%.1f");
        double median[MODES];
        for (int m = 0; m < MODES; m++)
            v[m] = median[m] = vg_median(ms[m].wall, (size_t)ms[m].n_wall, 1);
        bench_row_values(rep, "frame ms, median", MODES, v, "%.1f");
        for (int m = 0; m < MODES; m++)
            v[m] = 1000.0 / median[m];
        bench_row_values(rep, "fps, median (1000 / median ms)", MODES, v, "%.1f");
        for (int m = 0; m < MODES; m++)
            v[m] = vg_quantile(ms[m].wall, (size_t)ms[m].n_wall, 1, 0.95);
        bench_row_values(rep, "frame ms, 95th percentile", MODES, v, "%.1f");
        for (int m = 0; m < MODES; m++)
            v[m] = vg_quantile(ms[m].wall, (size_t)ms[m].n_wall, 1, 1.0);
        bench_row_values(rep, "frame ms, worst", MODES, v, "%.1f");
        for (int m = 0; m < MODES; m++)
            v[m] = 100 * ms[m].timed_passes / ms[m].timed_wall;
        bench_row_values(rep, "passes / wall (timed frames)", MODES, v, "%.1f%%");
        /* Every pass of the optimised frame, mean ms (the solve's share of a
         * keyframe interval included), beside the same pass in the others. */
        const mode_samples *of = &ms[FULL];
        for (int q = 0; q < of->passes; q++) {
            char label[64];
            snprintf(label, sizeof label, "  %s (mean ms)", of->pass_name[q]);
            for (int m = 0; m < MODES; m++) {
                v[m] = NAN;
                for (int p = 0; p < ms[m].passes; p++)
                    if (!strcmp(ms[m].pass_name[p], of->pass_name[q]))
                        v[m] = ms[m].pass_sum[p] / ms[m].n_timed;
            }
            if (v[FULL] >= 0.2)
                bench_row_values(rep, label, MODES, v, "%.1f");
        }
        char line[512];
        snprintf(line, sizeof line, "Optimized / original median fps: %.2f with the full solve, %.2f budgeted "
                 "(play's; target, issue 40: 0.75 or more); frames / wall seconds: %.2f, %.2f. The window's present "
                 "is not counted.", median[0] / median[FULL], median[0] / median[BUDGETED], fps[FULL] / fps[0],
                 fps[BUDGETED] / fps[0]);
        bench_note(rep, line);
        /* The floor of this design: the optimized frame's passes without the
         * solver's iterations (mid.solve), against the original's passes. */
        double solve = 0, sums[MODES];
        for (int m = 0; m < MODES; m++)
            sums[m] = ms[m].n_timed ? ms[m].timed_passes / ms[m].n_timed : NAN;
        for (int p = 0; p < of->passes; p++)
            if (!strcmp(of->pass_name[p], "mid.solve"))
                solve = of->pass_sum[p] / of->n_timed;
        snprintf(line, sizeof line, "Floor: the timed frames' passes, %.1f ms original and %.1f ms optimized, "
                 "%.1f of them mid.solve; without any solver iteration the ratio would be %.2f (the window's "
                 "build, the keyframes and the upsampling remain).", sums[0], sums[FULL], solve,
                 sums[0] / (sums[FULL] - solve));
        bench_note(rep, line);
    }
    for (int m = 0; m < MODES; m++) {
        frame_destroy(f[m]);
        free(ms[m].wall);
    }
    scene_set_pose_hook(sc, NULL, NULL);
    return st;
}

/* ------------------------------------------------------------------------- */
/* The ball's own figures (issue 39)                                         */
/* ------------------------------------------------------------------------- */

#define BALL_KINDS GAME_THROW_KINDS
#define BALL_LAUNCH 60 /* frame of every launch (a keyframe, one second in, as in play) */

vg_status bench_ball(gpu *g, scene *sc, const char *scene_path, stereo_display_desc display, int per_kind,
                     bool every_frame, bool each, bench_report *rep)
{
    /* In game_throw_kind's order. */
    static const char *const kinds[BALL_KINDS] = {"straight, near-to-far", "ballistic, near-to-far",
                                                  "straight, far-to-near", "ballistic, far-to-near"};
    game_ball ball = {0};
    vg_camera cam;
    if (!game_ball_attach(sc, &ball, &cam)) {
        vg_error("--scene %s: no node named 'ball' to throw (see docs/content.md)", scene_path);
        return VG_ERR_FORMAT;
    }
    uint32_t w, h;
    game_render_size(g, GAME_LAYOUT, GAME_WINDOW_W, GAME_WINDOW_H, &w, &h);
    frame_desc fd = game_frame_desc(g, 0, FRAME_MODE_OPTIMIZED, w, h, GAME_LAYOUT, DISP_OPERATOR_DEFAULT, false, &cam);
    fd.display = display;
    ball_measure *m;
    vg_status st = ball_measure_create(&(ball_measure_desc){.gpu = g, .scene = sc, .ball = &ball, .frame = fd,
                                                                  .every_frame = every_frame}, &m);
    if (st != VG_OK) {
        scene_set_pose_hook(sc, NULL, NULL);
        return st;
    }
    int total = BALL_KINDS * per_kind, count[BALL_KINDS] = {0}, done = 0;
    double *hj = calloc((size_t)total, sizeof *hj), *fj = calloc((size_t)total, sizeof *fj);
    double *ratio = calloc((size_t)total, sizeof *ratio);
    int *kind = calloc((size_t)total, sizeof *kind), min_samples[BALL_KINDS], min_px[BALL_KINDS];
    if (!hj || !fj || !ratio || !kind)
        st = VG_ERR_NOMEM;
    for (int k = 0; k < BALL_KINDS; k++)
        min_samples[k] = min_px[k] = INT32_MAX;
    if (each && st == VG_OK)
        printf("  throw  kind                       h JND   f JND    f/h  samples  pixels  g and f - h at the keyframes "
               "(arcmin)\n");
    /* Throws as free play draws them (seed 1), each kind until it has per_kind. */
    for (int n = 0; done < total && st == VG_OK && n < 1000 * total; n++) {
        game_throw th;
        game_throw_free_play(1, n, GAME_VISIBLE_S, &cam, &th);
        int k = game_throw_kind(&th);
        if (count[k] >= per_kind)
            continue;
        ball_figures b;
        if ((st = ball_measure_throw(m, &th, BALL_LAUNCH, &b)) != VG_OK)
            break;
        hj[done] = every_frame ? b.h_frame_jnd : b.h_jnd, fj[done] = every_frame ? b.f_frame_jnd : b.f_jnd;
        kind[done] = k;
        ratio[done] = hj[done] > 0 ? fj[done] / hj[done] : NAN;
        min_samples[k] = b.min_samples < min_samples[k] ? b.min_samples : min_samples[k];
        min_px[k] = b.min_pixels < min_px[k] ? b.min_pixels : min_px[k];
        if (each) {
            printf("  %5d  %-24s %7.3f %7.3f %6.3f %8d %7d  g", n, kinds[k], hj[done], fj[done], ratio[done],
                   b.min_samples, b.min_pixels);
            for (int q = 0; q < b.keys; q++)
                printf(" %.1f", b.g[q]);
            printf("; f - h");
            for (int q = 0; q < b.keys; q++)
                printf(" %+.2f", b.f[q] - b.h[q]);
            printf("\n");
        }
        count[k]++, done++;
        vg_progress("bench --game: the ball", done, total);
    }
    if (st == VG_OK) {
        char title[320], cells[8][32];
        snprintf(title, sizeof title,
                 "The ball's own MID distortion %s: %d throws of each kind as free play draws them (seed 1), "
                 "%ux%u per eye, the game's operator; medians",
                 every_frame ? "at the frame rate" : "at the keyframes", per_kind, w, h);
        bench_heading(rep, title);
        const char *head[] = {"throws", "h JND", "f JND", "f / h", "f < h", "fewest samples", "fewest px"};
        for (int c = 0; c < 7; c++)
            snprintf(cells[c], sizeof cells[c], "%s", head[c]);
        bench_row(rep, true, "kind", 7, cells);
        double *v = malloc(3 * (size_t)total * sizeof *v);
        for (int k = 0; k <= BALL_KINDS && v; k++) {
            int n = 0, below = 0, ms = INT32_MAX, mp = INT32_MAX;
            for (int i = 0; i < done; i++)
                if (k == BALL_KINDS || kind[i] == k) {
                    v[n] = hj[i], v[total + n] = fj[i], v[2 * total + n] = ratio[i];
                    below += fj[i] < hj[i];
                    n++;
                }
            for (int q = 0; q < BALL_KINDS; q++)
                if (k == BALL_KINDS || q == k)
                    ms = min_samples[q] < ms ? min_samples[q] : ms, mp = min_px[q] < mp ? min_px[q] : mp;
            snprintf(cells[0], sizeof cells[0], "%d", n);
            snprintf(cells[1], sizeof cells[1], "%.3f", vg_median(v, (size_t)n, 1));
            snprintf(cells[2], sizeof cells[2], "%.3f", vg_median(v + total, (size_t)n, 1));
            snprintf(cells[3], sizeof cells[3], "%.3f", vg_median(v + 2 * total, (size_t)n, 1));
            snprintf(cells[4], sizeof cells[4], "%.0f%%", n ? 100.0 * below / n : 0.0);
            snprintf(cells[5], sizeof cells[5], "%d", ms);
            snprintf(cells[6], sizeof cells[6], "%d", mp);
            bench_row(rep, false, k == BALL_KINDS ? "all" : kinds[k], 7, cells);
        }
        free(v);
        bench_note(rep, every_frame
                            ? "Per throw: the ball's displayed vergence under g, h and f at every frame of its visible "
                              "flight (its centre's g plus the mean of map - g over its pixels) and its MID distortion "
                              "against g at the frame rate (docs/method.md §11 on that track; "
                              "game/observer/ball_measure.h). Samples: the solver grid's samples on the ball, fewest "
                              "at a keyframe of the flight; px: its pixels."
                            : "Per throw: the ball's displayed vergence under g, h and f at every keyframe of its "
                              "visible flight (its centre's g plus the mean of map - g over its pixels) and its MID "
                              "distortion against g (docs/method.md §11 on that track; "
                              "game/observer/ball_measure.h); --ball-frames: at every frame. Samples: the solver "
                              "grid's samples on the ball, fewest at a keyframe of the flight; px: its pixels.");
    }
    free(hj), free(fj), free(ratio), free(kind);
    ball_measure_destroy(m);
    scene_set_pose_hook(sc, NULL, NULL);
    return st;
}
