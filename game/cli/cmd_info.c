/* vergence info — the devices, the features in use and the display model. */
#include <stdio.h>

#include "commands.h"
#include "core/log.h"
#include "options/gpu_cli.h"
#include "options/display_cli.h"
#include "stereo/stereo_display.h"

static gpu_cli g_gpu = {.device = -1};
static display_cli g_display;

static const vg_opt k_opts[] = {
    DISPLAY_CLI_OPTIONS(g_display),
    GPU_CLI_OPTIONS(g_gpu),
};

static void print_devices(const gpu *g)
{
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(g->instance, &n, NULL);
    VkPhysicalDevice devs[16];
    n = n > 16 ? 16 : n;
    vkEnumeratePhysicalDevices(g->instance, &n, devs);
    printf("devices:\n");
    for (uint32_t i = 0; i < n; i++) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(devs[i], &p);
        printf("  %c %u: %s (%s, Vulkan %u.%u.%u)\n", devs[i] == g->phys ? '*' : ' ', i, p.deviceName,
               gpu_device_type_text(p.deviceType), VK_API_VERSION_MAJOR(p.apiVersion),
               VK_API_VERSION_MINOR(p.apiVersion), VK_API_VERSION_PATCH(p.apiVersion));
    }
}

static int run(int argc, char **argv)
{
    bool help;
    if (vg_cli_parse(&vg_cmd_info, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    vg_status dst = display_cli_load(&g_display);
    if (dst != VG_OK)
        return vg_status_exit_code(dst);
    gpu *g;
    vg_status st = gpu_cli_open(&g_gpu, false, &g);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    printf("vergence %s\n", VERGENCE_VERSION);
    print_devices(g);
    const VkPhysicalDeviceLimits *l = &g->props.limits;
    printf("using: %s (%s)%s\n", g->props.deviceName, gpu_device_type_text(g->props.deviceType),
           g->is_cpu ? " - a CPU rasteriser: interactive modes pick cheaper settings" : "");
    printf("features in use:\n");
    printf("  required   Vulkan 1.3, dynamicRendering, synchronization2, maintenance4, scalarBlockLayout,\n"
           "             hostQueryReset, shaderStorageImageWriteWithoutFormat, drawIndirectFirstInstance,\n"
           "             VK_KHR_push_descriptor\n");
    printf("  tessellation            %s (max level %u)\n", g->features.tessellation ? "yes" : "no",
           l->maxTessellationGenerationLevel);
    printf("  multiview               %s (with tessellation: %s)\n", g->features.multiview ? "yes" : "no",
           g->features.multiview_tessellation ? "yes" : "no");
    printf("  timestamps              %s (period %.3g ns)\n", g->features.timestamps ? "yes" : "no",
           (double)l->timestampPeriod);
    printf("  wireframe               %s\n", g->features.fill_mode_non_solid ? "yes" : "no");
    printf("  validation              %s%s\n", g->validation ? "on" : "off",
           g->validation && g->sync_validation ? " (with synchronization validation)" : "");
    printf("  max image size          %u\n", l->maxImageDimension2D);
    stereo_display_desc dd = display_cli_desc(&g_display);
    stereo_display d;
    stereo_display_init(&d, &dd);
    bool given = g_display.file || g_display.screen_width_m > 0 || g_display.diagonal_in > 0 ||
                 g_display.resolution[0] || g_display.distance_m > 0 || g_display.ipd_m > 0;
    printf("display model (%s):\n", given ? "--display and the display flags, the rest the paper's" : "defaults, paper Sec. 5");
    printf("  panel                   %.3g\" 16:9, %dx%d, %.3f x %.3f m, pixel pitch %.3f mm\n",
           dd.diagonal_in > 0 ? dd.diagonal_in : 24.0, d.res_x, d.res_y, d.width_m, d.height_m, d.pitch_m * 1e3);
    printf("  viewing distance        %.2f m\n", d.distance_m);
    printf("  interocular distance    %.3f m\n", d.ipd_m);
    printf("  screen vergence         %.1f arcmin\n", d.screen_vergence);
    return gpu_cli_close(g, VG_OK);
}

const vg_cmd vg_cmd_info = {
    .name = "info",
    .summary = "print the Vulkan devices, the features in use and the display model",
    .usage = "vergence info [--gpu N] [--validate]",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
