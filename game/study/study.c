/* vergence — what both studies share: the session (log, seed, schedule)
 * and the checks of a resumed file. */
#include "study.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/log.h"
#include "rules/game.h"

void study_display_fields(const study_opts *o, char out[STUDY_DISPLAY_COUNT][32])
{
    stereo_display_desc desc = display_cli_desc(&o->display);
    stereo_display d;
    stereo_display_init(&d, &desc);
    snprintf(out[0], 32, "%.4f", d.width_m);
    snprintf(out[1], 32, "%dx%d", d.res_x, d.res_y);
    snprintf(out[2], 32, "%.3f", d.distance_m);
    snprintf(out[3], 32, "%.4f", d.ipd_m);
}

void study_utc_now(char *out, size_t cap)
{
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(out, cap, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

/* The seed: the file's when resuming (every row must agree, and a different
 * --seed is refused), else --seed, else the participant id's. */
static vg_status pick_seed(const study_opts *o, const study_log *log, int column, uint64_t *seed)
{
    *seed = o->seed >= 0 ? (uint64_t)o->seed : game_seed_from_text(o->participant);
    if (log->rows_read == 0)
        return VG_OK;
    const char *s = study_log_cell(log, 0, column);
    char *end;
    unsigned long long v = strtoull(s, &end, 10);
    if (!*s || *end) {
        vg_error("%s: line 2 has seed '%s', not a number: the file is corrupt (left as it is)", log->path, s);
        return VG_ERR_FORMAT;
    }
    if (o->seed >= 0 && v != (uint64_t)o->seed) {
        vg_error("%s was run with --seed %llu, not %d: resume without --seed (or with the same one)",
                 log->path, v, o->seed);
        return VG_ERR_ARG;
    }
    for (int i = 1; i < log->rows_read; i++)
        if (strcmp(study_log_cell(log, i, column), s)) {
            vg_error("%s: line %d has another seed than line 2: the file is corrupt (left as it is)",
                     log->path, i + 2);
            return VG_ERR_FORMAT;
        }
    *seed = v;
    return VG_OK;
}

/* Every row was run with the settings this run would write: trials of
 * another condition must not join the file. */
static vg_status check_settings(const study_kind *k, const study_log *log)
{
    for (int i = 0; i < log->rows_read; i++)
        for (int s = 0; s < k->setting_count; s++) {
            const char *have = study_log_cell(log, i, k->settings[s].column);
            if (strcmp(have, k->settings[s].value)) {
                vg_error("%s: line %d was run with %s %s, this run asks for %s: resume with the same %s, or "
                         "choose another --out", log->path, i + 2, k->settings[s].flag, have, k->settings[s].value,
                         k->settings[s].flag);
                return VG_ERR_ARG;
            }
        }
    return VG_OK;
}

/* Every measured number of a row read back is a finite number. */
static vg_status check_numbers(const study_kind *k, const study_log *log)
{
    for (int i = 0; i < log->rows_read; i++)
        for (int c = 0; c < k->numeric_count; c++) {
            const char *v = study_log_cell(log, i, k->numeric[c]);
            char *end;
            double x = strtod(v, &end);
            if (!*v || *end || !isfinite(x)) {
                vg_error("%s: line %d: %s is '%s', not a finite number: the file is corrupt (left as it is)",
                         log->path, i + 2, k->columns[k->numeric[c]], v);
                return VG_ERR_FORMAT;
            }
        }
    return VG_OK;
}

vg_status study_begin(const study_opts *o, const study_kind *k, study_session *out)
{
    *out = (study_session){0};
    vg_status st = study_log_open(&(study_log_desc){
        .path = o->out, .kind = k->name, .columns = k->columns, .column_count = k->column_count,
        .participant = o->participant, .resume = o->resume}, &out->log);
    if (st == VG_OK)
        st = pick_seed(o, &out->log, k->col_seed, &out->seed);
    if (st == VG_OK)
        st = check_settings(k, &out->log);
    if (st == VG_OK)
        st = check_numbers(k, &out->log);
    out->trials = o->trials > 0 ? o->trials : k->default_trials;
    if (st == VG_OK && out->log.rows_read > out->trials) {
        vg_error("%s holds %d trials, more than --trials %d: give at least %d to resume it", o->out,
                 out->log.rows_read, out->trials, out->log.rows_read);
        st = VG_ERR_ARG;
    }
    if (st == VG_OK && !(out->cells = malloc((size_t)out->trials * sizeof(int))))
        st = VG_ERR_NOMEM;
    if (st == VG_OK) {
        game_schedule(out->seed, k->cells, out->trials, out->cells);
        if (out->log.rows > 0)
            vg_info("study %s: %s holds %d finished trial(s) of participant %s: continuing at trial %d", k->name,
                    o->out, out->log.rows, o->participant, out->log.rows);
    }
    return st;
}

vg_status study_end(study_session *s, const study_opts *o, const study_kind *k, vg_status st)
{
    if (st == VG_OK)
        vg_info("study %s: participant %s: %d of %d trial(s) in %s (seed %" PRIu64 ")", k->name, o->participant,
                s->log.rows, s->trials, o->out, s->seed);
    free(s->cells);
    if (st == VG_OK)
        study_log_close(&s->log);
    else
        study_log_abandon(&s->log);
    *s = (study_session){0};
    return st;
}

const char *study_observer_name(const study_opts *o)
{
    static const char *const names[2][2] = {{"model", "model-cpu"}, {"model-2cue", "model-2cue-cpu"}};
    return !o->observer ? "human" : names[o->observer_cues != 0][o->observer_view == STUDY_VIEW_CPU];
}
