/* Placeholder until the CPU reference lands (issue 3). */
#include "commands.h"
#include "core/log.h"

static int run(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    vg_error("optimize: not built yet");
    return 2;
}

const vg_cmd vg_cmd_optimize = {
    .name = "optimize",
    .summary = "apply the motion-in-depth optimisation to disparity videos (not built yet)",
    .usage = "vergence optimize [options]",
    .run = run,
};
