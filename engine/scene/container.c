/* vergence — checks on raw bytes before and after tinygltf: the GLB
 * container, JSON nesting depth and node transforms, and base-colour image
 * decoding.
 *
 * tinygltf 2.7.0 trusts a GLB's chunk lengths (a BIN chunk may end 8 bytes
 * past the file), copies JSON extras recursively (deep nesting overflows the
 * stack), and lets stb allocate whatever an image header claims; these
 * functions keep such inputs away from it (and PNG textures away from stb). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image.h>

#include "core/io.h"
#include "core/json_read.h"
#include "core/log.h"
#include "scene_internal.h"

static uint32_t read_u32(const uint8_t *p)
{
    uint32_t v;
    memcpy(&v, p, 4);
    return v; /* GLB is little-endian, like every host we build for */
}

/* GLB layout (glTF 2.0 spec 4.4, "Binary glTF layout"): a 12-byte header
 * (magic, version, length), then chunks of (length, type, data), the JSON
 * chunk first. */
bool scene_glb_check(const uint8_t *b, size_t size, scene_err *e, uint32_t *length, const uint8_t **json,
                     size_t *json_size)
{
    if (size < 20)
        return scene_fail(e, VG_ERR_FORMAT, "truncated glTF-Binary: %zu bytes, the headers alone need 20", size);
    uint32_t version = read_u32(b + 4), len = read_u32(b + 8);
    if (version != 2)
        return scene_fail(e, VG_ERR_UNSUPPORTED, "glTF-Binary version %u (only 2 is supported)", version);
    if (len > size)
        return scene_fail(e, VG_ERR_FORMAT, "truncated glTF-Binary: its header says %u bytes, the file has %zu",
                          len, size);
    if (len < 20)
        return scene_fail(e, VG_ERR_FORMAT, "glTF-Binary header length %u is too small", len);
    size_t at = 12;
    int chunk = 0;
    while (at < len) {
        if (len - at < 8)
            return scene_fail(e, VG_ERR_FORMAT, "truncated glTF-Binary: the header of chunk %d is cut off", chunk);
        uint32_t clen = read_u32(b + at), ctype = read_u32(b + at + 4);
        if (clen > len - at - 8)
            return scene_fail(e, VG_ERR_FORMAT, "truncated glTF-Binary: chunk %d declares %u bytes, %zu remain",
                              chunk, clen, (size_t)(len - at - 8));
        if (chunk == 0) {
            if (ctype != 0x4E4F534Au || clen == 0) /* "JSON" */
                return scene_fail(e, VG_ERR_FORMAT, "glTF-Binary does not start with a JSON chunk");
            *json = b + at + 8;
            *json_size = clen;
        }
        at += 8 + (size_t)clen;
        chunk++;
    }
    if (chunk == 0)
        return scene_fail(e, VG_ERR_FORMAT, "glTF-Binary has no JSON chunk");
    *length = len;
    return true;
}

static bool json_depth_check(const uint8_t *s, size_t n, scene_err *e)
{
    const int max_depth = 64;
    int depth = 0;
    bool in_string = false;
    for (size_t i = 0; i < n; i++) {
        uint8_t c = s[i];
        if (in_string) {
            if (c == '\\')
                i++;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > max_depth)
                return scene_fail(e, VG_ERR_FORMAT, "JSON nested deeper than %d levels", max_depth);
        } else if (c == ']' || c == '}') {
            depth--;
        }
    }
    return true;
}

/* glTF 2.0 spec 5.25: a node has a matrix or TRS properties, not both. */
static bool json_nodes_check(const uint8_t *s, size_t n, scene_err *e)
{
    vg_jdoc doc = {0};
    bool silent = vg_log_set_silent(true);
    vg_status st = vg_json_parse("glTF", (const char *)s, n, &doc);
    vg_log_set_silent(silent);
    if (st != VG_OK)
        return true; /* tinygltf reports the syntax */
    const vg_jvalue *nodes = vg_jget(doc.root, "nodes");
    bool ok = true;
    for (size_t i = 0; ok && nodes && nodes->type == VG_JARRAY && i < nodes->count; i++) {
        const vg_jvalue *nd = vg_jat(nodes, i);
        if (vg_jget(nd, "matrix") &&
            (vg_jget(nd, "translation") || vg_jget(nd, "rotation") || vg_jget(nd, "scale")))
            ok = scene_fail(e, VG_ERR_FORMAT, "node %zu has both a matrix and translation/rotation/scale (glTF: one "
                            "or the other)", i);
    }
    vg_jdoc_free(&doc);
    return ok;
}

bool scene_json_check(const uint8_t *s, size_t n, scene_err *e)
{
    return json_depth_check(s, n, e) && json_nodes_check(s, n, e);
}

bool scene_texture_decode(const uint8_t *bytes, size_t size, scene_texture *out, char *why, size_t cap)
{
    int w = 0, h = 0, comp = 0;
    if (!bytes || size == 0 || size > 0x7fffffff) {
        snprintf(why, cap, "no image data");
        return false;
    }
    /* PNG through core's libpng decoder (stb inflates a truncated stream
     * to 2 GiB); JPEG through stb, its dimensions first so that a lying
     * header never reaches the allocator. */
    if (size >= 8 && !memcmp(bytes, "\x89PNG\r\n\x1a\n", 8)) {
        vg_png_image img = {.comp = 0};
        if (!vg_png_decode(bytes, size, &img, why, cap))
            return false;
        if ((long long)img.width * img.height > SCENE_MAX_TEXTURE_PIXELS) {
            snprintf(why, cap, "%dx%d pixels is outside 1..%d pixels", img.width, img.height, SCENE_MAX_TEXTURE_PIXELS);
            return false;
        }
        img.comp = 4;
        img.bits = 8;
        if (!vg_png_decode(bytes, size, &img, why, cap))
            return false;
        out->rgba = img.pixels;
        out->width = img.width;
        out->height = img.height;
        return true;
    }
    if (!stbi_info_from_memory(bytes, (int)size, &w, &h, &comp)) {
        snprintf(why, cap, "stb cannot decode it (%s)", stbi_failure_reason());
        return false;
    }
    if (w <= 0 || h <= 0 || (long long)w * h > SCENE_MAX_TEXTURE_PIXELS) {
        snprintf(why, cap, "%dx%d pixels is outside 1..%d pixels", w, h, SCENE_MAX_TEXTURE_PIXELS);
        return false;
    }
    /* Grey and RGB are expanded to RGBA (req_comp 4). */
    uint8_t *px = stbi_load_from_memory(bytes, (int)size, &w, &h, &comp, 4);
    if (!px) {
        snprintf(why, cap, "stb cannot decode it (%s)", stbi_failure_reason());
        return false;
    }
    size_t n = (size_t)w * (size_t)h * 4;
    out->rgba = malloc(n);
    if (!out->rgba) {
        stbi_image_free(px);
        snprintf(why, cap, "out of memory for %dx%d pixels", w, h);
        return false;
    }
    memcpy(out->rgba, px, n);
    stbi_image_free(px);
    out->width = w;
    out->height = h;
    return true;
}
