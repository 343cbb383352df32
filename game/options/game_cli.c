/* vergence — shared command-line pieces of `play` and `study`. */
#include "game_cli.h"

#include <libgen.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"

const char *game_scene_path(const char *given, char *buf, size_t cap)
{
    if (given)
        return given;
    if (access("content/arena.gltf", R_OK) == 0)
        return "content/arena.gltf";
    /* <checkout>/build-X/game/vergence -> <checkout>/content/arena.gltf */
    char exe[1024];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        exe[n] = '\0';
        char *dir = dirname(exe);
        snprintf(buf, cap, "%s/../../content/arena.gltf", dir);
        if (access(buf, R_OK) == 0)
            return buf;
    }
    vg_error("cannot find content/arena.gltf (run from the checkout or give --scene FILE)");
    return NULL;
}
