/* vergence — the manifest of a result. */
#include "manifest.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "json_read.h"
#include "log.h"

/* A name a manifest may list: inside its folder, no way out of it. */
static bool name_safe(const char *n)
{
    if (!n || !*n || n[0] == '/')
        return false;
    for (const char *p = n; *p;) {
        const char *slash = strchr(p, '/');
        size_t len = slash ? (size_t)(slash - p) : strlen(p);
        if ((len == 2 && !strncmp(p, "..", 2)) || len == 0)
            return false;
        p = slash ? slash + 1 : p + len;
    }
    return true;
}

vg_status vg_manifest_clear(const char *dir, const char *name)
{
    char path[2048];
    vg_status st = vg_path_join(path, sizeof path, dir, name);
    if (st != VG_OK)
        return st;
    uint8_t *data;
    size_t size;
    if (access(path, F_OK) != 0)
        return VG_OK;
    if ((st = vg_file_read(path, &data, &size)) != VG_OK)
        return st;
    /* The list: the whole JSON file, or the block an HTML manifest carries. */
    const char *text = (const char *)data, *end = text + size;
    const char *open = strstr(text, VG_MANIFEST_HTML_OPEN);
    bool html = strstr(name, ".html") != NULL;
    if (open) {
        text = open + strlen(VG_MANIFEST_HTML_OPEN);
        const char *close = strstr(text, VG_MANIFEST_HTML_CLOSE);
        end = close ? close : end;
    }
    vg_jdoc doc = {0};
    bool silent = vg_log_set_silent(true);
    bool parsed = (!html || open) && vg_json_parse(path, text, (size_t)(end - text), &doc) == VG_OK;
    vg_log_set_silent(silent);
    const vg_jvalue *files = parsed ? vg_jget(doc.root, "files") : NULL;
    /* A file of that name that vergence did not write is the user's: it
     * stays, and so does everything beside it. An earlier vergence result
     * without a list (written before lists existed) loses its manifest. */
    bool ours = files || (parsed && vg_jget(doc.root, "vergence")) ||
                (html && strstr((const char *)data, "<title>vergence"));
    if (!ours) {
        vg_error("%s: not a result of vergence, left as it is: choose another folder or remove it", path);
        vg_jdoc_free(&doc);
        free(data);
        return VG_ERR_ARG;
    }
    if (!files)
        vg_warn("%s: an earlier result without a file list: removing its manifest alone", path);
    /* The manifest first: from here on the folder holds no complete result. */
    if (unlink(path) != 0) {
        vg_error("%s: cannot remove the earlier result's manifest: %s", path, strerror(errno));
        st = VG_ERR_IO;
    }
    for (size_t i = 0; st == VG_OK && files && i < files->count; i++) {
        const vg_jvalue *f = vg_jat(files, i), *n = f ? vg_jget(f, "name") : NULL;
        const char *fname = n && n->type == VG_JSTRING ? n->string : NULL;
        char file[2048];
        if (!name_safe(fname) || vg_path_join(file, sizeof file, dir, fname) != VG_OK)
            continue;
        if (unlink(file) != 0 && errno != ENOENT) {
            vg_error("%s: cannot remove this file of the earlier result: %s", file, strerror(errno));
            st = VG_ERR_IO;
        }
    }
    vg_jdoc_free(&doc);
    free(data);
    return st;
}

vg_status vg_manifest_begin(vg_manifest *m, const char *dir, const char *name)
{
    *m = (vg_manifest){0};
    snprintf(m->dir, sizeof m->dir, "%s", dir);
    snprintf(m->name, sizeof m->name, "%s", name);
    vg_status st = vg_dir_prepare(dir);
    if (st == VG_OK)
        st = vg_manifest_clear(dir, name);
    if (st == VG_OK)
        vg_write_watch_begin(&m->watch, dir);
    return st;
}

vg_status vg_manifest_files(const vg_manifest *m, vg_json *j)
{
    if (m->watch.failed) {
        vg_error("%s/%s: a written file went unrecorded (out of memory): no manifest", m->dir, m->name);
        return VG_ERR_NOMEM;
    }
    vg_json_array_begin(j, "files");
    for (int i = 0; i < m->watch.count; i++) {
        const vg_written *f = &m->watch.files[i];
        if (!strcmp(f->name, m->name))
            continue;
        vg_json_object_begin(j, NULL);
        vg_json_str(j, "name", f->name);
        vg_json_int(j, "bytes", (long long)f->bytes);
        vg_json_object_end(j);
    }
    vg_json_array_end(j);
    return VG_OK;
}

void vg_manifest_end(vg_manifest *m)
{
    if (m->watch.dir[0])
        vg_write_watch_end(&m->watch);
}

/* ------------------------------------------------------------------------- */
/* Inputs against outputs                                                    */
/* ------------------------------------------------------------------------- */

/* The absolute path of a file that may not exist yet: its folder's real
 * path (links resolved) and its name; "." and ".." folded. */
static void canonical(const char *path, char *out, size_t cap)
{
    char real[4096];
    if (realpath(path, real)) {
        snprintf(out, cap, "%s", real);
        return;
    }
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    const char *name = path;
    if (slash) {
        name = path + (slash - dir) + 1;
        *slash = '\0';
        if (!dir[0])
            snprintf(dir, sizeof dir, "/");
    } else {
        snprintf(dir, sizeof dir, ".");
    }
    if (!realpath(dir, real) || snprintf(out, cap, "%s/%s", strcmp(real, "/") ? real : "", name) >= (int)cap)
        snprintf(out, cap, "%s", path);
}

static bool same_file(const struct vg_input *a, const char *canon_b, const char *b)
{
    struct stat sa, sb;
    if (stat(a->given, &sa) == 0 && stat(b, &sb) == 0)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    return !strcmp(a->path, canon_b);
}

vg_status vg_inputs_add(vg_inputs *in, const char *label, const char *path)
{
    if (in->count == in->cap) {
        int cap = in->cap ? 2 * in->cap : 16;
        struct vg_input *p = realloc(in->items, (size_t)cap * sizeof *p);
        if (!p)
            return VG_ERR_NOMEM;
        in->items = p;
        in->cap = cap;
    }
    struct vg_input *it = &in->items[in->count++];
    snprintf(it->given, sizeof it->given, "%s", path);
    snprintf(it->label, sizeof it->label, "%s", label);
    canonical(path, it->path, sizeof it->path);
    return VG_OK;
}

vg_status vg_inputs_check(const vg_inputs *in, const char *label, const char *path)
{
    char c[4096];
    canonical(path, c, sizeof c);
    for (int i = 0; i < in->count; i++)
        if (same_file(&in->items[i], c, path)) {
            vg_error("%s %s: would overwrite the input %s %s; write elsewhere", label, path, in->items[i].label,
                     in->items[i].given);
            return VG_ERR_ARG;
        }
    return VG_OK;
}

vg_status vg_inputs_check_dir(const vg_inputs *in, const char *label, const char *dir, const char *manifest,
                              bool (*writes)(const char *name))
{
    char cdir[4096];
    canonical(dir, cdir, sizeof cdir);
    size_t n = strlen(cdir);
    for (int i = 0; i < in->count; i++) {
        const struct vg_input *it = &in->items[i];
        if (strncmp(it->path, cdir, n) || it->path[n] != '/')
            continue;
        const char *rel = it->path + n + 1;
        if ((manifest && !strcmp(rel, manifest)) || (writes && writes(rel))) {
            vg_error("%s %s: the result written there would overwrite the input %s %s; write elsewhere", label, dir,
                     it->label, it->given);
            return VG_ERR_ARG;
        }
    }
    /* What an earlier result there lists is removed before the run. */
    char path[2048];
    uint8_t *data;
    size_t size;
    if (!manifest || vg_path_join(path, sizeof path, dir, manifest) != VG_OK || access(path, F_OK) != 0 ||
        vg_file_read(path, &data, &size) != VG_OK)
        return VG_OK;
    const char *text = (const char *)data, *end = text + size, *open = strstr(text, VG_MANIFEST_HTML_OPEN);
    if (open) {
        text = open + strlen(VG_MANIFEST_HTML_OPEN);
        const char *close = strstr(text, VG_MANIFEST_HTML_CLOSE);
        end = close ? close : end;
    }
    vg_jdoc doc = {0};
    vg_status st = VG_OK;
    bool silent = vg_log_set_silent(true); /* vg_manifest_clear says it, once */
    bool parsed = vg_json_parse(path, text, (size_t)(end - text), &doc) == VG_OK;
    vg_log_set_silent(silent);
    const vg_jvalue *files = parsed ? vg_jget(doc.root, "files") : NULL;
    for (size_t k = 0; st == VG_OK && files && k < files->count; k++) {
        const vg_jvalue *f = vg_jat(files, k), *nm = f ? vg_jget(f, "name") : NULL;
        char file[2048];
        if (nm && nm->type == VG_JSTRING && name_safe(nm->string) &&
            vg_path_join(file, sizeof file, dir, nm->string) == VG_OK && vg_inputs_check(in, label, file) != VG_OK)
            st = VG_ERR_ARG;
    }
    vg_jdoc_free(&doc);
    free(data);
    return st;
}

void vg_inputs_free(vg_inputs *in)
{
    free(in->items);
    *in = (vg_inputs){0};
}
