/* vergence — a small JSON reader: parses a document into a tree of values
 * held in one allocation, with lookups by dotted path ("camera.frames").
 *
 * Strict RFC 8259 (no comments, no trailing commas), nesting at most 64
 * deep, strings kept as parsed (escapes decoded, \u limited to the BMP).
 * Errors give one line naming the file, the line and what was expected. */
#pragma once
#include <stdbool.h>
#include <stddef.h>

#include "status.h"

typedef enum vg_jtype {
    VG_JNULL = 0,
    VG_JBOOL,
    VG_JNUMBER,
    VG_JSTRING,
    VG_JARRAY,
    VG_JOBJECT,
} vg_jtype;

typedef struct vg_jvalue vg_jvalue;
struct vg_jvalue {
    vg_jtype type;
    double number;               /* VG_JNUMBER; VG_JBOOL: 0 or 1 */
    const char *string;          /* VG_JSTRING; the member name for object members */
    const char *key;             /* set on members of an object */
    vg_jvalue *child;            /* first element or member */
    vg_jvalue *next;             /* next sibling */
    size_t count;                /* elements or members */
};

typedef struct vg_jdoc {
    vg_jvalue *root;
    void *arena;                 /* owns every value and string */
} vg_jdoc;

/* Parses text (size bytes; need not be NUL-terminated). `name` is used in errors. */
vg_status vg_json_parse(const char *name, const char *text, size_t size, vg_jdoc *out);
vg_status vg_json_read_file(const char *path, vg_jdoc *out);
void vg_jdoc_free(vg_jdoc *doc);

/* Member `key` of an object, NULL when absent or not an object. */
const vg_jvalue *vg_jget(const vg_jvalue *obj, const char *key);
/* Dotted path of object members ("camera.zfar"). */
const vg_jvalue *vg_jpath(const vg_jvalue *root, const char *path);
/* Element i of an array. */
const vg_jvalue *vg_jat(const vg_jvalue *arr, size_t i);
/* Number at a path, or `fallback` when missing or not a number. */
double vg_jnum(const vg_jvalue *root, const char *path, double fallback);
