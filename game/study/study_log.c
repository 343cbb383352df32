/* vergence — study CSV files: exclusive create, checked resume, append + fsync. */
#include "study_log.h"

#include <errno.h>
#include <fcntl.h>
#include <libgen.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/fault.h"
#include "core/io.h"
#include "core/log.h"

bool study_participant_valid(const char *id)
{
    size_t n = id ? strlen(id) : 0;
    if (n == 0 || n > 64)
        return false;
    for (size_t i = 0; i < n; i++) {
        char c = id[i];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' ||
              c == '_' || c == '.'))
            return false;
    }
    return true;
}

/* ------------------------------------------------------------------------- */
/* Writing                                                                   */
/* ------------------------------------------------------------------------- */

/* A line reaches the disk whole or not at all: a write that fails part-way
 * (a full disk) is cut back to the last complete line before the error. */
static vg_status write_all(study_log *log, const char *text, size_t len)
{
    off_t before = lseek(log->fd, 0, SEEK_END);
    vg_status st = vg_write_all(log->fd, text, len, log->path);
    if (st == VG_OK && fsync(log->fd) != 0) {
        vg_error("%s: cannot sync to disk: %s", log->path, strerror(errno));
        st = VG_ERR_IO;
    }
    if (st == VG_OK)
        vg_fault_file_done(); /* tests: VERGENCE_FAULT=kill:N kills after the N-th line */
    if (st != VG_OK && before >= 0) {
        if (ftruncate(log->fd, before) == 0 && fsync(log->fd) == 0)
            vg_info("%s: cut back to its last complete line (%d trial(s))", log->path, log->rows);
        else
            vg_error("%s: cannot cut the torn line back: %s (remove its last line before --resume)", log->path,
                     strerror(errno));
    }
    return st;
}

static vg_status write_row(study_log *log, const char *const *fields, int count)
{
    size_t len = 0;
    for (int i = 0; i < count; i++)
        len += strlen(fields[i]) + 1;
    char *line = malloc(len + 2);
    if (!line)
        return VG_ERR_NOMEM;
    size_t at = 0;
    for (int i = 0; i < count; i++) {
        size_t n = strlen(fields[i]);
        memcpy(line + at, fields[i], n);
        at += n;
        if (i + 1 == count && log->crlf)
            line[at++] = '\r';
        line[at++] = i + 1 < count ? ',' : '\n';
    }
    /* One write per line: a killed process leaves whole lines only. */
    vg_status st = write_all(log, line, at);
    free(line);
    return st;
}

vg_status study_log_append(study_log *log, const char *const *fields)
{
    vg_status st = write_row(log, fields, log->columns);
    if (st == VG_OK)
        log->rows++;
    return st;
}

/* The new name must survive a crash too: sync the folder that holds it. */
static void sync_folder(const char *path)
{
    char copy[1024];
    snprintf(copy, sizeof copy, "%s", path);
    int dfd = open(dirname(copy), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);
        close(dfd);
    }
}

/* ------------------------------------------------------------------------- */
/* Reading back                                                              */
/* ------------------------------------------------------------------------- */

/* Splits text into lines and fields in place; checks the header and every
 * row. *participant_found gets the participant of the first row. */
static vg_status parse(study_log *log, const study_log_desc *d, char *text, size_t size,
                       const char **participant_found)
{
    *participant_found = NULL;
    if (size == 0 || memchr(text, '\0', size)) {
        vg_error("%s: %s (not a vergence %s-study CSV: rename it or choose another --out)", log->path,
                 size ? "binary data" : "empty file", d->kind);
        return VG_ERR_FORMAT;
    }
    int lines = 0;
    for (size_t i = 0; i < size; i++)
        lines += text[i] == '\n';
    /* Appended lines end as the file's first line does (CRLF or LF). */
    const char *first_end = memchr(text, '\n', size);
    log->crlf = first_end && first_end > text && first_end[-1] == '\r';
    if (text[size - 1] != '\n') {
        vg_error("%s: line %d is incomplete (no end of line): the file was cut mid-write; "
                 "it is left as it is: fix or remove that line, then resume", log->path, lines + 1);
        return VG_ERR_FORMAT;
    }
    free(log->cells);
    log->cells = calloc((size_t)lines * (size_t)d->column_count, sizeof(char *));
    if (!log->cells)
        return VG_ERR_NOMEM;
    char *line = text;
    for (int ln = 0; ln < lines; ln++) {
        char *end = strchr(line, '\n');
        *end = '\0';
        if (end > line && end[-1] == '\r')
            end[-1] = '\0';
        char *fields[STUDY_LOG_MAX_COLUMNS + 1];
        int n = 0;
        for (char *f = line;; n++) {
            char *comma = strchr(f, ',');
            if (n <= STUDY_LOG_MAX_COLUMNS)
                fields[n] = f;
            if (!comma) {
                n++;
                break;
            }
            *comma = '\0';
            f = comma + 1;
        }
        if (ln == 0) {
            bool same = n == d->column_count;
            for (int c = 0; same && c < n; c++)
                same = !strcmp(fields[c], d->columns[c]);
            if (!same) {
                vg_error("%s: line 1 is not the header of a vergence %s-study CSV: rename it or "
                         "choose another --out", log->path, d->kind);
                return VG_ERR_FORMAT;
            }
        } else {
            if (n != d->column_count) {
                vg_error("%s: line %d has %d fields, the header %d: the file is corrupt (left as it is)",
                         log->path, ln + 1, n, d->column_count);
                return VG_ERR_FORMAT;
            }
            if (!*participant_found)
                *participant_found = fields[0];
            if (strcmp(fields[0], *participant_found)) {
                vg_error("%s: line %d is participant '%s', earlier lines '%s': the file is corrupt",
                         log->path, ln + 1, fields[0], *participant_found);
                return VG_ERR_FORMAT;
            }
            memcpy(log->cells + (size_t)(ln - 1) * d->column_count, fields,
                   (size_t)d->column_count * sizeof(char *));
        }
        line = end + 1;
    }
    log->rows = log->rows_read = lines - 1;
    return VG_OK;
}

const char *study_log_cell(const study_log *log, int row, int column)
{
    if (!log->cells || row < 0 || row >= log->rows_read || column < 0 || column >= log->columns)
        return NULL;
    return log->cells[(size_t)row * log->columns + column];
}

/* ------------------------------------------------------------------------- */
/* Open                                                                      */
/* ------------------------------------------------------------------------- */

/* Checks text (log->text, size bytes and a NUL after them) and reads its rows
 * back; *who gets the participant of the rows (NULL when there are none). */
static vg_status read_back(study_log *log, const study_log_desc *d, size_t size, const char **who)
{
    vg_status st = parse(log, d, log->text, size, who);
    if (st != VG_OK)
        return st;
    if (*who && strcmp(*who, d->participant)) {
        vg_error("%s belongs to participant '%s', not '%s': choose another --out", d->path, *who,
                 d->participant);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

static vg_status open_existing(study_log *log, const study_log_desc *d)
{
    size_t size;
    vg_status st = vg_file_read(d->path, (uint8_t **)&log->text, &size);
    if (st != VG_OK)
        return st;
    const char *who;
    st = read_back(log, d, size, &who);
    if (st != VG_OK)
        return st;
    if (!d->resume) {
        vg_error("%s already exists (%d trial(s) of participant '%s'): add --resume to continue it, "
                 "or choose another --out (nothing is overwritten)", d->path, log->rows,
                 who ? who : d->participant);
        return VG_ERR_ARG;
    }
    log->fd = open(d->path, O_WRONLY | O_APPEND | O_CLOEXEC);
    if (log->fd < 0) {
        vg_error("%s: cannot open for appending: %s", d->path, strerror(errno));
        return VG_ERR_IO;
    }
    return VG_OK;
}

static vg_status log_begin(const study_log_desc *d, study_log *out)
{
    *out = (study_log){.fd = -1, .columns = d->column_count};
    snprintf(out->path, sizeof out->path, "%s", d->path);
    if (d->column_count > STUDY_LOG_MAX_COLUMNS || !study_participant_valid(d->participant))
        return VG_ERR_ARG;
    return VG_OK;
}

vg_status study_log_read(const study_log_desc *d, const void *data, size_t size, study_log *out)
{
    vg_status st = log_begin(d, out);
    if (st != VG_OK)
        return st;
    if (!(out->text = malloc(size + 1)))
        return VG_ERR_NOMEM;
    if (size)
        memcpy(out->text, data, size);
    out->text[size] = '\0';
    const char *who;
    st = read_back(out, d, size, &who);
    if (st != VG_OK)
        study_log_close(out);
    return st;
}

vg_status study_log_open(const study_log_desc *d, study_log *out)
{
    vg_status st = log_begin(d, out);
    if (st != VG_OK)
        return st;
    struct stat sb;
    if (stat(d->path, &sb) == 0) {
        if (!S_ISREG(sb.st_mode)) {
            vg_error("%s is not a regular file", d->path);
            return VG_ERR_IO;
        }
        st = open_existing(out, d);
        if (st != VG_OK)
            study_log_close(out);
        return st;
    }
    out->fd = open(d->path, O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
    if (out->fd < 0) {
        vg_error("%s: cannot create: %s", d->path, strerror(errno));
        return errno == EEXIST ? VG_ERR_ARG : VG_ERR_IO;
    }
    out->created = true;
    st = write_row(out, d->columns, d->column_count);
    if (st == VG_OK)
        sync_folder(d->path);
    if (st != VG_OK) {
        study_log_close(out);
        unlink(d->path); /* ours, just created, holds nothing yet */
    }
    return st;
}

void study_log_close(study_log *log)
{
    if (!log)
        return;
    if (log->fd >= 0)
        close(log->fd);
    free(log->cells);
    free(log->text);
    *log = (study_log){.fd = -1};
}

void study_log_abandon(study_log *log)
{
    if (!log)
        return;
    bool remove = log->created && log->rows == 0 && log->fd >= 0;
    char path[sizeof log->path];
    memcpy(path, log->path, sizeof path);
    study_log_close(log);
    if (remove)
        unlink(path);
}
