/* vergence content — procedural ground textures, encoded as PNG in memory.
 *
 * Every texture tiles seamlessly (periodic value noise on an integer hash),
 * so a small image repeats over a large ground without visible seams. Pixels
 * are sRGB bytes, as glTF expects of base-colour textures. */
#pragma once
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/status.h"

typedef struct texture {
    int width, height;
    uint8_t *rgb; /* width * height * 3, top row first */
} texture;

typedef enum texture_kind {
    TEXTURE_DEFAULT = 0, /* = grass */
    TEXTURE_GRASS,       /* mottled meadow green */
    TEXTURE_CHECKER,     /* soft two-tone paving, 2 x 2 squares per tile */
    TEXTURE_FIELD,       /* sports-field green with a 1 m grid and bold tile edges */
} texture_kind;

/* Makes a size x size texture (size a power of two). */
vg_status texture_make(texture *t, texture_kind kind, int size);
void texture_free(texture *t);

