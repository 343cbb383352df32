/* vergence — a study's CSV file (docs/game.md "CSV files").
 *
 * One header line, then one line per finished trial. Each line is written
 * with one write() and fsync'd before the next trial starts, so a crash or
 * `kill -9` leaves every finished trial on disk and no torn line; a write
 * that fails part-way (a full disk) is cut back to the last complete line. A file is
 * never overwritten: a new study creates its file exclusively (and syncs
 * the folder, so the name survives a power cut too); --resume reads the
 * file back, checks it line by line (header, field counts, the participant
 * of every row) and appends. Any problem is one error line naming the file
 * (and the line), and the file is left as it was. */
#pragma once
#include <stdbool.h>
#include <stddef.h>

#include "core/status.h"

#define STUDY_LOG_MAX_COLUMNS 40

typedef struct study_log_desc {
    const char *path;
    const char *kind;            /* "hit" or "preference": named in errors */
    const char *const *columns;  /* the header; column 0 must be "participant" */
    int column_count;
    const char *participant;
    bool resume;                 /* continue an existing file (a missing one is created) */
} study_log_desc;

typedef struct study_log {
    int fd;
    char path[1024];
    int columns;
    int rows;                    /* finished trials in the file (read back + appended) */
    int rows_read;               /* rows read back on resume */
    char **cells;                /* rows_read x columns fields, pointing into text */
    char *text;
    bool created;                /* this run created the file */
    bool crlf;                   /* its lines end in CRLF: appended ones do too */
} study_log;

/* Participant ids are short and CSV-safe: letters, digits, '-', '_', '.'. */
bool study_participant_valid(const char *id);

vg_status study_log_open(const study_log_desc *desc, study_log *out);
/* Reads size bytes of CSV (any bytes) as study_log_open reads an existing
 * file back: the same checks and errors (naming desc->path; desc->resume is
 * not looked at), rows and cells filled in, but no file is opened (fd is -1:
 * nothing can be appended). study_log_open uses the same code; the fuzz
 * target (tests/fuzz/fuzz_study_csv.c) calls this. On an error *out is
 * already closed. */
vg_status study_log_read(const study_log_desc *desc, const void *data, size_t size, study_log *out);
/* Field `column` of row `row` of the rows read back (NULL when out of range). */
const char *study_log_cell(const study_log *log, int row, int column);
/* Appends one row (fields joined by commas, no quoting needed: the fields
 * are numbers, names and the checked participant id), then fsyncs. */
vg_status study_log_append(study_log *log, const char *const *fields);
void study_log_close(study_log *log);
/* Closes, and removes the file when this run created it and finished no
 * trial (a study that could not start leaves nothing behind). */
void study_log_abandon(study_log *log);
