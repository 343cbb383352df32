#include "log.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "clock.h"

static vg_log_level g_level = VG_LOG_INFO;
static int g_errors;
static bool g_progress_open;
static bool g_silent;
static _Thread_local vg_log_sink t_sink;

vg_log_sink vg_log_set_sink(vg_log_sink sink)
{
    vg_log_sink was = t_sink;
    t_sink = sink;
    return was;
}

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

/* Length of the valid UTF-8 sequence at p (0 when it is not one). */
static int utf8_length(const unsigned char *p)
{
    int n = p[0] < 0x80 ? 1 : (p[0] & 0xe0) == 0xc0 ? 2 : (p[0] & 0xf0) == 0xe0 ? 3 : (p[0] & 0xf8) == 0xf0 ? 4 : 0;
    if (n == 2 && p[0] < 0xc2)
        return 0; /* overlong */
    for (int i = 1; i < n; i++)
        if ((p[i] & 0xc0) != 0x80)
            return 0;
    return n;
}

/* A message quotes what the user gave (file names, bad bytes of a file): it
 * reaches the terminal as printable UTF-8 only, the rest as \xNN. */
static void put_clean(const char *text)
{
    for (const unsigned char *p = (const unsigned char *)text; *p;) {
        int n = utf8_length(p);
        if (n == 1 && (*p < 0x20 || *p == 0x7f))
            n = 0;
        if (n == 0) {
            fprintf(stderr, "\\x%02x", *p++);
            continue;
        }
        fwrite(p, 1, (size_t)n, stderr);
        p += n;
    }
}

void vg_log(vg_log_level level, const char *fmt, ...)
{
    if (level == VG_LOG_ERROR)
        g_errors++;
    if (!t_sink.fn && (level > g_level || g_silent))
        return;
    static const char *const prefix[] = {"", "error: ", "warning: ", "", "debug: "};
    char line[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (t_sink.fn) {
        t_sink.fn(level, line, t_sink.user);
        return;
    }
    end_progress_line();
    fprintf(stderr, "vergence: %s", prefix[level]);
    put_clean(line);
    fputc('\n', stderr);
}

/* The time left of a progress, from its pace so far: empty until a
 * second has passed (a new label, or a count that starts again, restarts
 * the clock). */
static void time_left(const char *label, int done, int total, char *out, size_t cap)
{
    static char s_label[128];
    static int s_done = -1;
    static double s_t0;
    double now = vg_now_ms();
    if (strncmp(label, s_label, sizeof s_label - 1) || done < s_done || done == 0) {
        snprintf(s_label, sizeof s_label, "%s", label);
        s_t0 = now;
    }
    s_done = done;
    out[0] = 0;
    double elapsed = (now - s_t0) / 1000.0;
    if (done <= 0 || done >= total || elapsed < 1.0)
        return;
    int left = (int)(elapsed * (total - done) / done + 0.5);
    if (left >= 60)
        snprintf(out, cap, ", %d:%02d left", left / 60, left % 60);
    else
        snprintf(out, cap, ", %d s left", left);
}

void vg_progress(const char *label, int done, int total)
{
    if (g_level < VG_LOG_INFO || total <= 0 || g_silent)
        return;
    char left[32];
    time_left(label, done, total, left, sizeof left);
    if (isatty(STDERR_FILENO)) {
        int width = 30, filled = (int)((long)width * done / total);
        fprintf(stderr, "\r%s [%.*s%*s] %d/%d%s\033[K", label, filled,
                "##############################", width - filled, "", done, total, left);
        g_progress_open = done < total;
        if (!g_progress_open)
            fputc('\n', stderr);
    } else {
        /* Non-terminal: a line at 0 %, every 25 % and at the end. */
        int step = total >= 4 ? total / 4 : 1;
        if (done == 0 || done == total || done % step == 0)
            fprintf(stderr, "%s %d/%d%s\n", label, done, total, left);
    }
    fflush(stderr);
}
