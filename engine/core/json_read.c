/* vergence — JSON reader (recursive descent into an arena). */
#include "json_read.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "io.h"
#include "log.h"

#define JSON_MAX_DEPTH 64

typedef struct parser {
    const char *name, *p, *end;
    int line;
    char *arena;
    size_t used, cap;
    bool failed;
} parser;

static void *alloc(parser *ps, size_t n)
{
    n = (n + 15) & ~(size_t)15;
    if (ps->used + n > ps->cap) {
        ps->failed = true;
        return NULL;
    }
    void *r = ps->arena + ps->used;
    ps->used += n;
    return r;
}

static vg_status fail(parser *ps, const char *what)
{
    if (!ps->failed)
        vg_error("%s: line %d: %s", ps->name, ps->line, what);
    ps->failed = true;
    return VG_ERR_FORMAT;
}

static void skip_ws(parser *ps)
{
    while (ps->p < ps->end && (*ps->p == ' ' || *ps->p == '\t' || *ps->p == '\n' || *ps->p == '\r')) {
        if (*ps->p == '\n')
            ps->line++;
        ps->p++;
    }
}

static bool literal(parser *ps, const char *word)
{
    size_t n = strlen(word);
    if ((size_t)(ps->end - ps->p) < n || memcmp(ps->p, word, n) != 0)
        return false;
    ps->p += n;
    return true;
}

static void put_utf8(char *out, size_t *k, unsigned c)
{
    if (c < 0x80) {
        out[(*k)++] = (char)c;
    } else if (c < 0x800) {
        out[(*k)++] = (char)(0xc0 | (c >> 6));
        out[(*k)++] = (char)(0x80 | (c & 0x3f));
    } else {
        out[(*k)++] = (char)(0xe0 | (c >> 12));
        out[(*k)++] = (char)(0x80 | ((c >> 6) & 0x3f));
        out[(*k)++] = (char)(0x80 | (c & 0x3f));
    }
}

static const char *parse_string(parser *ps)
{
    ps->p++; /* opening quote */
    const char *start = ps->p;
    while (ps->p < ps->end && *ps->p != '"') {
        if ((unsigned char)*ps->p < 0x20) {
            fail(ps, "control character inside a string");
            return NULL;
        }
        ps->p += *ps->p == '\\' && ps->p + 1 < ps->end ? 2 : 1;
    }
    if (ps->p >= ps->end) {
        fail(ps, "unterminated string");
        return NULL;
    }
    /* Decoded text is never longer than the source. */
    char *out = alloc(ps, (size_t)(ps->p - start) + 1);
    if (!out) {
        fail(ps, "document too large");
        return NULL;
    }
    size_t k = 0;
    for (const char *s = start; s < ps->p; s++) {
        if (*s != '\\') {
            out[k++] = *s;
            continue;
        }
        s++;
        switch (*s) {
        case '"': case '\\': case '/': out[k++] = *s; break;
        case 'b': out[k++] = '\b'; break;
        case 'f': out[k++] = '\f'; break;
        case 'n': out[k++] = '\n'; break;
        case 'r': out[k++] = '\r'; break;
        case 't': out[k++] = '\t'; break;
        case 'u': {
            unsigned c = 0;
            for (int i = 1; i <= 4; i++) {
                char h = s + i < ps->p ? s[i] : 0;
                int v = h >= '0' && h <= '9' ? h - '0' : h >= 'a' && h <= 'f' ? h - 'a' + 10
                                                     : h >= 'A' && h <= 'F' ? h - 'A' + 10 : -1;
                if (v < 0) {
                    fail(ps, "bad \\u escape");
                    return NULL;
                }
                c = c * 16 + (unsigned)v;
            }
            s += 4;
            put_utf8(out, &k, c);
            break;
        }
        default:
            fail(ps, "bad escape in a string");
            return NULL;
        }
    }
    out[k] = 0;
    ps->p++; /* closing quote */
    return out;
}

static vg_jvalue *parse_value(parser *ps, int depth);

static vg_jvalue *parse_container(parser *ps, int depth, bool object)
{
    vg_jvalue *v = alloc(ps, sizeof *v);
    if (!v) {
        fail(ps, "document too large");
        return NULL;
    }
    *v = (vg_jvalue){.type = object ? VG_JOBJECT : VG_JARRAY};
    ps->p++;
    skip_ws(ps);
    char close = object ? '}' : ']';
    if (ps->p < ps->end && *ps->p == close) {
        ps->p++;
        return v;
    }
    vg_jvalue **tail = &v->child;
    for (;;) {
        skip_ws(ps);
        const char *key = NULL;
        if (object) {
            if (ps->p >= ps->end || *ps->p != '"') {
                fail(ps, "expected a member name in quotes");
                return NULL;
            }
            if (!(key = parse_string(ps)))
                return NULL;
            skip_ws(ps);
            if (ps->p >= ps->end || *ps->p != ':') {
                fail(ps, "expected ':' after a member name");
                return NULL;
            }
            ps->p++;
        }
        vg_jvalue *item = parse_value(ps, depth + 1);
        if (!item)
            return NULL;
        item->key = key;
        *tail = item;
        tail = &item->next;
        v->count++;
        skip_ws(ps);
        if (ps->p < ps->end && *ps->p == ',') {
            ps->p++;
            continue;
        }
        if (ps->p < ps->end && *ps->p == close) {
            ps->p++;
            return v;
        }
        fail(ps, object ? "expected ',' or '}'" : "expected ',' or ']'");
        return NULL;
    }
}

static vg_jvalue *parse_value(parser *ps, int depth)
{
    if (depth > JSON_MAX_DEPTH) {
        fail(ps, "nested too deeply");
        return NULL;
    }
    skip_ws(ps);
    if (ps->p >= ps->end) {
        fail(ps, "unexpected end of the document");
        return NULL;
    }
    char c = *ps->p;
    if (c == '{' || c == '[')
        return parse_container(ps, depth, c == '{');
    vg_jvalue *v = alloc(ps, sizeof *v);
    if (!v) {
        fail(ps, "document too large");
        return NULL;
    }
    *v = (vg_jvalue){0};
    if (c == '"') {
        v->type = VG_JSTRING;
        return (v->string = parse_string(ps)) ? v : NULL;
    }
    if (literal(ps, "true") || literal(ps, "false")) {
        v->type = VG_JBOOL;
        v->number = ps->p[-1] == 'e' && ps->p[-2] == 'u';
        return v;
    }
    if (literal(ps, "null"))
        return v;
    if (c == '-' || (c >= '0' && c <= '9')) {
        char buf[64];
        size_t n = 0;
        while (ps->p < ps->end && n < sizeof buf - 1 && strchr("+-.0123456789eE", *ps->p))
            buf[n++] = *ps->p++;
        buf[n] = 0;
        char *end;
        v->type = VG_JNUMBER;
        v->number = strtod(buf, &end);
        if (*end || !isfinite(v->number)) {
            fail(ps, "malformed number");
            return NULL;
        }
        return v;
    }
    fail(ps, "expected a value");
    return NULL;
}

vg_status vg_json_parse(const char *name, const char *text, size_t size, vg_jdoc *out)
{
    *out = (vg_jdoc){0};
    /* A value takes 64 bytes and at least 2 source bytes ("0,"); strings
     * decode no longer than they are written: 34x the source always fits. */
    if (size > ((size_t)1 << 26)) {
        vg_error("%s: JSON document too large (%zu bytes)", name, size);
        return VG_ERR_FORMAT;
    }
    size_t cap = size * 34 + 4096;
    parser ps = {.name = name, .p = text, .end = text + size, .line = 1, .arena = malloc(cap), .cap = cap};
    if (!ps.arena)
        return VG_ERR_NOMEM;
    vg_jvalue *root = parse_value(&ps, 0);
    if (root) {
        skip_ws(&ps);
        if (ps.p != ps.end) {
            fail(&ps, "text after the document");
            root = NULL;
        }
    }
    if (!root) {
        free(ps.arena);
        return VG_ERR_FORMAT;
    }
    out->root = root;
    out->arena = ps.arena;
    return VG_OK;
}

vg_status vg_json_read_file(const char *path, vg_jdoc *out)
{
    uint8_t *data;
    size_t size;
    *out = (vg_jdoc){0};
    vg_status st = vg_file_read(path, &data, &size);
    if (st != VG_OK)
        return st;
    st = vg_json_parse(path, (const char *)data, size, out);
    free(data);
    return st;
}

void vg_jdoc_free(vg_jdoc *doc)
{
    if (!doc)
        return;
    free(doc->arena);
    *doc = (vg_jdoc){0};
}

const vg_jvalue *vg_jget(const vg_jvalue *obj, const char *key)
{
    if (!obj || obj->type != VG_JOBJECT)
        return NULL;
    for (const vg_jvalue *m = obj->child; m; m = m->next)
        if (!strcmp(m->key, key))
            return m;
    return NULL;
}

const vg_jvalue *vg_jpath(const vg_jvalue *root, const char *path)
{
    char key[128];
    const vg_jvalue *v = root;
    while (v && *path) {
        size_t n = strcspn(path, ".");
        if (n >= sizeof key)
            return NULL;
        memcpy(key, path, n);
        key[n] = 0;
        v = vg_jget(v, key);
        path += n + (path[n] == '.');
    }
    return v;
}

const vg_jvalue *vg_jat(const vg_jvalue *arr, size_t i)
{
    if (!arr || arr->type != VG_JARRAY)
        return NULL;
    const vg_jvalue *e = arr->child;
    while (e && i--)
        e = e->next;
    return e;
}

double vg_jnum(const vg_jvalue *root, const char *path, double fallback)
{
    const vg_jvalue *v = vg_jpath(root, path);
    return v && v->type == VG_JNUMBER ? v->number : fallback;
}
