/* vergence — logging and progress on stderr.
 *
 * Errors are one line: "vergence: error: <what>". Progress is a single
 * rewritten line on a terminal and a few plain lines otherwise, so CI logs
 * stay short. */
#pragma once
#include <stdarg.h>
#include <stdbool.h>

typedef enum vg_log_level {
    VG_LOG_DEFAULT = 0,
    VG_LOG_ERROR,
    VG_LOG_WARN,
    VG_LOG_INFO,
    VG_LOG_DEBUG,
} vg_log_level;

void vg_log_set_level(vg_log_level max_level);
/* Silences every line, errors included (fuzzers); errors are still counted.
 * Returns the setting before. */
bool vg_log_set_silent(bool silent);
void vg_log(vg_log_level level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
#define vg_error(...) vg_log(VG_LOG_ERROR, __VA_ARGS__)
#define vg_warn(...)  vg_log(VG_LOG_WARN, __VA_ARGS__)
#define vg_info(...)  vg_log(VG_LOG_INFO, __VA_ARGS__)
#define vg_debug(...) vg_log(VG_LOG_DEBUG, __VA_ARGS__)

/* Where this thread's lines go instead of stderr, all levels (the SDK hands
 * them to its host's callback while one of its calls runs); {0} = stderr.
 * Returns the sink before. */
typedef struct vg_log_sink {
    void (*fn)(vg_log_level level, const char *line, void *user);
    void *user;
} vg_log_sink;
vg_log_sink vg_log_set_sink(vg_log_sink sink);

/* Number of error lines logged so far (lets callers avoid logging twice). */
int vg_log_error_count(void);

/* Progress of a long job: call with done in [0, total]; done == total ends the
 * line. Once a second has passed it says the time left at the pace so far. */
void vg_progress(const char *label, int done, int total);
