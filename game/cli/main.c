/* vergence — entry point: git-style subcommands.
 *
 *   vergence <command> [options]     vergence <command> --help
 */
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "core/fault.h"
#include "core/log.h"

static const vg_cmd *const g_commands[] = {
    &vg_cmd_info,
    &vg_cmd_capture,
    &vg_cmd_optimize,
    &vg_cmd_play, &vg_cmd_study,
    &vg_cmd_bake_curve,
    &vg_cmd_demo,
    &vg_cmd_bench,
};
#define COMMAND_COUNT (int)(sizeof g_commands / sizeof g_commands[0])

static void print_usage(FILE *out)
{
    fprintf(out,
            "usage: vergence <command> [options]\n\n"
            "A Vulkan stereo engine that compresses disparity for comfort while keeping\n"
            "motion in depth faithful (Kellnhofer et al., \"Optimizing Disparity for\n"
            "Motion in Depth\").\n\ncommands:\n");
    for (int i = 0; i < COMMAND_COUNT; i++)
        fprintf(out, "  %-12s %s\n", g_commands[i]->name, g_commands[i]->summary);
    fprintf(out, "\nRun 'vergence <command> --help' for the options of a command.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        print_usage(stderr);
        return 2;
    }
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        print_usage(stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("vergence %s\n", VERGENCE_VERSION);
        return 0;
    }
    /* A test's fault that would not be injected is an error, not a pass. */
    if (vg_fault_check() != VG_OK)
        return 2;
    for (int i = 0; i < COMMAND_COUNT; i++)
        if (!strcmp(argv[1], g_commands[i]->name))
            return g_commands[i]->run(argc - 1, argv + 1);
    vg_error("'%s' is not a command (see 'vergence --help')", argv[1]);
    return 2;
}
