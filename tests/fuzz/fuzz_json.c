/* JSON reader (capture.json for bake-curve): parse, walk, look up paths. */
#include "core/json_read.h"
#include "core/log.h"
#include "fuzz.h"

static double walk(const vg_jvalue *v, int depth)
{
    double sum = 0;
    for (const vg_jvalue *c = v->child; c && depth < 100; c = c->next)
        sum += c->number + walk(c, depth + 1);
    return sum;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vg_log_set_silent(true);
    vg_jdoc doc;
    if (vg_json_parse("fuzz.json", (const char *)data, size, &doc) == VG_OK) {
        volatile double sink = walk(doc.root, 0);
        sink += vg_jnum(doc.root, "camera.zfar", 0);
        const vg_jvalue *frames = vg_jpath(doc.root, "camera.frames");
        if (frames && frames->count)
            sink += vg_jnum(vg_jat(frames, frames->count - 1), "time", 0);
        (void)sink;
    }
    vg_jdoc_free(&doc);
    return 0;
}
