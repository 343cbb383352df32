#include "json.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io.h"
#include "log.h"

static void put(vg_json *j, const char *s, size_t n)
{
    if (j->failed)
        return;
    if (j->len + n + 1 > j->cap) {
        size_t cap = j->cap ? j->cap * 2 : 4096;
        while (cap < j->len + n + 1)
            cap *= 2;
        char *p = realloc(j->buf, cap);
        if (!p) {
            j->failed = true;
            return;
        }
        j->buf = p;
        j->cap = cap;
    }
    memcpy(j->buf + j->len, s, n);
    j->len += n;
    j->buf[j->len] = 0;
}

static void putf(vg_json *j, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void putf(vg_json *j, const char *fmt, ...)
{
    char tmp[64];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    put(j, tmp, (size_t)n < sizeof tmp ? (size_t)n : sizeof tmp - 1);
}

static void put_string(vg_json *j, const char *s)
{
    put(j, "\"", 1);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') {
            char e[2] = {'\\', (char)c};
            put(j, e, 2);
        } else if (c < 0x20) {
            putf(j, "\\u%04x", c);
        } else {
            put(j, (const char *)&c, 1);
        }
    }
    put(j, "\"", 1);
}

static void newline(vg_json *j)
{
    if (j->compact)
        return;
    put(j, "\n", 1);
    for (int i = 0; i < j->depth; i++)
        put(j, "  ", 2);
}

/* Comma, newline, indentation and key before a value. */
static void member(vg_json *j, const char *key)
{
    if (j->depth > 0) {
        if (j->has_items[j->depth - 1])
            put(j, ",", 1);
        j->has_items[j->depth - 1] = true;
        newline(j);
    }
    if (key) {
        put_string(j, key);
        put(j, j->compact ? ":" : ": ", j->compact ? 1 : 2);
    }
}

static void open_container(vg_json *j, const char *key, const char *bracket)
{
    member(j, key);
    put(j, bracket, 1);
    if (j->depth >= VG_JSON_MAX_DEPTH) {
        j->failed = true;
        return;
    }
    j->has_items[j->depth++] = false;
}

static void close_container(vg_json *j, const char *bracket)
{
    if (j->depth <= 0) {
        j->failed = true;
        return;
    }
    bool had = j->has_items[--j->depth];
    if (had)
        newline(j);
    put(j, bracket, 1);
    if (j->depth == 0 && !j->compact)
        put(j, "\n", 1);
}

void vg_json_object_begin(vg_json *j, const char *key) { open_container(j, key, "{"); }
void vg_json_object_end(vg_json *j) { close_container(j, "}"); }
void vg_json_array_begin(vg_json *j, const char *key) { open_container(j, key, "["); }
void vg_json_array_end(vg_json *j) { close_container(j, "]"); }

static void put_num(vg_json *j, double v)
{
    if (!isfinite(v))
        put(j, "null", 4);
    else if (v == floor(v) && fabs(v) < 1e15)
        putf(j, "%.0f", v == 0 ? 0.0 : v); /* no "-0" */
    else
        putf(j, "%.9g", v);
}

void vg_json_num(vg_json *j, const char *key, double v)
{
    member(j, key);
    put_num(j, v);
}

void vg_json_int(vg_json *j, const char *key, long long v)
{
    member(j, key);
    putf(j, "%lld", v);
}

void vg_json_str(vg_json *j, const char *key, const char *s)
{
    member(j, key);
    put_string(j, s ? s : "");
}

void vg_json_bool(vg_json *j, const char *key, bool v)
{
    member(j, key);
    put(j, v ? "true" : "false", v ? 4 : 5);
}

void vg_json_nums(vg_json *j, const char *key, const float *v, int n)
{
    member(j, key);
    put(j, "[", 1);
    for (int i = 0; i < n; i++) {
        if (i)
            put(j, j->compact ? "," : ", ", j->compact ? 1 : 2);
        put_num(j, v[i]);
    }
    put(j, "]", 1);
}

vg_status vg_json_write_file(vg_json *j, const char *path)
{
    if (j->failed || j->depth != 0) {
        vg_error("%s: JSON document is incomplete or out of memory", path);
        return VG_ERR_NOMEM;
    }
    return vg_file_write_atomic(path, j->buf, j->len);
}

void vg_json_free(vg_json *j)
{
    if (!j)
        return;
    free(j->buf);
    *j = (vg_json){0};
}
