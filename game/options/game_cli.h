/* vergence — command-line pieces shared by `play` and `study`: finding the
 * arena (the display: display_cli.h, shared by every command). */
#pragma once
#include <stddef.h>

#include "core/cli.h"
#include "disparity/disp_operator.h"
#include "display_cli.h"

/* The scene to play in: `given`, else content/arena.gltf in the working
 * folder or beside the executable's build tree. Returns NULL (with one
 * error line) when none is found. */
const char *game_scene_path(const char *given, char *buf, size_t cap);
