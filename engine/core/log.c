#include "log.h"

#include <stdio.h>
#include <unistd.h>

static vg_log_level g_level = VG_LOG_INFO;
static int g_errors;
static bool g_progress_open;
static bool g_silent;

bool vg_log_set_silent(bool silent)
{
    bool was = g_silent;
    g_silent = silent;
    return was;
}

void vg_log_set_level(vg_log_level max_level)
{
    g_level = max_level == VG_LOG_DEFAULT ? VG_LOG_INFO : max_level;
}

int vg_log_error_count(void)
{
    return g_errors;
}

static void end_progress_line(void)
{
    if (g_progress_open) {
        fputc('\n', stderr);
        g_progress_open = false;
    }
}

void vg_log(vg_log_level level, const char *fmt, ...)
{
    if (level == VG_LOG_ERROR)
        g_errors++;
    if (level > g_level || g_silent)
        return;
    static const char *const prefix[] = {"", "error: ", "warning: ", "", "debug: "};
    end_progress_line();
    fprintf(stderr, "vergence: %s", prefix[level]);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}

void vg_progress(const char *label, int done, int total)
{
    if (g_level < VG_LOG_INFO || total <= 0 || g_silent)
        return;
    if (isatty(STDERR_FILENO)) {
        int width = 30, filled = (int)((long)width * done / total);
        fprintf(stderr, "\r%s [%.*s%*s] %d/%d", label, filled,
                "##############################", width - filled, "", done, total);
        g_progress_open = done < total;
        if (!g_progress_open)
            fputc('\n', stderr);
    } else {
        /* Non-terminal: a line at 0 %, every 25 % and at the end. */
        int step = total >= 4 ? total / 4 : 1;
        if (done == 0 || done == total || done % step == 0)
            fprintf(stderr, "%s %d/%d\n", label, done, total);
    }
    fflush(stderr);
}
