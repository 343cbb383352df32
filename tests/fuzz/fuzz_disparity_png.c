/* Disparity PNGs of stereo datasets (KITTI 16-bit grey, Sintel 8-bit RGB):
 * vg_disparity_png_parse on any bytes. */
#include "core/io.h"
#include "core/log.h"
#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vg_log_set_silent(true);
    vg_imagef img;
    const char *encoding = NULL;
    if (vg_disparity_png_parse("fuzz.png", data, size, &img, &encoding) == VG_OK) {
        volatile float sink = 0;
        for (int i = 0; i < img.width * img.height; i += 97)
            sink += img.data[i];
        (void)sink;
    }
    vg_imagef_free(&img);
    return 0;
}
