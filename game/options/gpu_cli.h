/* vergence — options and start-up shared by the commands that use the GPU. */
#pragma once
#include <stdbool.h>

#include "core/cli.h"
#include "gpu/gpu.h"

typedef struct gpu_cli {
    int device;        /* --gpu N, -1 = automatic */
    bool validate;     /* --validate */
} gpu_cli;

#define GPU_CLI_OPTIONS(g)                                                                         \
    {"--gpu", VG_OPT_INT, &(g).device, "N", "use Vulkan device N (see 'vergence info'); default: a "   \
                                           "discrete GPU if present, else the best other", NULL, 0, 63}, \
    {"--validate", VG_OPT_FLAG, &(g).validate, NULL, "enable the Khronos validation layer (also "        \
                                                    "VERGENCE_VALIDATE=1); any message fails the run", NULL, 0, 0}

/* Creates the context, or logs why not. */
vg_status gpu_cli_open(const gpu_cli *opts, bool need_swapchain, gpu **out);
/* Destroys the context and turns validation messages into a failure:
 * returns the exit code for `st` (VG_ERR_VALIDATION when messages appeared). */
int gpu_cli_close(gpu *g, vg_status st);
/* The same, as a status (VG_ERR_VALIDATION when messages appeared). */
vg_status gpu_cli_release(gpu *g, vg_status st);
