/* Middlebury .flo reader: vg_flo_parse on any bytes. */
#include "core/io.h"
#include "core/log.h"
#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vg_log_set_silent(true);
    vg_imagef img;
    if (vg_flo_parse("fuzz.flo", data, size, &img) == VG_OK) {
        volatile float sink = 0;
        for (int i = 0; i < img.width * img.height * 2; i += 97)
            sink += img.data[i];
        (void)sink;
    }
    vg_imagef_free(&img);
    return 0;
}
