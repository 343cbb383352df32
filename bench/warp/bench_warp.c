/* vergence — stereo benchmark: warp.stereo GPU ms per eye at 960x540 for
 * tess-px 1, 2, 4, 8 and error-driven tessellation of the optimised map f,
 * and the ratio of the whole optimised stereo frame (G-buffer, disparity
 * pipeline, curve, warp, compose) to the plain two-camera stereo frame in
 * the same run. Medians of N frames after warm-up, no readback, no
 * per-pixel measurement (what a game frame does).
 *
 *   bench_warp [--scene FILE] [--frames N] [--size WxH] [--skip-1px]
 *
 * Not a test: figures go to docs/PERFORMANCE.md. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/clock.h"
#include "core/log.h"
#include "core/stats.h"
#include "frame/frame.h"

typedef struct result {
    double frame_ms;   /* wall clock of a frame that waits for completion */
    double eye_ms;     /* warp.left + warp.right (or cameras.*) */
    double passes_ms;  /* every pass, by the frame's pass clock */
} result;

static vg_status run(gpu *g, const scene *s, const frame_desc *d, int frames, result *out)
{
    frame *f;
    vg_status st = frame_create(g, s, d, &f);
    if (st != VG_OK)
        return st;
    frame_time_passes(f, true);
    double *total = calloc((size_t)frames, sizeof *total), *eyes = calloc((size_t)frames, sizeof *eyes),
           *sum = calloc((size_t)frames, sizeof *sum);
    for (int i = -3; i < frames && st == VG_OK; i++) {
        double t0 = vg_now_ms();
        st = frame_render(f, 90 + i);
        double wall = vg_now_ms() - t0;
        const char *names[64];
        double ms[64];
        uint32_t n = frame_pass_timings(f, names, ms, 64);
        if (i < 0)
            continue;
        total[i] = wall;
        for (uint32_t p = 0; p < n; p++) {
            sum[i] += ms[p];
            if (!strncmp(names[p], "warp.left", 9) || !strncmp(names[p], "warp.right", 10) ||
                !strncmp(names[p], "cameras.", 8))
                eyes[i] += ms[p];
        }
    }
    if (st == VG_OK)
        *out = (result){vg_median(total, (size_t)frames, 1), vg_median(eyes, (size_t)frames, 1),
                        vg_median(sum, (size_t)frames, 1)};
    free(total);
    free(sum);
    free(eyes);
    frame_destroy(f);
    return st;
}

int main(int argc, char **argv)
{
    const char *path = "content/balloon.gltf";
    int frames = 7, w = 960, h = 540;
    bool skip_1px = false;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--scene") && i + 1 < argc)
            path = argv[++i];
        else if (!strcmp(argv[i], "--frames") && i + 1 < argc)
            frames = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--size") && i + 1 < argc && sscanf(argv[i + 1], "%dx%d", &w, &h) == 2)
            i++;
        else if (!strcmp(argv[i], "--skip-1px"))
            skip_1px = true;
        else {
            fprintf(stderr, "usage: bench_warp [--scene FILE] [--frames N] [--size WxH] [--skip-1px]\n");
            return 2;
        }
    }
    if (frames < 1 || w < 16 || h < 16) {
        vg_error("bench_warp: bad --frames or --size");
        return 2;
    }
    scene *s;
    gpu *g;
    if (scene_load(path, &s) != VG_OK)
        return 1;
    if (gpu_create(&(gpu_desc){0}, &g) != VG_OK) {
        scene_destroy(s);
        return 1;
    }
    printf("warp benchmark: %s, %dx%d, %s, median of %d frames\n", path, w, h, g->props.deviceName, frames);
    printf("%-22s %12s %12s %12s\n", "tessellation", "warp ms/eye", "frame ms (wall)", "passes/wall");
    frame_desc base = {.width = (uint32_t)w, .height = (uint32_t)h, .stereo = FRAME_STEREO_WARP,
                       .mode = FRAME_MODE_OPTIMIZED, .diffuse = true};
    static const double px[] = {1, 2, 4, 8};
    result warp_error = {0};
    vg_status st = VG_OK;
    for (int i = 0; i < 5 && st == VG_OK; i++) {
        frame_desc d = base;
        char label[32];
        if (i < 4) {
            if (skip_1px && px[i] == 1)
                continue;
            d.tess_px = px[i];
            snprintf(label, sizeof label, "tess-px %g", px[i]);
        } else {
            d.tess_error = getenv("VG_TESS_ERROR") ? atof(getenv("VG_TESS_ERROR")) : 0; /* 0: the frame default */
            snprintf(label, sizeof label, "error-driven %g px", d.tess_error > 0 ? d.tess_error : 0.025);
        }
        result r;
        st = run(g, s, &d, i < 4 ? (frames + 2) / 3 : frames, &r);
        if (st == VG_OK)
            printf("%-22s %12.1f %12.1f %11.1f%%\n", label, r.eye_ms / 2, r.frame_ms, 100 * r.passes_ms / r.frame_ms);
        if (i == 4)
            warp_error = r;
    }
    result cams = {0}, original = {0};
    if (st == VG_OK) {
        frame_desc d = base;
        d.mode = FRAME_MODE_ORIGINAL;
        st = run(g, s, &d, frames, &original);
        if (st == VG_OK)
            printf("%-22s %12.1f %12.1f %11.1f%%\n", "error-driven, g only", original.eye_ms / 2, original.frame_ms,
                   100 * original.passes_ms / original.frame_ms);
    }
    if (st == VG_OK) {
        frame_desc d = base;
        d.stereo = FRAME_STEREO_CAMERAS;
        d.mode = FRAME_MODE_ORIGINAL;
        st = run(g, s, &d, frames, &cams);
    }
    if (st == VG_OK) {
        printf("%-22s %12.1f %12.1f %11.1f%%\n", "two cameras", cams.eye_ms / 2, cams.frame_ms,
               100 * cams.passes_ms / cams.frame_ms);
        printf("stereo frame ratio: optimised warp / two cameras %.2fx; warp of g / two cameras %.2fx\n",
               warp_error.frame_ms / cams.frame_ms, original.frame_ms / cams.frame_ms);
    }
    gpu_destroy(g);
    scene_destroy(s);
    return st == VG_OK ? 0 : 1;
}
