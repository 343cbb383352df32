/* vergence bench — its tables: plain text, and the same as Markdown. */
#include "bench_report.h"

void bench_heading(bench_report *r, const char *title)
{
    printf("\n%s\n", title);
    if (r->md)
        fprintf(r->md, "\n### %s\n\n", title);
}

/* One table row: a label and up to 4 cells already formatted. */
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

