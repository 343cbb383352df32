/* vergence bench — its tables: plain text on stdout, and the same tables as
 * Markdown (docs/PERFORMANCE.md) when a file is given. */
#pragma once
#include <stdbool.h>
#include <stdio.h>

typedef struct bench_report {
    FILE *md; /* NULL: text only */
} bench_report;

void bench_heading(bench_report *r, const char *title);
/* One table row: a label and up to 4 cells already formatted. */
void bench_row(bench_report *r, bool header, const char *label, int n, char cells[][32]);
void bench_row_values(bench_report *r, const char *label, int n, const double *v, const char *fmt);
void bench_note(bench_report *r, const char *text);
