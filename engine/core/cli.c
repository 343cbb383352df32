#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "log.h"

static const vg_opt *find(const vg_cmd *cmd, const char *name, size_t len)
{
    for (int i = 0; i < cmd->opt_count; i++)
        if (strlen(cmd->opts[i].name) == len && !strncmp(cmd->opts[i].name, name, len))
            return &cmd->opts[i];
    return NULL;
}

static bool in_range(const vg_opt *o, double v)
{
    return !(o->min < o->max) || (v >= o->min && v <= o->max);
}

static vg_status bad(const vg_cmd *cmd, const vg_opt *o, const char *val, const char *why)
{
    vg_error("%s %s: '%s' %s (see 'vergence %s --help')", cmd->name, o->name, val, why, cmd->name);
    return VG_ERR_ARG;
}

/* VG_OPT_ENUM tables name the enum's default at [0]: not a choice of its own. */
static int first_choice(const vg_opt *o) { return o->kind == VG_OPT_ENUM ? 1 : 0; }

static vg_status set_value(const vg_cmd *cmd, const vg_opt *o, const char *val)
{
    char *end;
    switch (o->kind) {
    case VG_OPT_INT: {
        errno = 0;
        long v = strtol(val, &end, 10);
        if (!*val || *end || errno || v < -2147483647L || v > 2147483647L)
            return bad(cmd, o, val, "is not an integer");
        if (!in_range(o, (double)v)) {
            char why[96];
            snprintf(why, sizeof why, "is out of range [%g, %g]", o->min, o->max);
            return bad(cmd, o, val, why);
        }
        *(int *)o->dest = (int)v;
        return VG_OK;
    }
    case VG_OPT_FLOAT: {
        errno = 0;
        double v = strtod(val, &end);
        if (!*val || *end || errno || !isfinite(v))
            return bad(cmd, o, val, "is not a number");
        if (!in_range(o, v)) {
            char why[96];
            snprintf(why, sizeof why, "is out of range [%g, %g]", o->min, o->max);
            return bad(cmd, o, val, why);
        }
        *(double *)o->dest = v;
        return VG_OK;
    }
    case VG_OPT_STRING:
        if (!*val)
            return bad(cmd, o, val, "is empty");
        *(const char **)o->dest = val;
        return VG_OK;
    case VG_OPT_SIZE: {
        long w = strtol(val, &end, 10), h = 0;
        if (*end == 'x' || *end == 'X')
            h = strtol(end + 1, &end, 10);
        if (*end || w < 16 || h < 16 || w > 8192 || h > 8192)
            return bad(cmd, o, val, "is not a size WxH between 16x16 and 8192x8192");
        ((int *)o->dest)[0] = (int)w;
        ((int *)o->dest)[1] = (int)h;
        return VG_OK;
    }
    case VG_OPT_CHOICE:
    case VG_OPT_ENUM:
        for (int i = first_choice(o); o->choices[i]; i++)
            if (!strcmp(o->choices[i], val)) {
                *(int *)o->dest = i;
                return VG_OK;
            }
        {
            char why[256] = "is not one of:";
            for (int i = first_choice(o); o->choices[i]; i++) {
                strncat(why, " ", sizeof why - strlen(why) - 1);
                strncat(why, o->choices[i], sizeof why - strlen(why) - 1);
            }
            return bad(cmd, o, val, why);
        }
    default:
        return VG_ERR_ARG;
    }
}

/* An option given twice: a file or name (--out a --out b) is ambiguous and
 * refused; a number or choice given again is an override, and the line says
 * which value counts. The same value twice is harmless. */
static vg_status repeated(const vg_cmd *cmd, const vg_opt *o, const char *before, const char *val)
{
    if (!strcmp(before, val))
        return VG_OK;
    if (o->kind == VG_OPT_STRING) {
        vg_error("%s: %s given twice ('%s', then '%s'): give it once (see 'vergence %s --help')", cmd->name,
                 o->name, before, val, cmd->name);
        return VG_ERR_ARG;
    }
    vg_warn("%s: %s given twice: the last, '%s', counts ('%s' is ignored)", cmd->name, o->name, val, before);
    return VG_OK;
}

vg_status vg_cli_parse(const vg_cmd *cmd, int argc, char **argv, bool *help)
{
    *help = false;
    /* The value each option was given, to find one given twice. */
    const char **given = cmd->opt_count > 0 ? calloc((size_t)cmd->opt_count, sizeof *given) : NULL;
    vg_status st = cmd->opt_count > 0 && !given ? VG_ERR_NOMEM : VG_OK;
    for (int i = 1; i < argc && st == VG_OK; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            vg_cli_print_help(cmd, stdout);
            *help = true;
            free(given);
            return VG_OK;
        }
        if (strncmp(a, "--", 2) != 0) {
            vg_error("%s: unexpected argument '%s' (see 'vergence %s --help')", cmd->name, a, cmd->name);
            st = VG_ERR_ARG;
            break;
        }
        const char *eq = strchr(a, '=');
        size_t len = eq ? (size_t)(eq - a) : strlen(a);
        const vg_opt *o = find(cmd, a, len);
        if (!o) {
            vg_error("%s: unknown option '%.*s' (see 'vergence %s --help')", cmd->name, (int)len, a, cmd->name);
            st = VG_ERR_ARG;
            break;
        }
        if (o->kind == VG_OPT_FLAG) {
            if (eq) {
                vg_error("%s: %s takes no value", cmd->name, o->name);
                st = VG_ERR_ARG;
                break;
            }
            *(bool *)o->dest = true;
            continue;
        }
        const char *val = eq ? eq + 1 : (i + 1 < argc ? argv[++i] : NULL);
        if (!val) {
            vg_error("%s: %s needs a value %s", cmd->name, o->name, o->metavar ? o->metavar : "");
            st = VG_ERR_ARG;
            break;
        }
        const char **seen = &given[o - cmd->opts];
        if (*seen && (st = repeated(cmd, o, *seen, val)) != VG_OK)
            break;
        *seen = val;
        st = set_value(cmd, o, val);
    }
    free(given);
    return st;
}

vg_status vg_cli_require(const vg_cmd *cmd, const char *name, const void *value_set)
{
    if (value_set)
        return VG_OK;
    vg_error("%s: %s is required (see 'vergence %s --help')", cmd->name, name, cmd->name);
    return VG_ERR_ARG;
}

void vg_cli_print_help(const vg_cmd *cmd, FILE *out)
{
    fprintf(out, "usage: %s\n\n%s\n", cmd->usage, cmd->summary);
    if (cmd->details)
        fprintf(out, "\n%s\n", cmd->details);
    fprintf(out, "\noptions:\n");
    for (int i = 0; i < cmd->opt_count; i++) {
        const vg_opt *o = &cmd->opts[i];
        char left[64];
        snprintf(left, sizeof left, "%s%s%s", o->name, o->metavar ? " " : "", o->metavar ? o->metavar : "");
        fprintf(out, "  %-24s %s", left, o->help);
        if (o->kind == VG_OPT_CHOICE || o->kind == VG_OPT_ENUM) {
            fprintf(out, " (");
            for (int c = first_choice(o); o->choices[c]; c++)
                fprintf(out, "%s%s", c > first_choice(o) ? ", " : "", o->choices[c]);
            fprintf(out, ")");
        }
        fputc('\n', out);
    }
    fprintf(out, "  %-24s %s\n", "--help", "show this help");
}
