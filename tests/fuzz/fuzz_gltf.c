/* glTF loading: the tinygltf wrapper and everything after it up to GPU
 * upload (scene_load takes a path: the input goes through a temporary file),
 * then evaluation at a few times and the camera. */
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "core/io.h"
#include "core/log.h"
#include "fuzz.h"
#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vg_log_set_silent(true);
    static char path[512];
    if (!path[0]) { /* in the test's own TMPDIR (tests/tmpdir.sh), which goes with it */
        const char *tmp = getenv("TMPDIR");
        snprintf(path, sizeof path, "%s/vergence_fuzz_%ld.gltf", tmp && *tmp ? tmp : "/tmp", (long)getpid());
    }
    if (vg_file_write_atomic(path, data, size) != VG_OK)
        return 0;
    scene *s;
    if (scene_load(path, &s) == VG_OK) {
        scene_state st;
        if (scene_state_init(s, &st) == VG_OK) {
            const float times[] = {0.0f, 0.37f, s->duration, s->duration + 1.0f, -1.0f};
            for (int i = 0; i < 5; i++) {
                scene_evaluate(s, times[i], &st);
                vg_camera cam;
                scene_camera_resolve(s, &st, 0, 16.0f / 9.0f, &cam);
            }
            scene_state_free(&st);
        }
        scene_destroy(s);
    }
    return 0;
}
