/* Study CSV read back (`vergence study ... --resume`, game/study/study_log.c):
 * study_log_read on any bytes, the code study_log_open runs on an existing
 * file. Three headers each time: the hit and the preference study's, and
 * one taken from the input's own first line (so any column count up to the
 * limit gets past the header check). When the read succeeds every cell is
 * looked up, in range and out of it, and checked. */
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "fuzz.h"
#include "study/study_log.h"

/* The headers of game/study/study_hit.c and game/study/study_pref.c (their k_columns). */
static const char *const k_hit[] = {
    "participant", "study", "trial", "seed", "condition", "direction", "path", "operator", "observer",
    "visible_s", "start_x", "start_y", "start_z", "velocity_x", "velocity_y", "velocity_z", "gravity",
    "flight_s", "ground_x", "ground_y", "ground_z", "click_u", "click_v", "error_m", "response_s", "utc",
};
static const char *const k_pref[] = {
    "participant", "study", "trial", "seed", "scene", "saliency", "optimized_side", "operator", "observer",
    "choice", "chose_optimized", "response_s", "utc",
};
#define PARTICIPANT "sim" /* the seeds' participant */

static void check(const study_log *log, const study_log_desc *d, const uint8_t *data, size_t size)
{
    int lines = 0;
    for (size_t i = 0; i < size; i++)
        lines += data[i] == '\n';
    if (log->fd != -1 || log->columns != d->column_count || log->rows != lines - 1 || log->rows_read != log->rows)
        abort();
    volatile size_t sink = 0;
    for (int r = -1; r <= log->rows_read; r++)
        for (int c = -1; c <= log->columns; c++) {
            const char *cell = study_log_cell(log, r, c);
            bool inside = r >= 0 && r < log->rows_read && c >= 0 && c < log->columns;
            if (!inside) {
                if (cell)
                    abort();
                continue;
            }
            /* A cell lies inside the text and holds no separator. */
            if (!cell || cell < log->text || cell > log->text + size || strpbrk(cell, ",\n"))
                abort();
            if (c == 0 && strcmp(cell, d->participant))
                abort();
            sink += strlen(cell);
        }
    (void)sink;
}

static void read_as(const study_log_desc *d, const uint8_t *data, size_t size)
{
    study_log log;
    if (study_log_read(d, data, size, &log) == VG_OK)
        check(&log, d, data, size);
    study_log_close(&log);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vg_log_set_silent(true);
    if (size > 1 << 16)
        return 0;
    study_log_desc d = {.path = "fuzz.csv", .kind = "hit", .columns = k_hit,
                        .column_count = sizeof k_hit / sizeof k_hit[0], .participant = PARTICIPANT, .resume = true};
    read_as(&d, data, size);
    d.kind = "preference";
    d.columns = k_pref;
    d.column_count = sizeof k_pref / sizeof k_pref[0];
    read_as(&d, data, size);

    /* The input's first line as the header (without a trailing '\r'); the
     * participant is line 2's first field when that is a valid id. */
    char head[1024], who[72];
    size_t n = 0;
    while (n < size && n < sizeof head - 1 && data[n] != '\n')
        n++;
    if (n)
        memcpy(head, data, n);
    head[n] = '\0';
    if (n && head[n - 1] == '\r')
        head[n - 1] = '\0';
    const char *cols[STUDY_LOG_MAX_COLUMNS];
    int count = 0;
    char *f = head;
    for (; f && count < STUDY_LOG_MAX_COLUMNS; count++) {
        cols[count] = f;
        char *comma = strchr(f, ',');
        if (comma)
            *comma = '\0';
        f = comma ? comma + 1 : NULL;
    }
    if (f) /* more columns than a study log may have */
        return 0;
    size_t at = n < size ? n + 1 : size, w = 0;
    while (at + w < size && w < sizeof who - 1 && data[at + w] != ',' && data[at + w] != '\n')
        w++;
    if (w)
        memcpy(who, data + at, w);
    who[w] = '\0';
    d.kind = "fuzz";
    d.columns = cols;
    d.column_count = count;
    d.participant = study_participant_valid(who) ? who : PARTICIPANT;
    read_as(&d, data, size);
    return 0;
}
