/* vergence — the display calibration shared by every command. */
#include "display_cli.h"

#include <math.h>
#include <string.h>

#include "core/json_read.h"
#include "core/log.h"

/* 16:9: width = diagonal * 16 / sqrt(16^2 + 9^2). */
static const double k_width_per_diagonal = 16.0 / 18.357559750685819;

static vg_status bad(const char *file, const char *what)
{
    vg_error("--display %s: %s", file, what);
    return VG_ERR_FORMAT;
}

static vg_status number(const char *file, const vg_jvalue *v, const char *key, double lo, double hi, double *out)
{
    char why[160];
    if (v->type != VG_JNUMBER || !(v->number >= lo && v->number <= hi)) {
        snprintf(why, sizeof why, "\"%s\" must be a number in [%g, %g]", key, lo, hi);
        return bad(file, why);
    }
    if (*out == 0) /* a flag given wins */
        *out = v->number;
    return VG_OK;
}

void display_cli_renames(const char *cmd, int argc, char **argv)
{
    static const char *const k_old[][2] = {{"--display-diagonal", "--screen-diagonal-in"},
                                           {"--display-resolution", "--screen-resolution"},
                                           {"--display-distance", "--distance-m"},
                                           {"--display-ipd", "--ipd-m"}};
    for (int i = 1; i < argc; i++)
        for (size_t k = 0; k < sizeof k_old / sizeof k_old[0]; k++) {
            size_t n = strlen(k_old[k][0]);
            if (strncmp(argv[i], k_old[k][0], n) || (argv[i][n] && argv[i][n] != '='))
                continue;
            vg_warn("%s: %s is deprecated: use %s", cmd, k_old[k][0], k_old[k][1]);
            if (!argv[i][n]) {
                argv[i] = (char *)k_old[k][1];
            } else { /* --old=value: the new name before the same value */
                static char buf[8][96];
                static int used;
                char *b = buf[used++ % 8];
                snprintf(b, sizeof buf[0], "%s%s", k_old[k][1], argv[i] + n);
                argv[i] = b;
            }
        }
}

vg_status display_cli_load(display_cli *c)
{
    if (c->screen_width_m > 0 && c->diagonal_in > 0) {
        vg_error("--screen-width-m and --screen-diagonal-in both give the panel's size: give one");
        return VG_ERR_ARG;
    }
    if ((c->resolution[0] || c->resolution[1]) &&
        (c->resolution[0] < 16 || c->resolution[1] < 16 || c->resolution[0] > 65536 || c->resolution[1] > 65536)) {
        vg_error("--screen-resolution %dx%d: want 16..65536 pixels each way", c->resolution[0], c->resolution[1]);
        return VG_ERR_ARG;
    }
    if (!c->file)
        return VG_OK;
    vg_jdoc doc;
    vg_status st = vg_json_read_file(c->file, &doc);
    if (st != VG_OK)
        return st;
    const vg_jvalue *root = doc.root, *inner = vg_jget(root, "display");
    if (inner)
        root = inner;
    if (!root || root->type != VG_JOBJECT) {
        vg_jdoc_free(&doc);
        return bad(c->file, "not a JSON object (or one with a \"display\" object)");
    }
    bool sized = c->screen_width_m > 0 || c->diagonal_in > 0;
    double width = 0, diagonal = 0, px[2] = {c->resolution[0], c->resolution[1]};
    for (const vg_jvalue *m = root->child; m && st == VG_OK; m = m->next) {
        if (!strcmp(m->key, "diagonal_in"))
            st = number(c->file, m, m->key, 1, 1000, &diagonal);
        else if (!strcmp(m->key, "width_m"))
            st = number(c->file, m, m->key, 0.05, 20, &width);
        else if (!strcmp(m->key, "width_px"))
            st = number(c->file, m, m->key, 16, 65536, &px[0]);
        else if (!strcmp(m->key, "height_px"))
            st = number(c->file, m, m->key, 16, 65536, &px[1]);
        else if (!strcmp(m->key, "distance_m"))
            st = number(c->file, m, m->key, 0.05, 100, &c->distance_m);
        else if (!strcmp(m->key, "ipd_m"))
            st = number(c->file, m, m->key, 0.03, 0.09, &c->ipd_m);
        else if (strcmp(m->key, "height_m") && strcmp(m->key, "screen_vergence_arcmin")) {
            char why[160];
            snprintf(why, sizeof why, "unknown member \"%.60s\" (diagonal_in or width_m, width_px, height_px, "
                     "distance_m, ipd_m)", m->key);
            st = bad(c->file, why);
        }
    }
    vg_jdoc_free(&doc);
    if (st != VG_OK)
        return st;
    if (width > 0 && diagonal > 0 && fabs(width - diagonal * 0.0254 * k_width_per_diagonal) > 1e-3)
        return bad(c->file, "\"width_m\" and \"diagonal_in\" disagree for a 16:9 panel: give one");
    if (!sized) { /* the file's size unless a flag gave one */
        c->diagonal_in = diagonal;
        c->screen_width_m = diagonal > 0 ? 0 : width;
    }
    if ((px[0] > 0) != (px[1] > 0))
        return bad(c->file, "give both \"width_px\" and \"height_px\"");
    c->resolution[0] = (int)px[0];
    c->resolution[1] = (int)px[1];
    return VG_OK;
}

stereo_display_desc display_cli_desc(const display_cli *c)
{
    stereo_display_desc s = {.diagonal_in = c->diagonal_in, .res_x = c->resolution[0], .res_y = c->resolution[1],
                             .distance_m = c->distance_m, .ipd_m = c->ipd_m};
    if (c->screen_width_m > 0)
        s.diagonal_in = c->screen_width_m / k_width_per_diagonal / 0.0254;
    return s;
}
