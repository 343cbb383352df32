/* engine/footage: OpenEXR and HDF5 depth and disparity files, read back
 * exactly, refused with one error line when broken; and `vergence
 * optimize` on a g sequence as OpenEXR equal to the same as PFM, and on a
 * Spring-style .dsp5 sequence read as pixel disparity. Run one case:
 *   test_footage NAME [VERGENCE_EXECUTABLE WORKDIR] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include <hdf5.h>

#include "../test.h"
#include "core/io.h"
#include "footage/footage.h"

static const char *g_exe = "build/game/vergence";
static const char *g_work = "build/test-footage";

/* An image with the values files hold: negative, zero, large, NaN, inf. */
static int sample(vg_imagef *img, int w, int h)
{
    CHECK(vg_imagef_alloc(img, w, h, 1) == VG_OK, "alloc");
    for (int i = 0; i < w * h; i++)
        img->data[i] = (float)(i % 7) * 0.37f - 1.0f + (float)(i / w) * 1000.0f;
    img->data[3] = NAN;
    img->data[5] = INFINITY;
    img->data[6] = 0.0f;
    return 0;
}

static bool same(const vg_imagef *a, const vg_imagef *b)
{
    if (a->width != b->width || a->height != b->height || a->channels != b->channels)
        return false;
    for (int i = 0; i < a->width * a->height; i++)
        if (!(a->data[i] == b->data[i] || (isnan(a->data[i]) && isnan(b->data[i]))))
            return false;
    return true;
}

static void path_in(char *out, size_t cap, const char *name)
{
    snprintf(out, cap, "%s/%s", g_work, name);
}

/* A 2-D float dataset per name, written with libhdf5 as Spring's files are. */
static int write_h5(const char *path, const char *const *names, int count, const vg_imagef *img)
{
    hid_t f = H5Fcreate(path, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    CHECK(f >= 0, "%s: H5Fcreate", path);
    hsize_t dims[2] = {(hsize_t)img->height, (hsize_t)img->width};
    for (int k = 0; k < count; k++) {
        hid_t space = H5Screate_simple(2, dims, NULL);
        hid_t set = H5Dcreate2(f, names[k], H5T_IEEE_F32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        CHECK(set >= 0 && H5Dwrite(set, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, img->data) >= 0, "%s: %s",
              path, names[k]);
        H5Dclose(set);
        H5Sclose(space);
    }
    H5Fclose(f);
    return 0;
}

/* A copy of the first `keep` bytes of a file. */
static int truncated(const char *from, const char *to, double keep)
{
    uint8_t *b;
    size_t n;
    CHECK(vg_file_read(from, &b, &n) == VG_OK, "%s", from);
    vg_status st = vg_file_write_atomic(to, b, (size_t)(n * keep));
    free(b);
    CHECK(st == VG_OK, "%s", to);
    return 0;
}

/* A reader's refusals, each with nothing read: the file `good` cut at
 * `keep` of its length (a format error), text, a missing file (I/O). */
typedef vg_status (*footage_reader)(const char *path, const char *name, vg_imagef *out);
static int refusals(footage_reader read, const char *good, const char *kind, double keep)
{
    char q[1200], name[64];
    vg_imagef b = {0};
    snprintf(name, sizeof name, "cut.%s", kind);
    path_in(q, sizeof q, name);
    if (truncated(good, q, keep))
        return 1;
    CHECK(read(q, NULL, &b) == VG_ERR_FORMAT && !b.data, "a truncated %s file was read", kind);
    snprintf(name, sizeof name, "text.%s", kind);
    path_in(q, sizeof q, name);
    CHECK(vg_file_write_atomic(q, "not an image\n", 13) == VG_OK, "%s", q);
    CHECK(read(q, NULL, &b) == VG_ERR_FORMAT && !b.data, "text read as %s", kind);
    snprintf(name, sizeof name, "missing.%s", kind);
    path_in(q, sizeof q, name);
    CHECK(read(q, NULL, &b) == VG_ERR_IO, "a missing %s file is not an I/O error", kind);
    return 0;
}

static int exr(void)
{
    CHECK(vg_dir_prepare(g_work) == VG_OK, "%s", g_work);
    char p[1200], q[1200];
    vg_imagef a, b = {0};
    if (sample(&a, 37, 21))
        return 1;
    /* Each channel name the reader looks for, and one it takes as the only one. */
    static const char *const names[] = {"Z", "depth", "disparity", "Y", "R", "A"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++) {
        path_in(p, sizeof p, "a.exr");
        CHECK(footage_exr_write(p, names[k], &a) == VG_OK, "write %s", names[k]);
        CHECK(footage_exr_read(p, NULL, &b) == VG_OK && same(&a, &b), "channel %s not read back exactly", names[k]);
        vg_imagef_free(&b);
    }
    printf("OpenEXR: a 37x21 float channel read back exactly under each name (NaN, inf, 0 kept)\n");
    /* Refused, one line each: another channel asked for, a cut file, not EXR, missing. */
    CHECK(footage_exr_read(p, "Z", &b) == VG_ERR_FORMAT && !b.data, "a missing channel was read");
    path_in(q, sizeof q, "header.exr");
    if (truncated(p, q, 0.05))
        return 1;
    CHECK(footage_exr_read(q, NULL, &b) != VG_OK && !b.data, "an EXR cut in its header was read");
    if (refusals(footage_exr_read, p, "exr", 0.6))
        return 1;
    vg_imagef_free(&a);
    return 0;
}

static int hdf5(void)
{
    CHECK(vg_dir_prepare(g_work) == VG_OK, "%s", g_work);
    char p[1200], q[1200];
    vg_imagef a, b = {0};
    if (sample(&a, 33, 19))
        return 1;
    static const char *const spring[] = {"disparity"}, *const two[] = {"left", "right"}, *const one[] = {"d"};
    path_in(p, sizeof p, "a.dsp5");
    if (write_h5(p, spring, 1, &a))
        return 1;
    CHECK(footage_is_spring(p) && footage_is_hdf5(p), "%s is not Spring's", p);
    CHECK(footage_hdf5_read(p, NULL, &b) == VG_OK && same(&a, &b), "Spring's disparity not read back exactly");
    vg_imagef_free(&b);
    path_in(q, sizeof q, "one.h5");
    if (write_h5(q, one, 1, &a))
        return 1;
    CHECK(footage_hdf5_read(q, NULL, &b) == VG_OK && same(&a, &b), "the only dataset not read");
    vg_imagef_free(&b);
    printf("HDF5: a 33x19 float dataset read back exactly (\"disparity\", or the only one)\n");
    path_in(q, sizeof q, "two.h5");
    if (write_h5(q, two, 2, &a))
        return 1;
    CHECK(footage_hdf5_read(q, NULL, &b) == VG_ERR_FORMAT && !b.data, "two datasets: one was guessed");
    if (refusals(footage_hdf5_read, p, "h5", 0.5))
        return 1;
    vg_imagef_free(&a);
    return 0;
}

/* ------------------------------------------------------------------------- */
/* vergence optimize on them                                                 */
/* ------------------------------------------------------------------------- */

#define W 64
#define H 36
#define FRAMES 21

static int optimize(const char *args, const char *out)
{
    char cmd[16384], path[1300];
    snprintf(path, sizeof path, "%s/stderr.txt", g_work);
    snprintf(cmd, sizeof cmd, "'%s' optimize %s --frames 0:%d --flow none --no-video --threads 2 --out '%s' 2> '%s'",
             g_exe, args, FRAMES - 1, out, path);
    int rc = system(cmd);
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : 128;
}

static char *slurp(const char *path)
{
    uint8_t *b = NULL;
    size_t n;
    char *text = NULL;
    if (vg_file_read(path, &b, &n) == VG_OK)
        text = (char *)b;
    return text;
}

static int optimize_files(void)
{
    CHECK(vg_dir_prepare(g_work) == VG_OK, "%s", g_work);
    vg_imagef g, px;
    CHECK(vg_imagef_alloc(&g, W, H, 1) == VG_OK && vg_imagef_alloc(&px, W, H, 1) == VG_OK, "alloc");
    static const char *const spring[] = {"disparity"};
    for (int t = 0; t < FRAMES; t++) {
        /* A surface coming nearer, faster and faster: motion in depth. */
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                g.data[y * W + x] = 300.0f + 2.0f * (float)x + 0.05f * (float)(t * t) * (x > W / 2);
                px.data[y * W + x] = 5.0f + 0.1f * (float)x + 0.01f * (float)(t * t) * (x > W / 2);
            }
        px.data[0] = NAN; /* Spring's unknown */
        char p[1300];
        snprintf(p, sizeof p, "%s/g_%04d.pfm", g_work, t);
        CHECK(vg_pfm_write(p, &g) == VG_OK, "%s", p);
        snprintf(p, sizeof p, "%s/g_%04d.exr", g_work, t);
        CHECK(footage_exr_write(p, "disparity", &g) == VG_OK, "%s", p);
        snprintf(p, sizeof p, "%s/d_%04d.dsp5", g_work, t);
        if (write_h5(p, spring, 1, &px))
            return 1;
    }
    char args[4096], out[3][1300], path[1400];
    static const char *const kinds[3] = {"pfm", "exr", "dsp5"};
    for (int k = 0; k < 3; k++) {
        snprintf(out[k], sizeof out[k], "%s/out_%s", g_work, kinds[k]);
        snprintf(args, sizeof args, "--g '%s/%s_%%04d.%s'", g_work, k == 2 ? "d" : "g", kinds[k]);
        CHECK(optimize(args, out[k]) == 0, "optimize on %s failed", kinds[k]);
    }
    /* OpenEXR and PFM: the same g, the same f to the bit. */
    for (int t = 0; t < FRAMES; t += 10) {
        char a[1400], b[1400];
        snprintf(a, sizeof a, "%s/f_%04d.pfm", out[0], t);
        snprintf(b, sizeof b, "%s/f_%04d.pfm", out[1], t);
        vg_imagef fa, fb;
        CHECK(vg_pfm_read(a, &fa) == VG_OK && vg_pfm_read(b, &fb) == VG_OK, "f of frame %d", t);
        CHECK(same(&fa, &fb), "frame %d: f from OpenEXR differs from f from PFM", t);
        vg_imagef_free(&fa);
        vg_imagef_free(&fb);
    }
    for (int k = 1; k < 3; k++) {
        snprintf(path, sizeof path, "%s/metrics.json", out[k]);
        char *m = slurp(path);
        CHECK(m, "%s", path);
        bool ok = k == 1 ? strstr(m, "\"g_file\": \"OpenEXR\"") && strstr(m, "\"g_units\": \"arcmin\"")
                         : strstr(m, "\"g_file\": \"Spring\"") && strstr(m, "\"g_units\": \"px\"");
        free(m);
        CHECK(ok, "%s: g_file / g_units wrong", path);
    }
    printf("optimize: g as OpenEXR gives f equal to g as PFM; Spring's .dsp5 read as pixels, its NaN unknown\n");
    /* A broken frame stops the run with one line naming it, nothing written. */
    char p[1300];
    snprintf(p, sizeof p, "%s/g_%04d.exr", g_work, 7);
    CHECK(vg_file_write_atomic(p, "garbage", 7) == VG_OK, "%s", p);
    snprintf(out[1], sizeof out[1], "%s/out_bad", g_work);
    snprintf(args, sizeof args, "--g '%s/g_%%04d.exr'", g_work);
    int code = optimize(args, out[1]);
    snprintf(path, sizeof path, "%s/stderr.txt", g_work);
    char *err = slurp(path);
    int lines = 0;
    for (const char *e = err; e && (e = strstr(e, "error:")); e++)
        lines++;
    printf("a garbage OpenEXR frame: exit %d, %d error line(s): %s", code, lines, err ? err : "");
    bool named = err && strstr(err, "g_0007.exr");
    free(err);
    snprintf(path, sizeof path, "%s/metrics.json", out[1]);
    CHECK(code == 4 && lines == 1 && named, "a garbage OpenEXR frame: exit %d, %d error lines", code, lines);
    CHECK(!slurp(path), "a failed run wrote %s", path);
    vg_imagef_free(&g);
    vg_imagef_free(&px);
    return 0;
}

/* --operator ema by hand: frame t's g spans [300, 310 + t] arcmin (its
 * range grows by 1 a frame); with a 3-frame window and decay 0.5 the range
 * h maps from is hi_t = 0.5 hi_(t-1) + 0.5 (312 + t) from hi_0 = 312 (the
 * window's max), lo 300 throughout, clipped at the shot's end. */
static int optimize_ema(void)
{
    CHECK(vg_dir_prepare(g_work) == VG_OK, "%s", g_work);
    vg_imagef g;
    CHECK(vg_imagef_alloc(&g, W, H, 1) == VG_OK, "alloc");
    for (int t = 0; t < FRAMES; t++) {
        for (int i = 0; i < W * H; i++)
            g.data[i] = 300.0f + (10.0f + (float)t) * (float)(i % W) / (float)(W - 1);
        char p[1300];
        snprintf(p, sizeof p, "%s/g_%04d.pfm", g_work, t);
        CHECK(vg_pfm_write(p, &g) == VG_OK, "%s", p);
    }
    vg_imagef_free(&g);
    char args[4096], out[1300], path[1400];
    snprintf(out, sizeof out, "%s/out_ema", g_work);
    snprintf(args, sizeof args, "--g '%s/g_%%04d.pfm' --operator ema --ema-window 3 --ema-decay 0.5", g_work);
    CHECK(optimize(args, out) == 0, "optimize --operator ema failed");
    double hi = 0;
    for (int t = 0; t < FRAMES; t++) {
        double window_max = 310.0 + fmin(t + 2, FRAMES - 1);
        hi = t ? 0.5 * hi + 0.5 * window_max : window_max;
    }
    snprintf(path, sizeof path, "%s/metrics.json", out);
    uint8_t *bytes;
    size_t size;
    CHECK(vg_file_read(path, &bytes, &size) == VG_OK, "%s", path);
    char *m = (char *)bytes;
    const char *first = strstr(m, "\"ema_range_first\": ["), *last = strstr(m, "\"ema_range_last\": [");
    double f0 = first ? strtod(first + 20, NULL) : NAN, f1 = first ? strtod(strchr(first + 20, ',') + 1, NULL) : NAN;
    double l0 = last ? strtod(last + 19, NULL) : NAN, l1 = last ? strtod(strchr(last + 19, ',') + 1, NULL) : NAN;
    bool named = strstr(m, "\"operator\": \"ema\"") != NULL;
    free(m);
    printf("--operator ema: first frame's range [%.4f, %.4f] (want [300, 312]), last [%.4f, %.4f] (want [300, %.4f])\n",
           f0, f1, l0, l1, hi);
    CHECK(named && fabs(f0 - 300) < 1e-3 && fabs(f1 - 312) < 1e-3 && fabs(l0 - 300) < 1e-3 && fabs(l1 - hi) < 1e-3,
          "the EMA's ranges are not iw3's");
    return 0;
}

int main(int argc, char **argv)
{
    static char work[1024];
    const char *tmp = getenv("TMPDIR"); /* the test's own (tests/tmpdir.sh) */
    if (tmp && *tmp) {
        snprintf(work, sizeof work, "%s/footage", tmp);
        g_work = work;
    }
    if (argc > 2)
        g_exe = argv[2];
    if (argc > 3)
        g_work = argv[3];
    static const vg_test_case cases[] = {{"exr", exr}, {"hdf5", hdf5}, {"optimize_files", optimize_files},
                                         {"optimize_ema", optimize_ema}};
    return vg_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0]));
}
