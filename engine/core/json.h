/* vergence — a small streaming JSON writer with stable formatting.
 *
 * Output is byte-for-byte reproducible: two-space indentation, numbers as
 * %.9g (shortest form that round-trips a float), non-finite numbers as null.
 * A key is given for members of an object and NULL for array elements. */
#pragma once
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "status.h"

#define VG_JSON_MAX_DEPTH 32

typedef struct vg_json {
    char *buf;
    size_t len, cap;
    int depth;
    bool compact;                       /* no newlines or indentation */
    bool has_items[VG_JSON_MAX_DEPTH];  /* per open container: emit a comma first */
    bool failed;
} vg_json;

void vg_json_object_begin(vg_json *j, const char *key);
void vg_json_object_end(vg_json *j);
void vg_json_array_begin(vg_json *j, const char *key);
void vg_json_array_end(vg_json *j);
void vg_json_num(vg_json *j, const char *key, double v);
void vg_json_int(vg_json *j, const char *key, long long v);
void vg_json_str(vg_json *j, const char *key, const char *s);
void vg_json_bool(vg_json *j, const char *key, bool v);
/* Array of numbers on one line (matrices, vectors). */
void vg_json_nums(vg_json *j, const char *key, const float *v, int n);

vg_status vg_json_write_file(vg_json *j, const char *path);
void vg_json_free(vg_json *j);
