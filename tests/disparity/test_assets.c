/* Third-party stereo fixtures (../shared/assets/stereo): read with the right
 * sizes and value ranges; truncated or garbled copies give one clear error
 * each. Run one case: test_assets NAME [WORKDIR]. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../test.h"
#include "core/io.h"
#include "core/log.h"

#define FT3D "../shared/assets/stereo/flyingthings3d_pair_from_RAFT-3D/"
#define SINTEL "../shared/assets/stereo/sintel_alley_2_flow_from_faldoi/gt/frame_0002.flo"

static const char *g_work = "build/test-assets";

static int ft3d_disparity(void)
{
    const char *names[] = {FT3D "disp1.pfm", FT3D "disp2.pfm"};
    for (int f = 0; f < 2; f++) {
        vg_imagef img;
        CHECK(vg_pfm_read(names[f], &img) == VG_OK, "%s", names[f]);
        double lo = 1e30, hi = -1e30, mean = 0;
        int n = img.width * img.height;
        for (int i = 0; i < n; i++) {
            lo = fmin(lo, img.data[i]);
            hi = fmax(hi, img.data[i]);
            mean += img.data[i] / n;
        }
        printf("%s: %dx%d, %d channel(s), disparity %.3f .. %.3f px (mean %.2f)\n", names[f], img.width,
               img.height, img.channels, lo, hi, mean);
        CHECK(img.width == 960 && img.height == 540 && img.channels == 1, "size %dx%dx%d", img.width, img.height, img.channels);
        CHECK(lo > 0.5 && lo < 2.0 && hi > 100 && hi < 120, "range %.3f .. %.3f px (README: about 1.1 .. 109)", lo, hi);
        vg_imagef_free(&img);
    }
    return 0;
}

static int sintel_flow(void)
{
    vg_imagef img;
    CHECK(vg_flo_read(SINTEL, &img) == VG_OK, "read");
    int n = img.width * img.height;
    double mag_max = 0, mag_mean = 0, u_mean = 0;
    for (int i = 0; i < n; i++) {
        double u = img.data[2 * i], v = img.data[2 * i + 1];
        CHECK(isfinite(u) && isfinite(v), "non-finite flow at %d", i);
        double m = sqrt(u * u + v * v);
        mag_max = fmax(mag_max, m);
        mag_mean += m / n;
        u_mean += u / n;
    }
    printf("%s: %dx%d, %d channels, |flow| mean %.3f max %.3f px, mean u %.3f px\n", SINTEL, img.width,
           img.height, img.channels, mag_mean, mag_max, u_mean);
    CHECK(img.width == 1024 && img.height == 436 && img.channels == 2, "size %dx%dx%d", img.width, img.height, img.channels);
    CHECK(mag_mean > 0.1 && mag_max < 200, "flow magnitudes out of the plausible range");
    vg_imagef_free(&img);
    return 0;
}

/* Writes a corrupted copy of src: the first `keep` bytes, with `patch`
 * written over the start when given. */
static int corrupt_copy(const char *src, const char *dst, size_t keep, const char *patch)
{
    uint8_t *data;
    size_t size;
    if (vg_file_read(src, &data, &size) != VG_OK)
        return 1;
    if (keep > size)
        keep = size;
    if (patch)
        memcpy(data, patch, strlen(patch));
    vg_status st = vg_file_write_atomic(dst, data, keep);
    free(data);
    return st != VG_OK;
}

typedef vg_status (*reader_fn)(const char *, vg_imagef *);

static int one_error(reader_fn read, const char *path, const char *what)
{
    int before = vg_log_error_count();
    vg_imagef img;
    vg_status st = read(path, &img);
    int lines = vg_log_error_count() - before;
    printf("%s: status %d (%s), %d error line(s)\n", what, st, vg_status_text(st), lines);
    CHECK(st == VG_ERR_FORMAT, "%s must fail as malformed input, got %d", what, st);
    CHECK(lines == 1, "%s logged %d error lines, expected exactly one", what, lines);
    CHECK(img.data == NULL, "no image on failure");
    return 0;
}

static int corrupted_files(void)
{
    char a[512], b[512], c[512], d[512], e[512];
    mkdir(g_work, 0755);
    snprintf(a, sizeof a, "%s/truncated.pfm", g_work);
    snprintf(b, sizeof b, "%s/garbled.pfm", g_work);
    snprintf(c, sizeof c, "%s/bad_header.pfm", g_work);
    snprintf(d, sizeof d, "%s/truncated.flo", g_work);
    snprintf(e, sizeof e, "%s/garbled.flo", g_work);
    CHECK(!corrupt_copy(FT3D "disp1.pfm", a, 1000000, NULL), "write %s", a);
    CHECK(!corrupt_copy(FT3D "disp1.pfm", b, 100000, "P7"), "write %s", b);
    CHECK(!corrupt_copy(FT3D "disp1.pfm", c, 100000, "Pf\nx60 540\n"), "write %s", c);
    CHECK(!corrupt_copy(SINTEL, d, 2000000, NULL), "write %s", d);
    CHECK(!corrupt_copy(SINTEL, e, 100000, "HEIP"), "write %s", e); /* the magic is "PIEH" */
    if (one_error(vg_pfm_read, a, "truncated PFM") || one_error(vg_pfm_read, b, "garbled PFM magic") ||
        one_error(vg_pfm_read, c, "garbled PFM header") || one_error(vg_flo_read, d, "truncated .flo") ||
        one_error(vg_flo_read, e, "garbled .flo magic"))
        return 1;
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 2)
        g_work = argv[2];
    static const vg_test_case cases[] = {
        {"ft3d_disparity", ft3d_disparity},
        {"sintel_flow", sintel_flow},
        {"corrupted_files", corrupted_files},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
