/* vergence — injected faults. */
#include "fault.h"

#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "log.h"

static const char *const k_faults[] = {"device-lost", "enospc", "kill", "present-ms", NULL};
/* The engine's optional features, then the required ones as
 * gpu_missing_features names them (a test of the requirements query takes
 * several away at once). */
static const char *const k_features[] = {"tessellation", "multiview", "timestamps", "indirect", "dynamicRendering",
                                         "synchronization2", "maintenance4", "hostQueryReset", "scalarBlockLayout",
                                         "shaderStorageImageWriteWithoutFormat", "drawIndirectFirstInstance",
                                         "VK_KHR_push_descriptor", "VK_KHR_swapchain", NULL};

static bool listed(const char *const *names, const char *s, size_t n)
{
    for (int i = 0; names[i]; i++)
        if (strlen(names[i]) == n && !strncmp(names[i], s, n))
            return true;
    return false;
}

vg_status vg_fault_check(void)
{
    const char *f = getenv("VERGENCE_FAULT");
    for (const char *p = f && *f ? f : NULL; p;) {
        const char *end = strchr(p, ','), *colon = strchr(p, ':');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        char *num_end = NULL;
        errno = 0;
        long n = colon && colon < p + len ? strtol(colon + 1, &num_end, 10) : 0;
        if (errno == ERANGE) { /* strtol would clamp it to 2^63 - 1 without a word */
            vg_error("VERGENCE_FAULT=%s: '%.*s': the count is past %ld, the largest this build holds", f, (int)len, p,
                     LONG_MAX);
            return VG_ERR_ARG;
        }
        if (!colon || colon >= p + len || !listed(k_faults, p, (size_t)(colon - p)) || n < 1 ||
            num_end != p + len) {
            vg_error("VERGENCE_FAULT=%s: '%.*s' is not NAME:N with N >= 1 and NAME one of device-lost, enospc, kill, present-ms",
                     f, (int)len, p);
            return VG_ERR_ARG;
        }
        p = end ? end + 1 : NULL;
    }
    const char *d = getenv("VERGENCE_DISABLE");
    for (const char *p = d && *d ? d : NULL; p;) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (!listed(k_features, p, len)) {
            char all[512] = "";
            for (int i = 0; k_features[i]; i++)
                snprintf(all + strlen(all), sizeof all - strlen(all), "%s%s", i ? ", " : "", k_features[i]);
            vg_error("VERGENCE_DISABLE=%s: '%.*s' is not one of %s", d, (int)len, p, all);
            return VG_ERR_ARG;
        }
        p = end ? end + 1 : NULL;
    }
    return VG_OK;
}

long vg_fault(const char *name)
{
    const char *f = getenv("VERGENCE_FAULT");
    size_t n = strlen(name);
    for (const char *p = f && *f ? f : NULL; p;) {
        const char *end = strchr(p, ',');
        if (!strncmp(p, name, n) && p[n] == ':') {
            long v = strtol(p + n + 1, NULL, 10);
            return v >= 1 ? v : -1;
        }
        p = end ? end + 1 : NULL;
    }
    return -1;
}

bool vg_fault_disabled(const char *feature)
{
    const char *d = getenv("VERGENCE_DISABLE");
    size_t n = strlen(feature);
    for (const char *p = d && *d ? d : NULL; p;) {
        const char *end = strchr(p, ',');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        if (len == n && !strncmp(p, feature, n))
            return true;
        p = end ? end + 1 : NULL;
    }
    return false;
}

static size_t g_written;
static long g_files;

size_t vg_fault_write_allowance(size_t n)
{
    long budget = vg_fault("enospc");
    size_t allowed = n;
    if (budget >= 0)
        allowed = g_written >= (size_t)budget ? 0 : (size_t)budget - g_written < n ? (size_t)budget - g_written : n;
    g_written += allowed;
    return allowed;
}

void vg_fault_file_done(void)
{
    long kill_at = vg_fault("kill");
    if (kill_at >= 0 && ++g_files >= kill_at)
        raise(SIGKILL);
}
