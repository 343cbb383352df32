#include "commands.h"
#include "core/log.h"
static int run(int argc, char **argv) { (void)argc; (void)argv; vg_error("info: not built yet"); return 2; }
const vg_cmd vg_cmd_info = { .name = "info", .summary = "print the device, features and display model", .usage = "vergence info", .run = run };
