/* vergence bench — what its modes share: the tables, plain text on stdout
 * and the same tables as Markdown (docs/PERFORMANCE.md) when a file is given,
 * and the --sizes argument. */
#pragma once
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

typedef struct bench_report {
    FILE *md; /* NULL: text only */
} bench_report;

void bench_heading(bench_report *r, const char *title);
/* One table row: a label and up to 6 cells already formatted. */
void bench_row(bench_report *r, bool header, const char *label, int n, char cells[][32]);
void bench_row_values(bench_report *r, const char *label, int n, const double *v, const char *fmt);
void bench_note(bench_report *r, const char *text);

/* --sizes "WxH,WxH": two frame sizes the frame accepts; false after one error
 * line that names `cmd` ("bench", "bench gbuffer") and the option. */
bool bench_parse_sizes(const char *cmd, const char *text, uint32_t sizes[2][2]);
