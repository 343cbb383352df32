/* `vergence optimize` end to end: a synthetic sequence written here, the
 * third-party files, and bad inputs. Run one case:
 *   test_optimize_cli NAME VERGENCE_EXECUTABLE WORKDIR */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "../test.h"
#include "core/io.h"
#include "stereo/stereo_display.h"

#define W 160
#define H 90
#define LAST 60
#define STEREO "../shared/assets/stereo/"

static const char *g_exe = "build/game/vergence";
static char g_work[512] = "build/test-optimize";
static char g_stderr[65536];

/* ------------------------------------------------------------------------- */
/* Helpers                                                                   */
/* ------------------------------------------------------------------------- */

/* Runs vergence with the arguments; returns its exit code, stderr in g_stderr. */
static int run_vergence(const char *args)
{
    char cmd[20000], err[1200];
    snprintf(err, sizeof err, "%s/stderr.txt", g_work);
    snprintf(cmd, sizeof cmd, "'%s' optimize %s 2> '%s'", g_exe, args, err);
    int rc = system(cmd);
    FILE *f = fopen(err, "rb");
    size_t n = f ? fread(g_stderr, 1, sizeof g_stderr - 1, f) : 0;
    g_stderr[n] = 0;
    if (f)
        fclose(f);
    int code = WIFEXITED(rc) ? WEXITSTATUS(rc) : 128;
    printf("$ vergence optimize %s\n  -> exit %d\n", args, code);
    return code;
}

static int count_errors(const char *text)
{
    int n = 0;
    for (const char *p = text; (p = strstr(p, "error:")); p++)
        n++;
    return n;
}

/* The number after "key": inside the object "section" of a JSON text. */
static double json_number(const char *json, const char *section, const char *key)
{
    char pat[128];
    snprintf(pat, sizeof pat, "\"%s\": {", section);
    const char *s = strstr(json, pat);
    if (!s)
        return NAN;
    const char *end = strchr(s, '}');
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char *k = strstr(s, pat);
    return k && k < end ? strtod(k + strlen(pat), NULL) : NAN;
}

static bool exists(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

static void path_in(char *out, size_t cap, const char *name)
{
    snprintf(out, cap, "%s/%s", g_work, name);
}

/* ------------------------------------------------------------------------- */
/* The synthetic sequence                                                    */
/* ------------------------------------------------------------------------- */

/* Static layers at 10 m, 3 m, 1.5 m and 0.9 m; a ball of radius 20 px moves
 * sideways and in depth at constant vergence speed from 35 to 230 arcmin,
 * crossing the layers' depths (the operator compresses the gaps). */
static double ball_x(int t)
{
    return 40.0 + 80.0 * t / LAST;
}

static bool on_ball(int t, int x, int y)
{
    double dx = x - ball_x(t), dy = y - 0.5 * (H - 1);
    return dx * dx + dy * dy <= 20.0 * 20.0;
}

static vg_status write_sequence(const char *dir)
{
    stereo_display d;
    stereo_display_init(&d, &(stereo_display_desc){0});
    vg_imagef g, z, fn, fp;
    if (vg_imagef_alloc(&g, W, H, 1) || vg_imagef_alloc(&z, W, H, 1) || vg_imagef_alloc(&fn, W, H, 2) ||
        vg_imagef_alloc(&fp, W, H, 2))
        return VG_ERR_NOMEM;
    vg_status st = VG_OK;
    uint8_t *sal = malloc(W * H);
    if (!sal)
        return VG_ERR_NOMEM;
    for (int t = 0; t <= LAST && st == VG_OK; t++) {
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                int i = y * W + x;
                bool ball = on_ball(t, x, y);
                double zm = y < H / 4 ? 3.0 : (y >= H - H / 4 ? 1.5 : (x >= W - 30 ? 0.9 : 10.0));
                double a = ball ? 35.0 + 195.0 * t / LAST : stereo_vergence_from_distance(&d, zm);
                g.data[i] = (float)a;
                z.data[i] = (float)stereo_distance_from_vergence(&d, a);
                fn.data[2 * i] = ball && t < LAST ? (float)(ball_x(t + 1) - ball_x(t)) : 0.0f;
                fp.data[2 * i] = ball && t > 0 ? (float)(ball_x(t - 1) - ball_x(t)) : 0.0f;
                fn.data[2 * i + 1] = fp.data[2 * i + 1] = 0.0f;
                sal[i] = ball ? 255 : 20; /* the moving object is the salient one */
            }
        char p[1200];
        snprintf(p, sizeof p, "%s/g_%04d.pfm", dir, t);
        st = vg_pfm_write(p, &g);
        snprintf(p, sizeof p, "%s/z_%04d.pfm", dir, t);
        if (st == VG_OK)
            st = vg_pfm_write(p, &z);
        snprintf(p, sizeof p, "%s/fn_%04d.flo", dir, t);
        if (st == VG_OK)
            st = vg_flo_write(p, &fn);
        snprintf(p, sizeof p, "%s/fp_%04d.flo", dir, t);
        if (st == VG_OK)
            st = vg_flo_write(p, &fp);
        snprintf(p, sizeof p, "%s/s_%04d.png", dir, t);
        if (st == VG_OK)
            st = vg_png_write(p, W, H, 1, sal);
    }
    free(sal);
    vg_imagef_free(&g);
    vg_imagef_free(&z);
    vg_imagef_free(&fn);
    vg_imagef_free(&fp);
    return st;
}

static int prepare(void)
{
    CHECK(vg_dir_prepare(g_work) == VG_OK, "work folder %s", g_work);
    char first[1200];
    path_in(first, sizeof first, "s_0060.png");
    if (!exists(first))
        CHECK(write_sequence(g_work) == VG_OK, "writing the synthetic sequence");
    return 0;
}

/* ------------------------------------------------------------------------- */
/* Cases                                                                     */
/* ------------------------------------------------------------------------- */

/* `none` manipulates nothing: even where g leaves the comfort range, the
 * optimiser has no reason to move it, so f = g and motion is untouched. */
static int operator_none_keeps_g(void)
{
    CHECK(prepare() == 0, "prepare");
    char args[16384], out[1200];
    path_in(out, sizeof out, "out_none");
    snprintf(args, sizeof args,
             "--g '%s/g_%%04d.pfm' --depth '%s/z_%%04d.pfm' --flow-next '%s/fn_%%04d.flo' "
             "--flow-prev '%s/fp_%%04d.flo' --frames 0:%d --operator none --out '%s' --threads 2",
             g_work, g_work, g_work, g_work, LAST, out);
    CHECK(run_vergence(args) == 0, "optimize failed:\n%s", g_stderr);
    char path[1400];
    snprintf(path, sizeof path, "%s/metrics.json", out);
    uint8_t *json;
    size_t size;
    CHECK(vg_file_read(path, &json, &size) == VG_OK, "metrics.json");
    double mf = json_number((char *)json, "f", "mid_distortion_jnd");
    double tepe = json_number((char *)json, "f", "tepe_arcmin"), tepe_a = json_number((char *)json, "f", "tepe_accel_arcmin");
    free(json);
    printf("operator none: f's TEPE against g %.4g arcmin, its acceleration variant %.4g\n", tepe, tepe_a);
    CHECK(tepe >= 0 && tepe < 0.01 && tepe_a >= 0 && tepe_a < 0.01, "f = g, yet TEPE %.4g / %.4g", tepe, tepe_a);
    double worst = 0;
    for (int t = 0; t <= LAST; t += 10) {
        vg_imagef f, g;
        snprintf(path, sizeof path, "%s/f_%04d.pfm", out, t);
        CHECK(vg_pfm_read(path, &f) == VG_OK, "%s", path);
        char name[32];
        snprintf(name, sizeof name, "g_%04d.pfm", t);
        path_in(path, sizeof path, name);
        CHECK(vg_pfm_read(path, &g) == VG_OK, "%s", path);
        for (int i = 0; i < W * H; i++)
            worst = fmax(worst, fabs((double)f.data[i] - g.data[i]));
        vg_imagef_free(&f);
        vg_imagef_free(&g);
    }
    printf("operator none: f MID distortion %.4g JND, max |f - g| %.4g arcmin\n", mf, worst);
    CHECK(mf < 0.05, "f distorts motion in depth: %.4g JND", mf);
    CHECK(worst < 0.01, "f differs from g by %.4g arcmin", worst);
    return 0;
}

static int synthetic_sequence(void)
{
    CHECK(prepare() == 0, "prepare");
    char args[16384], out[1200];
    path_in(out, sizeof out, "out");
    snprintf(args, sizeof args,
             "--g '%s/g_%%04d.pfm' --depth '%s/z_%%04d.pfm' --flow-next '%s/fn_%%04d.flo' "
             "--flow-prev '%s/fp_%%04d.flo' --frames 0:%d --out '%s' --threads 2",
             g_work, g_work, g_work, g_work, LAST, out);
    CHECK(run_vergence(args) == 0, "optimize failed:\n%s", g_stderr);
    char path[1400];
    snprintf(path, sizeof path, "%s/metrics.json", out);
    uint8_t *json;
    size_t size;
    CHECK(vg_file_read(path, &json, &size) == VG_OK, "metrics.json");
    double mh = json_number((char *)json, "h", "mid_distortion_jnd");
    double mf = json_number((char *)json, "f", "mid_distortion_jnd");
    double rv = json_number((char *)json, "f", "range_violation");
    double srms = json_number((char *)json, "f", "static_rms");
    double th = json_number((char *)json, "h", "tepe_arcmin"), tf = json_number((char *)json, "f", "tepe_arcmin");
    double tha = json_number((char *)json, "h", "tepe_accel_arcmin"), tfa = json_number((char *)json, "f", "tepe_accel_arcmin");
    printf("metrics.json: TEPE against g, h %.3f / f %.3f arcmin; acceleration h %.3f / f %.3f arcmin\n", th, tf, tha, tfa);
    CHECK(th > 0 && tf > 0 && tha > 0 && tfa > 0 && isfinite(th + tf + tha + tfa), "TEPE missing or not positive");
    double lo = json_number((char *)json, "input", "range_lo"), hi = json_number((char *)json, "input", "range_hi");
    printf("metrics.json: MID distortion h %.3f -> f %.3f JND (%.1f %% less); f range violation %.4g; static RMS %.3f arcmin of %.0f\n",
           mh, mf, 100 * (1 - mf / mh), rv, srms, hi - lo);
    CHECK(mh > 1.0, "h must distort motion in depth (%.3f JND)", mh);
    CHECK(mf <= 0.5 * mh, "f must halve the MID distortion: %.3f -> %.3f", mh, mf);
    CHECK(rv == 0.0, "f leaves the target range: %.4g", rv);
    CHECK(srms < 0.05 * (hi - lo), "static RMS %.3f", srms);
    free(json);
    /* Every frame written, full size, inside the range. */
    for (int t = 0; t <= LAST; t++) {
        vg_imagef f;
        snprintf(path, sizeof path, "%s/f_%04d.pfm", out, t);
        CHECK(vg_pfm_read(path, &f) == VG_OK && f.width == W && f.height == H, "%s", path);
        for (int i = 0; i < W * H; i++)
            CHECK(f.data[i] >= lo - 1e-3 && f.data[i] <= hi + 1e-3, "%s: %.4f outside the range", path, f.data[i]);
        vg_imagef_free(&f);
    }
    /* The x-t slices (one row of every frame) and the previews (the middle
     * frame) for people: in colour, enlarged 2x to 320 px, a legend below. */
    const char *figures[] = {"xt_g.png", "xt_h.png", "xt_f.png", "preview_g.png", "preview_h.png", "preview_f.png"};
    for (int i = 0; i < 6; i++) {
        int w, h, rows = i < 3 ? LAST + 1 : H;
        uint8_t *px;
        snprintf(path, sizeof path, "%s/%s", out, figures[i]);
        CHECK(vg_png_read(path, &w, &h, 3, &px) == VG_OK && w == 2 * W && h > 2 * rows + 30, "%s is %dx%d", path,
              w, h);
        int coloured = 0, paper = 0;
        for (int p = 0; p < w * 2 * rows; p++)
            coloured += abs(px[3 * p] - px[3 * p + 1]) > 20 || abs(px[3 * p + 1] - px[3 * p + 2]) > 20;
        for (int p = w * (2 * rows + 2); p < w * h; p++)
            paper += px[3 * p] == 255 && px[3 * p + 1] == 255 && px[3 * p + 2] == 255;
        CHECK(coloured > w * rows, "%s: the map is not in colour (%d coloured pixels)", path, coloured);
        CHECK(paper > w * 10, "%s: no legend strip below the map", path);
        free(px);
    }
    if (system("command -v ffmpeg > /dev/null 2>&1") == 0)
        for (int m = 0; m < 3; m++) {
            snprintf(path, sizeof path, "%s/%c.mp4", out, "ghf"[m]);
            CHECK(access(path, R_OK) == 0, "ffmpeg is installed but %s is missing", path);
        }
    return 0;
}

/* h = g inside the target range: g already has g's motion, so every written
 * frame is g (through the keyframe flows, the solve and both upsamplings). */
static int given_h_identity(void)
{
    CHECK(prepare() == 0, "prepare");
    char args[16384], out[1200], path[1400];
    path_in(out, sizeof out, "out_identity");
    snprintf(args, sizeof args,
             "--g '%s/g_%%04d.pfm' --h '%s/g_%%04d.pfm' --depth '%s/z_%%04d.pfm' --flow-next '%s/fn_%%04d.flo' "
             "--flow-prev '%s/fp_%%04d.flo' --frames 0:%d --target-range 270 --out '%s'",
             g_work, g_work, g_work, g_work, g_work, LAST, out);
    CHECK(run_vergence(args) == 0, "optimize failed:\n%s", g_stderr);
    double worst = 0;
    for (int t = 0; t <= LAST; t++) {
        vg_imagef f, g;
        snprintf(path, sizeof path, "%s/f_%04d.pfm", out, t);
        CHECK(vg_pfm_read(path, &f) == VG_OK, "%s", path);
        snprintf(path, sizeof path, "%s/g_%04d.pfm", g_work, t);
        CHECK(vg_pfm_read(path, &g) == VG_OK, "%s", path);
        for (int i = 0; i < W * H; i++)
            worst = fmax(worst, fabs(f.data[i] - g.data[i]));
        vg_imagef_free(&f);
        vg_imagef_free(&g);
    }
    printf("h = g: max |f - g| over %d frames = %.3g arcmin\n", LAST + 1, worst);
    CHECK(worst <= 1e-3, "f departs from g by %.3g arcmin", worst);
    return 0;
}

/* --saliency feeds the operator: h changes (its x-t slice differs), the run
 * completes and f stays in the range. */
static int saliency_input(void)
{
    CHECK(prepare() == 0, "prepare");
    /* Runs: every pixel alike (--uniform-saliency), a saliency file, and the
     * default without one: computed from the flows and depth. */
    static const char *const names[3] = {"out_plain", "out_saliency", "out_computed"};
    static const char *const said[3] = {"\"saliency\": \"uniform\"", "\"saliency\": \"file\"",
                                        "\"saliency\": \"computed\""};
    char args[16384], out[3][600], path[2048], extra[1024];
    uint8_t *px[3];
    double rv = 1;
    for (int run = 0; run < 3; run++) {
        path_in(out[run], sizeof out[run], names[run]);
        if (run == 1)
            snprintf(extra, sizeof extra, "--saliency '%s/s_%%04d.png'", g_work);
        else
            snprintf(extra, sizeof extra, "%s", run ? "" : "--uniform-saliency");
        snprintf(args, sizeof args, "--g '%s/g_%%04d.pfm' --flow-next '%s/fn_%%04d.flo' %s --frames 0:%d --out '%s'",
                 g_work, g_work, extra, LAST, out[run]);
        CHECK(run_vergence(args) == 0, "optimize failed:\n%s", g_stderr);
        int w, h;
        snprintf(path, sizeof path, "%s/xt_h.png", out[run]);
        CHECK(vg_png_read(path, &w, &h, 1, &px[run]) == VG_OK, "%s", path);
        snprintf(path, sizeof path, "%s/preview_saliency.png", out[run]);
        CHECK(exists(path) == (run > 0), "%s: preview_saliency.png %s", names[run], run ? "missing" : "written");
        snprintf(path, sizeof path, "%s/metrics.json", out[run]);
        uint8_t *json;
        size_t size;
        CHECK(vg_file_read(path, &json, &size) == VG_OK, "%s", path);
        rv = fmax(json_number((char *)json, "f", "range_violation"), run ? rv : 0);
        CHECK(strstr((char *)json, said[run]) != NULL, "%s: metrics.json does not say %s", names[run], said[run]);
        free(json);
    }
    int differ[2] = {0, 0};
    for (int i = 0; i < W * (LAST + 1); i++)
        for (int k = 0; k < 2; k++)
            differ[k] += px[0][i] != px[k + 1][i];
    printf("x-t slice of h: %d (file) and %d (computed) of %d pixels change against uniform saliency; "
           "f range violation %g\n", differ[0], differ[1], W * (LAST + 1), rv);
    CHECK(differ[0] > 100, "the saliency file must change h");
    CHECK(differ[1] > 100, "the computed saliency must change h");
    CHECK(rv == 0.0, "f outside the range");
    for (int k = 0; k < 3; k++)
        free(px[k]);
    return 0;
}

/* A missing frame, a truncated one, one of another size: one clear error
 * naming the file, found before any work, so the earlier result in --out
 * (here an empty one) is left as it was (docs/formats.md "Results"). */
static int check_failure(const char *args, const char *out, const char *file, const char *words)
{
    static const char earlier[] = "{\"vergence\": \"0.1.0\", \"files\": []}";
    char stale[1400];
    snprintf(stale, sizeof stale, "%s/metrics.json", out);
    vg_dir_prepare(out);
    vg_file_write_atomic(stale, earlier, sizeof earlier - 1);
    int code = run_vergence(args);
    printf("  stderr: %s", g_stderr);
    CHECK(code != 0, "must fail");
    CHECK(strstr(g_stderr, file) && strstr(g_stderr, words), "the error must name %s and say '%s'", file, words);
    CHECK(count_errors(g_stderr) == 1, "exactly one error line, got %d", count_errors(g_stderr));
    uint8_t *data = NULL;
    size_t size = 0;
    CHECK(vg_file_read(stale, &data, &size) == VG_OK && size == sizeof earlier - 1 && !memcmp(data, earlier, size),
          "the earlier result must stay as it was when the inputs are refused");
    free(data);
    return 0;
}

static int bad_inputs(void)
{
    CHECK(prepare() == 0, "prepare");
    char args[16384], out[1200], p[1200];
    path_in(out, sizeof out, "out_bad");
    /* Missing: frame 61 does not exist. */
    snprintf(args, sizeof args, "--g '%s/g_%%04d.pfm' --frames 0:61 --out '%s'", g_work, out);
    if (check_failure(args, out, "g_0061.pfm", "cannot open"))
        return 1;
    /* Truncated: a copy of the sequence's g with frame 5 cut short. */
    for (int t = 0; t <= 10; t++) {
        char src[1200];
        uint8_t *data;
        size_t size;
        snprintf(src, sizeof src, "%s/g_%04d.pfm", g_work, t);
        snprintf(p, sizeof p, "%s/trunc_%04d.pfm", g_work, t);
        CHECK(vg_file_read(src, &data, &size) == VG_OK, "%s", src);
        CHECK(vg_file_write_atomic(p, data, t == 5 ? size / 2 : size) == VG_OK, "%s", p);
        free(data);
    }
    snprintf(args, sizeof args, "--g '%s/trunc_%%04d.pfm' --frames 0:10 --out '%s'", g_work, out);
    if (check_failure(args, out, "trunc_0005.pfm", "truncated"))
        return 1;
    /* Mismatched size: depth frame 3 is half size. */
    vg_imagef z;
    for (int t = 0; t <= 10; t++) {
        int w = t == 3 ? W / 2 : W, h = t == 3 ? H / 2 : H;
        CHECK(vg_imagef_alloc(&z, w, h, 1) == VG_OK, "alloc");
        for (int i = 0; i < w * h; i++)
            z.data[i] = 2.0f;
        snprintf(p, sizeof p, "%s/zs_%04d.pfm", g_work, t);
        CHECK(vg_pfm_write(p, &z) == VG_OK, "%s", p);
        vg_imagef_free(&z);
    }
    snprintf(args, sizeof args, "--g '%s/g_%%04d.pfm' --depth '%s/zs_%%04d.pfm' --frames 0:10 --out '%s'",
             g_work, g_work, out);
    return check_failure(args, out, "zs_0003.pfm", "same size");
}

static int bad_patterns(void)
{
    const char *patterns[] = {"in/g.pfm", "in/g_%d_%d.pfm", "in/g_%s.pfm", "in/g_%04x.pfm"};
    CHECK(vg_dir_prepare(g_work) == VG_OK, "work folder");
    for (int i = 0; i < 4; i++) {
        char args[4096];
        snprintf(args, sizeof args, "--g '%s' --frames 0:3 --out '%s/out_pattern'", patterns[i], g_work);
        int code = run_vergence(args);
        printf("  stderr: %s", g_stderr);
        CHECK(code == 2, "bad pattern '%s' must be an argument error (exit 2), got %d", patterns[i], code);
        CHECK(count_errors(g_stderr) == 1 && strstr(g_stderr, "--g"), "one error naming --g");
    }
    return 0;
}

/* (b) Files that did not come from this engine: the FlyingThings3D pair
 * (pixel disparity) and the Sintel flow (with a g of its size). */
static int third_party(void)
{
    CHECK(vg_dir_prepare(g_work) == VG_OK, "work folder");
    char args[16384], out[1200], path[1400];
    /* Two frames are too few for an acceleration (three keyframes). */
    path_in(out, sizeof out, "out_ft3d");
    snprintf(args, sizeof args, "--g '" STEREO "flyingthings3d_pair_from_RAFT-3D/disp%%d.pfm' --frames 1:2 "
             "--g-units px --operator linear --out '%s'", out);
    CHECK(run_vergence(args) == 2 && count_errors(g_stderr) == 1 && strstr(g_stderr, "needs 3"),
          "FlyingThings3D pair, two frames: the too-few-frames error\n%s", g_stderr);
    /* The pair and its second frame again, a keyframe each, with the left images. */
    for (int t = 0; t < 3; t++) {
        vg_imagef in;
        snprintf(path, sizeof path, STEREO "flyingthings3d_pair_from_RAFT-3D/disp%d.pfm", t ? 2 : 1);
        CHECK(vg_pfm_read(path, &in) == VG_OK, "%s", path);
        snprintf(path, sizeof path, "%s/ft3d_%d.pfm", g_work, t);
        CHECK(vg_pfm_write(path, &in) == VG_OK, "%s", path);
        vg_imagef_free(&in);
        int iw, ih;
        uint8_t *rgb;
        snprintf(path, sizeof path, STEREO "flyingthings3d_pair_from_RAFT-3D/image%d.png", t ? 2 : 1);
        CHECK(vg_png_read(path, &iw, &ih, 3, &rgb) == VG_OK, "%s", path);
        snprintf(path, sizeof path, "%s/ft3d_image_%d.png", g_work, t);
        CHECK(vg_png_write(path, iw, ih, 3, rgb) == VG_OK, "%s", path);
        free(rgb);
    }
    snprintf(args, sizeof args, "--g '%s/ft3d_%%d.pfm' --image '%s/ft3d_image_%%d.png' --frames 0:2 "
             "--keyframe-stride 1 --g-units px --operator linear --no-video --out '%s'", g_work, g_work, out);
    CHECK(run_vergence(args) == 0, "FlyingThings3D pair, three frames:\n%s", g_stderr);
    snprintf(path, sizeof path, "%s/metrics.json", out);
    uint8_t *json;
    size_t size;
    CHECK(vg_file_read(path, &json, &size) == VG_OK, "metrics.json");
    double gmin = json_number((char *)json, "input", "g_min"), gmax = json_number((char *)json, "input", "g_max");
    double rv = json_number((char *)json, "f", "range_violation");
    stereo_display d;
    stereo_display_init(&d, &(stereo_display_desc){0});
    double want_lo = stereo_vergence_from_dataset_px(&d, 1.133, 0, 960), want_hi = stereo_vergence_from_dataset_px(&d, 108.917, 0, 960);
    printf("FlyingThings3D: g %.3f .. %.3f arcmin (expected about %.3f .. %.3f), f range violation %g\n", gmin,
           gmax, want_lo, want_hi, rv);
    CHECK(fabs(gmin - want_lo) < 0.5 && fabs(gmax - want_hi) < 0.5, "pixel disparity -> vergence");
    CHECK(rv == 0.0, "f outside the range");
    /* A new pair from f, the image taken as the left view (pixel disparities). */
    double holes = json_number((char *)json, "stereo_pair", "hole_fraction");
    printf("new stereo pair: %.4f holes before the fill, view %s\n", holes,
           strstr((char *)json, "\"image_view\": \"left\"") ? "left" : "not left");
    CHECK(holes > 0 && holes < 0.2 && strstr((char *)json, "\"image_view\": \"left\""), "the new pair");
    for (int t = 0; t < 3; t++)
        for (int e = 0; e < 2; e++) {
            int iw, ih;
            uint8_t *rgb;
            snprintf(path, sizeof path, "%s/%s_%04d.png", out, e ? "right" : "left", t);
            CHECK(vg_png_read(path, &iw, &ih, 3, &rgb) == VG_OK && iw == 960 && ih == 540, "%s", path);
            free(rgb);
        }
    free(json);
    vg_imagef f;
    snprintf(path, sizeof path, "%s/f_0002.pfm", out);
    CHECK(vg_pfm_read(path, &f) == VG_OK && f.width == 960 && f.height == 540, "%s", path);
    vg_imagef_free(&f);
    snprintf(path, sizeof path, "%s/f_0000.pfm", out);
    CHECK(vg_pfm_read(path, &f) == VG_OK, "%s", path);
    vg_imagef_free(&f);

    /* Sintel: its flow drives a g of its own size (1024x436). */
    vg_imagef g;
    CHECK(vg_imagef_alloc(&g, 1024, 436, 1) == VG_OK, "alloc");
    for (int t = 2; t <= 4; t++) {
        for (int i = 0; i < 1024 * 436; i++)
            g.data[i] = 250.0f + 20.0f * sinf(0.01f * (i % 1024) + 0.3f * t);
        snprintf(path, sizeof path, "%s/sintel_g_%04d.pfm", g_work, t);
        CHECK(vg_pfm_write(path, &g) == VG_OK, "%s", path);
    }
    vg_imagef_free(&g);
    /* Its one flow field, for frames 2 and 3 of the three. */
    vg_imagef flow;
    CHECK(vg_flo_read(STEREO "sintel_alley_2_flow_from_faldoi/gt/frame_0002.flo", &flow) == VG_OK, "Sintel flow");
    for (int t = 2; t <= 3; t++) {
        snprintf(path, sizeof path, "%s/sintel_flow_%04d.flo", g_work, t);
        CHECK(vg_flo_write(path, &flow) == VG_OK, "%s", path);
    }
    vg_imagef_free(&flow);
    path_in(out, sizeof out, "out_sintel");
    snprintf(args, sizeof args, "--g '%s/sintel_g_%%04d.pfm' --flow-next '%s/sintel_flow_%%04d.flo' --frames 2:4 "
             "--keyframe-stride 1 --out '%s'", g_work, g_work, out);
    CHECK(run_vergence(args) == 0, "Sintel flow:\n%s", g_stderr);
    snprintf(path, sizeof path, "%s/metrics.json", out);
    CHECK(exists(path), "metrics.json");
    /* The FlyingThings3D g with the Sintel flow: sizes differ. */
    path_in(out, sizeof out, "out_mixed");
    snprintf(args, sizeof args, "--g '" STEREO "flyingthings3d_pair_from_RAFT-3D/disp%%d.pfm' --g-units px "
             "--flow-next '" STEREO "sintel_alley_2_flow_from_faldoi/gt/frame_%%04d.flo' --frames 2:3 --out '%s'", out);
    return check_failure(args, out, "frame_0002.flo", "same size");
}

/* The new pair's video as players read it (issue 43): each layout's file
 * named as iw3 names it (the suffixes VR players detect), its frame the size
 * the layout packs, and ffprobe finding the packing: the stereo_mode that
 * FFmpeg's H.264 decoder reads from the frame-packing SEI of the MP4, and
 * the Matroska track's StereoMode (stream side data "Stereo 3D"). */
static int stereo_video(void)
{
    CHECK(prepare() == 0, "prepare");
    CHECK(system("command -v ffprobe > /dev/null 2>&1") == 0, "ffprobe is missing (Debian package ffmpeg; tools/dev "
          "installs it)");
    char path[1400], args[16384], out[1200], cmd[3000], text[8192];
    uint8_t rgb[W * H * 3];
    for (int t = 0; t <= 20; t++) {
        for (int i = 0; i < W * H; i++)
            rgb[3 * i] = (uint8_t)(i % W), rgb[3 * i + 1] = (uint8_t)(2 * (i / W)), rgb[3 * i + 2] = (uint8_t)(10 * t);
        snprintf(path, sizeof path, "%s/img_%04d.png", g_work, t);
        CHECK(vg_png_write(path, W, H, 3, rgb) == VG_OK, "%s", path);
    }
    static const struct {
        const char *layout, *file, *mode, *type;
        int w, h;
    } cases[4] = {
        {"full-sbs", "stereo_LRF_Full_SBS", "left_right", "side by side", 2 * W, H},
        {"half-sbs", "stereo_LR", "left_right", "side by side", W, H},
        {"full-tb", "stereo_TBF_fulltb", "top_bottom", "top and bottom", W, 2 * H},
        {"half-tb", "stereo_TB", "top_bottom", "top and bottom", W, H},
    };
    for (int c = 0; c < 4; c++) {
        char name[64];
        snprintf(name, sizeof name, "out_%s", cases[c].layout);
        path_in(out, sizeof out, name);
        snprintf(args, sizeof args,
                 "--g '%s/g_%%04d.pfm' --depth '%s/z_%%04d.pfm' --flow-next '%s/fn_%%04d.flo' "
                 "--flow-prev '%s/fp_%%04d.flo' --frames 0:20 --image '%s/img_%%04d.png' --stereo-layout %s --mkv "
                 "--out '%s' --threads 2", g_work, g_work, g_work, g_work, g_work, cases[c].layout, out);
        CHECK(run_vergence(args) == 0, "optimize failed:\n%s", g_stderr);
        for (int k = 0; k < 2; k++) {
            snprintf(path, sizeof path, "%s/%s.%s", out, cases[c].file, k ? "mkv" : "mp4");
            CHECK(access(path, R_OK) == 0, "%s is missing", path);
            snprintf(cmd, sizeof cmd, "ffprobe -v error -show_streams -show_frames -read_intervals '%%+#1' '%s'", path);
            FILE *p = popen(cmd, "r");
            CHECK(p, "ffprobe");
            size_t n = fread(text, 1, sizeof text - 1, p);
            text[n] = 0;
            pclose(p);
            char want_w[32], want_h[32], want_mode[64], want_type[64];
            snprintf(want_w, sizeof want_w, "\nwidth=%d\n", cases[c].w);
            snprintf(want_h, sizeof want_h, "\nheight=%d\n", cases[c].h);
            snprintf(want_mode, sizeof want_mode, "stereo_mode=%s", cases[c].mode);
            snprintf(want_type, sizeof want_type, "\ntype=%s\n", cases[c].type);
            bool sized = strstr(text, want_w) && strstr(text, want_h), mode = strstr(text, want_mode) != NULL;
            bool track = !k || strstr(text, want_type);
            printf("%s.%s: %dx%d %s, ffprobe: %s%s\n", cases[c].file, k ? "mkv" : "mp4", cases[c].w, cases[c].h,
                   sized ? "ok" : "WRONG", mode ? want_mode : "no stereo_mode",
                   k ? (track ? ", the track's Stereo 3D side data" : ", no Stereo 3D side data") : "");
            CHECK(sized && mode && track, "%s: ffprobe says\n%s", path, text);
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 2)
        g_exe = argv[2];
    if (argc > 3)
        snprintf(g_work, sizeof g_work, "%s", argv[3]);
    static const vg_test_case cases[] = {
        {"synthetic_sequence", synthetic_sequence},
        {"operator_none_keeps_g", operator_none_keeps_g},
        {"given_h_identity", given_h_identity},
        {"saliency_input", saliency_input},
        {"bad_inputs", bad_inputs},
        {"bad_patterns", bad_patterns},
        {"third_party", third_party},
        {"stereo_video", stereo_video},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
