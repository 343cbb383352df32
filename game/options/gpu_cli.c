#include "gpu_cli.h"

#include "core/log.h"

vg_status gpu_cli_open(const gpu_cli *opts, bool need_swapchain, gpu **out)
{
    return gpu_create(&(gpu_desc){
        .validate = opts->validate,
        .use_device = opts->device >= 0,
        .device_index = opts->device,
        .need_swapchain = need_swapchain,
    }, out);
}

vg_status gpu_cli_release(gpu *g, vg_status st)
{
    int before = gpu_validation_messages();
    gpu_destroy(g);
    int messages = gpu_validation_messages();
    if (messages > before)
        vg_error("validation reported %d message(s) while shutting down", messages - before);
    if (messages > 0 && st == VG_OK) {
        vg_error("validation reported %d message(s): failing the run", messages);
        st = VG_ERR_VALIDATION;
    }
    return st;
}

int gpu_cli_close(gpu *g, vg_status st)
{
    return vg_status_exit_code(gpu_cli_release(g, st));
}
