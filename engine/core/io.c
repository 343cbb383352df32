#include "io.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "fault.h"
#include "log.h"

/* ------------------------------------------------------------------------- */
/* Images                                                                    */
/* ------------------------------------------------------------------------- */

vg_status vg_imagef_alloc(vg_imagef *img, int width, int height, int channels)
{
    *img = (vg_imagef){0};
    if (width <= 0 || height <= 0 || channels <= 0 || (long)width * height > VG_MAX_PIXELS)
        return VG_ERR_ARG;
    img->data = calloc((size_t)width * (size_t)height * (size_t)channels, sizeof(float));
    if (!img->data)
        return VG_ERR_NOMEM;
    img->width = width;
    img->height = height;
    img->channels = channels;
    return VG_OK;
}

void vg_imagef_free(vg_imagef *img)
{
    if (!img)
        return;
    free(img->data);
    *img = (vg_imagef){0};
}

/* ------------------------------------------------------------------------- */
/* Files                                                                     */
/* ------------------------------------------------------------------------- */

vg_status vg_file_read(const char *path, uint8_t **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f) {
        vg_error("%s: cannot open: %s", path, strerror(errno));
        return VG_ERR_IO;
    }
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
        vg_error("%s: not a regular file", path);
        fclose(f);
        return VG_ERR_IO;
    }
    size_t n = (size_t)st.st_size;
    uint8_t *buf = malloc(n + 1);
    if (!buf) {
        fclose(f);
        vg_error("%s: out of memory reading %zu bytes", path, n);
        return VG_ERR_NOMEM;
    }
    size_t got = fread(buf, 1, n, f);
    fclose(f);
    if (got != n) {
        free(buf);
        vg_error("%s: read %zu of %zu bytes", path, got, n);
        return VG_ERR_IO;
    }
    buf[n] = 0;
    *data = buf;
    *size = n;
    return VG_OK;
}

vg_status vg_write_all(int fd, const void *data, size_t size, const char *path)
{
    const uint8_t *p = data;
    while (size > 0) {
        /* A disk that fills up (tests: VERGENCE_FAULT=enospc:N). */
        size_t allowed = vg_fault_write_allowance(size);
        ssize_t w = allowed ? write(fd, p, allowed) : (errno = ENOSPC, -1);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            vg_error("%s: write failed: %s", path, strerror(w < 0 ? errno : EIO));
            return VG_ERR_IO;
        }
        p += w;
        size -= (size_t)w;
    }
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Watched folders: what was written under them                              */
/* ------------------------------------------------------------------------- */

static vg_write_watch *g_watches;

void vg_write_watch_begin(vg_write_watch *w, const char *dir)
{
    *w = (vg_write_watch){0};
    snprintf(w->dir, sizeof w->dir, "%s", dir);
    size_t n = strlen(w->dir);
    while (n > 1 && w->dir[n - 1] == '/')
        w->dir[--n] = '\0';
    w->next = g_watches;
    g_watches = w;
}

void vg_write_watch_end(vg_write_watch *w)
{
    for (vg_write_watch **p = &g_watches; *p; p = &(*p)->next)
        if (*p == w) {
            *p = w->next;
            break;
        }
    for (int i = 0; i < w->count; i++)
        free(w->files[i].name);
    free(w->files);
    *w = (vg_write_watch){0};
}

/* path relative to dir when it lies under it, else NULL ("./a" and "a" alike). */
static const char *under(const char *dir, const char *path)
{
    while (path[0] == '.' && path[1] == '/')
        path += 2;
    if (!strcmp(dir, "."))
        return path[0] != '/' ? path : NULL;
    size_t n = strlen(dir);
    if (strncmp(path, dir, n) || path[n] != '/')
        return NULL;
    path += n;
    while (*path == '/')
        path++;
    return *path ? path : NULL;
}

static bool grow(vg_write_watch *w)
{
    if (w->count < w->cap)
        return true;
    int cap = w->cap ? 2 * w->cap : 64;
    vg_written *f = realloc(w->files, (size_t)cap * sizeof *f);
    if (!f)
        return false;
    w->files = f;
    w->cap = cap;
    return true;
}

static void note_written(const char *path, uint64_t bytes)
{
    for (vg_write_watch *w = g_watches; w; w = w->next) {
        const char *rel = under(w->dir, path);
        if (!rel)
            continue;
        int i = 0;
        while (i < w->count && strcmp(w->files[i].name, rel))
            i++;
        if (i == w->count) {
            char *name = grow(w) ? strdup(rel) : NULL;
            if (!name) {
                w->failed = true; /* the manifest would not be exact: its writer refuses */
                continue;
            }
            w->files[w->count++] = (vg_written){name, 0};
        }
        w->files[i].bytes = bytes;
    }
}

vg_status vg_write_watch_add(const char *path)
{
    struct stat st;
    if (stat(path, &st) != 0) {
        vg_error("%s: %s", path, strerror(errno));
        return VG_ERR_IO;
    }
    note_written(path, (uint64_t)st.st_size);
    vg_fault_file_done();
    return VG_OK;
}

vg_status vg_file_write_atomic(const char *path, const void *data, size_t size)
{
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.tmp%ld", path, (long)getpid()) >= (int)sizeof tmp) {
        vg_error("%s: path too long", path);
        return VG_ERR_ARG;
    }
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) {
        vg_error("%s: cannot write: %s", path, strerror(errno));
        return VG_ERR_IO;
    }
    if (vg_write_all(fd, data, size, path) != VG_OK) {
        close(fd);
        unlink(tmp);
        return VG_ERR_IO;
    }
    if (close(fd) != 0 || rename(tmp, path) != 0) {
        vg_error("%s: cannot finish writing: %s", path, strerror(errno));
        unlink(tmp);
        return VG_ERR_IO;
    }
    note_written(path, size);
    vg_fault_file_done();
    return VG_OK;
}

vg_status vg_path_join(char *out, size_t cap, const char *dir, const char *name)
{
    int n = snprintf(out, cap, "%s/%s", dir, name);
    if (n < 0 || (size_t)n >= cap) {
        vg_error("%s/%s: path too long", dir, name);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

vg_status vg_dir_prepare(const char *path)
{
    char buf[4096];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf || !path[0]) {
        vg_error("'%s': bad output folder path", path);
        return VG_ERR_ARG;
    }
    /* mkdir -p: create each prefix in turn. */
    for (char *p = buf + 1;; p++) {
        if (*p == '/' || *p == 0) {
            char c = *p;
            *p = 0;
            if (mkdir(buf, 0755) != 0 && errno != EEXIST) {
                vg_error("%s: cannot create folder: %s", buf, strerror(errno));
                return VG_ERR_IO;
            }
            *p = c;
            if (!c)
                break;
        }
    }
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode)) {
        vg_error("%s: not a folder", path);
        return VG_ERR_IO;
    }
    char probe[4096];
    if (vg_path_join(probe, sizeof probe, path, ".vergence-probe") != VG_OK)
        return VG_ERR_ARG;
    int fd = open(probe, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) {
        vg_error("%s: output folder is not writable: %s", path, strerror(errno));
        return VG_ERR_IO;
    }
    close(fd);
    unlink(probe);
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* PFM                                                                       */
/* ------------------------------------------------------------------------- */

/* Reads one whitespace-delimited header token; returns bytes consumed or 0. */
static size_t pfm_token(const uint8_t *p, size_t n, char *tok, size_t cap)
{
    size_t i = 0, k = 0;
    while (i < n && (p[i] == ' ' || p[i] == '\t' || p[i] == '\n' || p[i] == '\r'))
        i++;
    while (i < n && k + 1 < cap && p[i] > ' ' && p[i] < 127)
        tok[k++] = (char)p[i++];
    tok[k] = 0;
    if (k == 0 || k + 1 >= cap || i >= n)
        return 0;
    return i;
}

static int host_is_little_endian(void)
{
    const uint16_t one = 1;
    return *(const uint8_t *)&one == 1;
}

static void swap4(void *data, size_t count)
{
    uint8_t *b = data;
    for (size_t i = 0; i < count; i++, b += 4) {
        uint8_t t0 = b[0], t1 = b[1];
        b[0] = b[3];
        b[1] = b[2];
        b[2] = t1;
        b[3] = t0;
    }
}

vg_status vg_pfm_parse(const char *path, const uint8_t *buf, size_t size, vg_imagef *out)
{
    *out = (vg_imagef){0};
    vg_status st;

    char magic[8], sw[32], sh[32], ss[64];
    size_t off = 0, used;
    if (!(used = pfm_token(buf, size, magic, sizeof magic)) || (strcmp(magic, "Pf") && strcmp(magic, "PF"))) {
        vg_error("%s: not a PFM file (magic must be 'Pf' or 'PF')", path);
        return VG_ERR_FORMAT;
    }
    off += used;
    char *end;
    long w = 0, h = 0;
    double scale = 0;
    if ((used = pfm_token(buf + off, size - off, sw, sizeof sw)))
        off += used, w = strtol(sw, &end, 10);
    if (used && *end == 0 && (used = pfm_token(buf + off, size - off, sh, sizeof sh)))
        off += used, h = strtol(sh, &end, 10);
    if (used && *end == 0 && (used = pfm_token(buf + off, size - off, ss, sizeof ss)))
        off += used, scale = strtod(ss, &end);
    if (!used || *end != 0 || w <= 0 || h <= 0 || w > VG_MAX_PIXELS || h > VG_MAX_PIXELS ||
        w * h > VG_MAX_PIXELS || scale == 0 || !isfinite(scale)) {
        vg_error("%s: bad PFM header (width, height and a non-zero scale expected)", path);
        return VG_ERR_FORMAT;
    }
    off += 1; /* exactly one whitespace byte ends the header */
    int channels = magic[1] == 'F' ? 3 : 1;
    size_t need = (size_t)w * (size_t)h * (size_t)channels * sizeof(float);
    if (size - off < need) {
        vg_error("%s: truncated PFM: %ldx%ld needs %zu bytes of pixels, file has %zu", path, w, h,
                 need, size - off);
        return VG_ERR_FORMAT;
    }
    st = vg_imagef_alloc(out, (int)w, (int)h, channels);
    if (st != VG_OK)
        return st;
    /* PFM rows run bottom to top. */
    size_t row = (size_t)w * (size_t)channels;
    for (long y = 0; y < h; y++)
        memcpy(out->data + (size_t)(h - 1 - y) * row, buf + off + (size_t)y * row * 4, row * 4);
    int file_le = scale < 0;
    if (file_le != host_is_little_endian())
        swap4(out->data, row * (size_t)h);
    return VG_OK;
}

vg_status vg_pfm_read(const char *path, vg_imagef *out)
{
    uint8_t *buf;
    size_t size;
    *out = (vg_imagef){0};
    vg_status st = vg_file_read(path, &buf, &size);
    if (st == VG_OK)
        st = vg_pfm_parse(path, buf, size, out);
    free(buf);
    return st;
}

vg_status vg_pfm_write(const char *path, const vg_imagef *img)
{
    if (img->channels != 1 && img->channels != 3) {
        vg_error("%s: PFM holds 1 or 3 channels, not %d", path, img->channels);
        return VG_ERR_ARG;
    }
    char header[64];
    int hn = snprintf(header, sizeof header, "%s\n%d %d\n%s\n", img->channels == 3 ? "PF" : "Pf",
                      img->width, img->height, host_is_little_endian() ? "-1.0" : "1.0");
    size_t row = (size_t)img->width * (size_t)img->channels * 4;
    size_t total = (size_t)hn + row * (size_t)img->height;
    uint8_t *buf = malloc(total);
    if (!buf)
        return VG_ERR_NOMEM;
    memcpy(buf, header, (size_t)hn);
    for (int y = 0; y < img->height; y++)
        memcpy(buf + hn + (size_t)y * row,
               (const uint8_t *)img->data + (size_t)(img->height - 1 - y) * row, row);
    vg_status st = vg_file_write_atomic(path, buf, total);
    free(buf);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Middlebury .flo                                                           */
/* ------------------------------------------------------------------------- */

#define FLO_MAGIC 202021.25f

vg_status vg_flo_parse(const char *path, const uint8_t *buf, size_t size, vg_imagef *out)
{
    *out = (vg_imagef){0};
    vg_status st;
    float magic;
    int32_t wh[2];
    if (size < 12) {
        vg_error("%s: truncated .flo: %zu bytes, the header alone needs 12", path, size);
        return VG_ERR_FORMAT;
    }
    memcpy(&magic, buf, 4);
    memcpy(wh, buf + 4, 8);
    if (!host_is_little_endian()) {
        swap4(&magic, 1);
        swap4(wh, 2);
    }
    if (magic != FLO_MAGIC) {
        vg_error("%s: not a Middlebury .flo file (magic is not 202021.25)", path);
        return VG_ERR_FORMAT;
    }
    if (wh[0] <= 0 || wh[1] <= 0 || (long)wh[0] * wh[1] > VG_MAX_PIXELS) {
        vg_error("%s: bad .flo size %dx%d", path, wh[0], wh[1]);
        return VG_ERR_FORMAT;
    }
    size_t need = (size_t)wh[0] * (size_t)wh[1] * 8;
    if (size - 12 < need) {
        vg_error("%s: truncated .flo: %dx%d needs %zu bytes of flow, file has %zu", path, wh[0],
                 wh[1], need, size - 12);
        return VG_ERR_FORMAT;
    }
    st = vg_imagef_alloc(out, wh[0], wh[1], 2);
    if (st == VG_OK) {
        memcpy(out->data, buf + 12, need);
        if (!host_is_little_endian())
            swap4(out->data, need / 4);
    }
    return st;
}

vg_status vg_flo_read(const char *path, vg_imagef *out)
{
    uint8_t *buf;
    size_t size;
    *out = (vg_imagef){0};
    vg_status st = vg_file_read(path, &buf, &size);
    if (st == VG_OK)
        st = vg_flo_parse(path, buf, size, out);
    free(buf);
    return st;
}

vg_status vg_flo_write(const char *path, const vg_imagef *img)
{
    if (img->channels != 2) {
        vg_error("%s: .flo holds 2 channels, not %d", path, img->channels);
        return VG_ERR_ARG;
    }
    size_t n = (size_t)img->width * (size_t)img->height * 2;
    uint8_t *buf = malloc(12 + n * 4);
    if (!buf)
        return VG_ERR_NOMEM;
    float magic = FLO_MAGIC;
    int32_t wh[2] = {img->width, img->height};
    memcpy(buf, &magic, 4);
    memcpy(buf + 4, wh, 8);
    memcpy(buf + 12, img->data, n * 4);
    if (!host_is_little_endian())
        swap4(buf, 3 + n);
    vg_status st = vg_file_write_atomic(path, buf, 12 + n * 4);
    free(buf);
    return st;
}
