/* vergence — command-line options for git-style subcommands.
 *
 * Each subcommand describes its options in a table; the parser fills the
 * destinations, checks ranges and choices, and reports the first problem in
 * one line ("vergence capture: --frames: 'x' is not an integer"). */
#pragma once
#include <stdbool.h>
#include <stdio.h>

#include "status.h"

typedef enum vg_opt_kind {
    VG_OPT_DEFAULT = 0,
    VG_OPT_FLAG,   /* bool *dest, no value */
    VG_OPT_INT,    /* int *dest */
    VG_OPT_FLOAT,  /* double *dest */
    VG_OPT_STRING, /* const char **dest */
    VG_OPT_SIZE,   /* int dest[2]: "WxH" */
    VG_OPT_CHOICE, /* int *dest: index into choices */
    VG_OPT_ENUM,   /* int *dest: an enum value v named choices[v]; choices[0] names what the
                      enum's 0 (its default) stands for and is not offered itself */
} vg_opt_kind;

typedef struct vg_opt {
    const char *name;                /* "--frames" */
    vg_opt_kind kind;
    void *dest;
    const char *metavar;             /* "N" in the help text */
    const char *help;
    const char *const *choices;      /* NULL-terminated, for VG_OPT_CHOICE: dest gets the index */
    double min, max;                 /* accepted range when min < max */
} vg_opt;

typedef struct vg_cmd {
    const char *name;    /* "capture" */
    const char *summary; /* one line for "vergence --help" */
    const char *usage;   /* "vergence capture --scene FILE --out DIR [options]" */
    const char *details; /* paragraph after the usage, may be NULL */
    const vg_opt *opts;
    int opt_count;
    int (*run)(int argc, char **argv);
} vg_cmd;

/* Parses argv[1..] (argv[0] is the subcommand). Sets *help when --help/-h was
 * given (after printing it to stdout); returns VG_ERR_ARG on a bad option. */
vg_status vg_cli_parse(const vg_cmd *cmd, int argc, char **argv, bool *help);
void vg_cli_print_help(const vg_cmd *cmd, FILE *out);
/* Error for a missing required option: "vergence capture: --out is required". */
vg_status vg_cli_require(const vg_cmd *cmd, const char *name, const void *value_set);
