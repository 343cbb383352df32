/* Command-line parsing: the input is split at NUL bytes into argv and parsed
 * against a table with every kind of option. */
#include <stdlib.h>
#include <string.h>

#include "core/cli.h"
#include "core/log.h"
#include "fuzz.h"

static const char *const k_choices[] = {"warp", "cameras", "imagewarp", NULL};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vg_log_set_silent(true);
    if (size > 4096)
        return 0;
    bool flag = false;
    int integer = 0, choice = 0, wh[2] = {0, 0};
    double number = 0;
    const char *string = NULL;
    const vg_opt opts[] = {
        {"--flag", VG_OPT_FLAG, &flag, NULL, "a flag", NULL, 0, 0},
        {"--int", VG_OPT_INT, &integer, "N", "an integer", NULL, 1, 1000},
        {"--float", VG_OPT_FLOAT, &number, "X", "a number", NULL, -1, 1},
        {"--string", VG_OPT_STRING, &string, "S", "a string", NULL, 0, 0},
        {"--size", VG_OPT_SIZE, wh, "WxH", "a size", NULL, 0, 0},
        {"--choice", VG_OPT_CHOICE, &choice, "C", "a choice", k_choices, 0, 0},
    };
    const vg_cmd cmd = {.name = "fuzz", .summary = "", .usage = "fuzz", .opts = opts,
                        .opt_count = sizeof opts / sizeof opts[0]};
    /* argv[0] is the command; the rest are the NUL-separated pieces. */
    char *buf = malloc(size + 1);
    char *argv[256] = {"fuzz"};
    int argc = 1;
    memcpy(buf, data, size);
    buf[size] = 0;
    for (size_t i = 0; i <= size && argc < 255;) {
        argv[argc++] = buf + i;
        i += strlen(buf + i) + 1;
    }
    bool help;
    vg_cli_parse(&cmd, argc, argv, &help);
    free(buf);
    return 0;
}
