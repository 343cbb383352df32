#include "commands.h"
#include "core/log.h"
static int run(int argc, char **argv) { (void)argc; (void)argv; vg_error("capture: not built yet"); return 2; }
const vg_cmd vg_cmd_capture = { .name = "capture", .summary = "print the device, features and display model", .usage = "vergence info", .run = run };
