/* vergence bench — its tables: plain text, and the same as Markdown; the
 * --sizes argument its modes share. */
#include "bench_report.h"

#include "core/log.h"
#include "frame/frame.h"

void bench_heading(bench_report *r, const char *title)
{
    printf("\n%s\n", title);
    if (r->md)
        fprintf(r->md, "\n### %s\n\n", title);
}

/* One table row: a label and up to 6 cells already formatted. */
void bench_row(bench_report *r, bool header, const char *label, int n, char cells[][32])
{
    printf("  %-40s", label);
    for (int i = 0; i < n; i++)
        printf(" %14s", cells[i]);
    printf("\n");
    if (!r->md)
        return;
    fprintf(r->md, "| %s |", label);
    for (int i = 0; i < n; i++)
        fprintf(r->md, " %s |", cells[i]);
    fprintf(r->md, "\n");
    if (header) {
        fprintf(r->md, "|---|");
        for (int i = 0; i < n; i++)
            fprintf(r->md, "---:|");
        fprintf(r->md, "\n");
    }
}

void bench_row_values(bench_report *r, const char *label, int n, const double *v, const char *fmt)
{
    char cells[4][32];
    for (int i = 0; i < n; i++)
        snprintf(cells[i], sizeof cells[i], fmt, v[i]);
    bench_row(r, false, label, n, cells);
}

void bench_note(bench_report *r, const char *text)
{
    printf("  %s\n", text);
    if (r->md)
        fprintf(r->md, "\n%s\n", text);
}


bool bench_parse_sizes(const char *cmd, const char *text, uint32_t sizes[2][2])
{
    unsigned w0, h0, w1, h1;
    char tail;
    if (sscanf(text, "%ux%u,%ux%u%c", &w0, &h0, &w1, &h1, &tail) != 4 || w0 < 16 || h0 < 16 || w1 < 16 ||
        h1 < 16 || w0 > 8192 || h0 > 8192 || w1 > 8192 || h1 > 8192) {
        vg_error("%s --sizes: '%s' is not two sizes WxH,WxH (16..8192)", cmd, text);
        return false;
    }
    sizes[0][0] = w0, sizes[0][1] = h0, sizes[1][0] = w1, sizes[1][1] = h1;
    for (int k = 0; k < 2; k++) {
        char why[256];
        if (!frame_size_ok(sizes[k][0], sizes[k][1], why, sizeof why)) {
            vg_error("%s --sizes %s: %s", cmd, text, why);
            return false;
        }
    }
    return true;
}
