#include "gpu.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fault.h"
#include "core/log.h"

/* ------------------------------------------------------------------------- */
/* Errors and names                                                          */
/* ------------------------------------------------------------------------- */

const char *gpu_result_text(VkResult r)
{
    switch (r) {
#define R(x) case x: return #x;
        R(VK_SUCCESS) R(VK_NOT_READY) R(VK_TIMEOUT) R(VK_INCOMPLETE) R(VK_SUBOPTIMAL_KHR)
        R(VK_ERROR_OUT_OF_HOST_MEMORY) R(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        R(VK_ERROR_INITIALIZATION_FAILED) R(VK_ERROR_DEVICE_LOST) R(VK_ERROR_MEMORY_MAP_FAILED)
        R(VK_ERROR_LAYER_NOT_PRESENT) R(VK_ERROR_EXTENSION_NOT_PRESENT)
        R(VK_ERROR_FEATURE_NOT_PRESENT) R(VK_ERROR_INCOMPATIBLE_DRIVER)
        R(VK_ERROR_TOO_MANY_OBJECTS) R(VK_ERROR_FORMAT_NOT_SUPPORTED) R(VK_ERROR_SURFACE_LOST_KHR)
        R(VK_ERROR_OUT_OF_DATE_KHR) R(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR)
#undef R
    default:
        return "VkResult(unknown)";
    }
}

const char *gpu_device_type_text(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
    }
}

void gpu_report_failure(const char *file, int line, const char *call, VkResult r)
{
    if (r == VK_ERROR_DEVICE_LOST)
        vg_error("the Vulkan device was lost (%s at %s:%d); the GPU driver reset or crashed", call,
                 file, line);
    else
        vg_error("%s:%d: %s failed: %s", file, line, call, gpu_result_text(r));
}

VkResult gpu_queue_submit(gpu *g, VkCommandBuffer cmd, VkSemaphore wait, VkPipelineStageFlags2 wait_stage,
                          VkSemaphore signal, VkFence fence)
{
    if (g->lost_at > 0 && ++g->submits >= g->lost_at)
        return VK_ERROR_DEVICE_LOST;
    VkSemaphoreSubmitInfo w = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO, .semaphore = wait,
                               .stageMask = wait_stage},
                          s = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_SUBMIT_INFO, .semaphore = signal,
                               .stageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT};
    VkCommandBufferSubmitInfo c = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO, .commandBuffer = cmd};
    VkSubmitInfo2 submit = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO_2,
        .waitSemaphoreInfoCount = wait ? 1 : 0,
        .pWaitSemaphoreInfos = wait ? &w : NULL,
        .commandBufferInfoCount = 1,
        .pCommandBufferInfos = &c,
        .signalSemaphoreInfoCount = signal ? 1 : 0,
        .pSignalSemaphoreInfos = signal ? &s : NULL,
    };
    return vkQueueSubmit2(g->queue, 1, &submit, fence);
}

void gpu_set_name(const gpu *g, VkObjectType type, uint64_t handle, const char *fmt, ...)
{
    if (!g->set_object_name || !handle)
        return;
    char name[128];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(name, sizeof name, fmt, ap);
    va_end(ap);
    VkDebugUtilsObjectNameInfoEXT info = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT,
        .objectType = type,
        .objectHandle = handle,
        .pObjectName = name,
    };
    g->set_object_name(g->device, &info);
}

void gpu_cmd_label_begin(const gpu *g, VkCommandBuffer cmd, const char *name)
{
    if (g->cmd_begin_label)
        g->cmd_begin_label(cmd, &(VkDebugUtilsLabelEXT){.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT,
                                                        .pLabelName = name});
}

void gpu_cmd_label_end(const gpu *g, VkCommandBuffer cmd)
{
    if (g->cmd_end_label)
        g->cmd_end_label(cmd);
}

/* The debug-utils entry points of an instance that enabled the extension. */
static void load_debug_utils(gpu *g)
{
    g->set_object_name =
        (PFN_vkSetDebugUtilsObjectNameEXT)vkGetInstanceProcAddr(g->instance, "vkSetDebugUtilsObjectNameEXT");
    g->cmd_begin_label =
        (PFN_vkCmdBeginDebugUtilsLabelEXT)vkGetInstanceProcAddr(g->instance, "vkCmdBeginDebugUtilsLabelEXT");
    g->cmd_end_label = (PFN_vkCmdEndDebugUtilsLabelEXT)vkGetInstanceProcAddr(g->instance, "vkCmdEndDebugUtilsLabelEXT");
    if (!g->cmd_begin_label || !g->cmd_end_label)
        g->cmd_begin_label = NULL, g->cmd_end_label = NULL;
}

/* ------------------------------------------------------------------------- */
/* Instance and validation                                                   */
/* ------------------------------------------------------------------------- */

static int g_validation_messages;

static VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                       VkDebugUtilsMessageTypeFlagsEXT types,
                                                       const VkDebugUtilsMessengerCallbackDataEXT *data,
                                                       void *user)
{
    (void)user;
    /* The loader also sends ~90 INFO/VERBOSE lines per run: count only what
     * the validation layer flags as a warning or an error (PLATFORM.md). */
    bool serious = severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT);
    if (serious && (types & (VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                             VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT))) {
        __atomic_add_fetch(&g_validation_messages, 1, __ATOMIC_RELAXED);
        vg_log(VG_LOG_ERROR, "validation: %s", data->pMessage);
    }
    return VK_FALSE;
}

static bool has_layer(const char *name)
{
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, NULL);
    VkLayerProperties *props = calloc(n ? n : 1, sizeof *props);
    vkEnumerateInstanceLayerProperties(&n, props);
    bool found = false;
    for (uint32_t i = 0; i < n && !found; i++)
        found = !strcmp(props[i].layerName, name);
    free(props);
    return found;
}

static bool has_instance_extension(const char *name)
{
    uint32_t n = 0;
    vkEnumerateInstanceExtensionProperties(NULL, &n, NULL);
    VkExtensionProperties *props = calloc(n ? n : 1, sizeof *props);
    vkEnumerateInstanceExtensionProperties(NULL, &n, props);
    bool found = false;
    for (uint32_t i = 0; i < n && !found; i++)
        found = !strcmp(props[i].extensionName, name);
    free(props);
    return found;
}

static bool env_flag(const char *name, bool fallback)
{
    const char *v = getenv(name);
    if (!v || !*v)
        return fallback;
    return strcmp(v, "0") != 0;
}

static vg_status create_instance(gpu *g, const gpu_desc *desc)
{
    uint32_t version = 0;
    if (vkEnumerateInstanceVersion(&version) != VK_SUCCESS || version < VK_API_VERSION_1_3) {
        vg_error("the Vulkan loader supports %u.%u; vergence needs Vulkan 1.3", VK_API_VERSION_MAJOR(version),
                 VK_API_VERSION_MINOR(version));
        return VG_ERR_DEVICE;
    }
    const char *exts[16];
    uint32_t ext_count = 0;
    for (uint32_t i = 0; i < desc->instance_extension_count && ext_count < 12; i++)
        exts[ext_count++] = desc->instance_extensions[i];
    g->debug_utils = has_instance_extension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (g->debug_utils)
        exts[ext_count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;

    const char *layers[1];
    uint32_t layer_count = 0;
    if (g->validation) {
        if (!has_layer("VK_LAYER_KHRONOS_validation") || !g->debug_utils) {
            vg_error("validation requested but VK_LAYER_KHRONOS_validation is not installed "
                     "(Debian package vulkan-validationlayers)");
            return VG_ERR_DEVICE;
        }
        layers[layer_count++] = "VK_LAYER_KHRONOS_validation";
    }

    VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features = {
        .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
        .enabledValidationFeatureCount = 1,
        .pEnabledValidationFeatures = enables,
    };
    VkDebugUtilsMessengerCreateInfoEXT messenger_info = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .pNext = g->validation && g->sync_validation ? &features : NULL,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_debug_message,
        .pUserData = g,
    };
    VkApplicationInfo app = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = "vergence",
        .pEngineName = "vergence",
        .apiVersion = VK_API_VERSION_1_3,
    };
    VkInstanceCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        .pNext = g->validation ? &messenger_info : NULL,
        .pApplicationInfo = &app,
        .enabledLayerCount = layer_count,
        .ppEnabledLayerNames = layers,
        .enabledExtensionCount = ext_count,
        .ppEnabledExtensionNames = exts,
    };
    VkResult r = vkCreateInstance(&info, NULL, &g->instance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER) {
        vg_error("no Vulkan driver is installed: install mesa-vulkan-drivers (lavapipe, any CPU) or your GPU's "
                 "Vulkan driver");
        return VG_ERR_DEVICE;
    }
    if (r == VK_ERROR_LAYER_NOT_PRESENT) {
        vg_error("the Khronos validation layer is not installed (install vulkan-validationlayers, or run without "
                 "--validate / VERGENCE_VALIDATE)");
        return VG_ERR_DEVICE;
    }
    if (r != VK_SUCCESS) {
        gpu_report_failure(__FILE__, __LINE__, "vkCreateInstance", r);
        return VG_ERR_VULKAN;
    }
    if (g->validation) {
        messenger_info.pNext = NULL;
        PFN_vkCreateDebugUtilsMessengerEXT create = (PFN_vkCreateDebugUtilsMessengerEXT)
            vkGetInstanceProcAddr(g->instance, "vkCreateDebugUtilsMessengerEXT");
        VK_TRY(create(g->instance, &messenger_info, NULL, &g->messenger));
    }
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Device choice and features                                                */
/* ------------------------------------------------------------------------- */

static int device_rank(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
    }
}

static bool device_has_extension(VkPhysicalDevice p, const char *name)
{
    uint32_t n = 0;
    vkEnumerateDeviceExtensionProperties(p, NULL, &n, NULL);
    VkExtensionProperties *props = calloc(n ? n : 1, sizeof *props);
    vkEnumerateDeviceExtensionProperties(p, NULL, &n, props);
    bool found = false;
    for (uint32_t i = 0; i < n && !found; i++)
        found = !strcmp(props[i].extensionName, name);
    free(props);
    return found;
}

static int find_queue_family(VkPhysicalDevice p)
{
    uint32_t n = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(p, &n, NULL);
    VkQueueFamilyProperties q[16];
    n = n > 16 ? 16 : n;
    vkGetPhysicalDeviceQueueFamilyProperties(p, &n, q);
    for (uint32_t i = 0; i < n; i++)
        if ((q[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
            (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT))
            return (int)i;
    return -1;
}

/* Counts every requirement the device lacks (or VERGENCE_DISABLE takes
 * away) and names the first `cap` of them. */
uint32_t gpu_missing_features(VkPhysicalDevice p, bool need_swapchain, bool need_tessellation, const char **names,
                              uint32_t cap)
{
    uint32_t n = 0;
#define LACKS(name)                                                                                                    \
    do {                                                                                                               \
        if (n < cap)                                                                                                   \
            names[n] = (name);                                                                                         \
        n++;                                                                                                           \
    } while (0)
/* A requirement the device lacks, or VERGENCE_DISABLE takes away (core/fault.h). */
#define REQUIRE(has, name)                                                                                             \
    do {                                                                                                               \
        if (!(has) || vg_fault_disabled(name))                                                                         \
            LACKS(name);                                                                                               \
    } while (0)
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(p, &props);
    if (props.apiVersion < VK_API_VERSION_1_3) {
        LACKS("Vulkan 1.3"); /* its feature structures cannot be asked for; the rest can */
    } else {
        VkPhysicalDeviceVulkan13Features f13 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
        VkPhysicalDeviceVulkan12Features f12 = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
                                                .pNext = &f13};
        VkPhysicalDeviceFeatures2 f = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &f12};
        vkGetPhysicalDeviceFeatures2(p, &f);
        REQUIRE(f13.dynamicRendering, "dynamicRendering");
        REQUIRE(f13.synchronization2, "synchronization2");
        REQUIRE(f13.maintenance4, "maintenance4");
        REQUIRE(f12.hostQueryReset, "hostQueryReset");
        REQUIRE(f12.scalarBlockLayout, "scalarBlockLayout");
        REQUIRE(f.features.shaderStorageImageWriteWithoutFormat, "shaderStorageImageWriteWithoutFormat");
        REQUIRE(f.features.drawIndirectFirstInstance, "drawIndirectFirstInstance");
    }
    if (need_tessellation) {
        VkPhysicalDeviceFeatures f10;
        vkGetPhysicalDeviceFeatures(p, &f10);
        if (!f10.tessellationShader || vg_fault_disabled("tessellation"))
            LACKS("tessellationShader");
    }
    REQUIRE(device_has_extension(p, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME), VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
    if (need_swapchain)
        REQUIRE(device_has_extension(p, VK_KHR_SWAPCHAIN_EXTENSION_NAME), VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    if (find_queue_family(p) < 0) LACKS("a graphics+compute queue");
#undef REQUIRE
#undef LACKS
    return n;
}

const char *gpu_missing_feature(VkPhysicalDevice p, bool need_swapchain)
{
    const char *first = NULL;
    return gpu_missing_features(p, need_swapchain, false, &first, 1) ? first : NULL;
}

static vg_status pick_device(gpu *g, const gpu_desc *desc)
{
    uint32_t n = 0;
    VK_TRY(vkEnumeratePhysicalDevices(g->instance, &n, NULL));
    if (n == 0) {
        vg_error("no Vulkan device found (install mesa-vulkan-drivers for lavapipe)");
        return VG_ERR_DEVICE;
    }
    VkPhysicalDevice devs[16];
    n = n > 16 ? 16 : n;
    VK_TRY(vkEnumeratePhysicalDevices(g->instance, &n, devs));

    bool forced = desc->use_device;
    if (forced && (desc->device_index < 0 || (uint32_t)desc->device_index >= n)) {
        vg_error("--gpu %d: there are only %u Vulkan devices (see 'vergence info')", desc->device_index, n);
        return VG_ERR_ARG;
    }
    int best = -1, best_rank = -1;
    const char *why = NULL;
    for (uint32_t i = 0; i < n; i++) {
        if (forced && i != (uint32_t)desc->device_index)
            continue;
        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(devs[i], &props);
        const char *missing = gpu_missing_feature(devs[i], desc->need_swapchain);
        if (missing) {
            why = missing;
            if (forced) {
                vg_error("device %u (%s) lacks %s, which vergence needs", i, props.deviceName, missing);
                return VG_ERR_DEVICE;
            }
            continue;
        }
        if (device_rank(props.deviceType) > best_rank) {
            best = (int)i;
            best_rank = device_rank(props.deviceType);
        }
    }
    if (best < 0) {
        vg_error("no Vulkan device has everything vergence needs: missing %s", why);
        return VG_ERR_DEVICE;
    }
    g->phys = devs[best];
    g->device_index = (uint32_t)best;
    vkGetPhysicalDeviceProperties(g->phys, &g->props);
    vkGetPhysicalDeviceMemoryProperties(g->phys, &g->mem);
    g->is_cpu = g->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    g->queue_family = (uint32_t)find_queue_family(g->phys);
    return VG_OK;
}

static vg_status create_device(gpu *g, const gpu_desc *desc)
{
    VkPhysicalDeviceVulkan12Features f12q = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceVulkan11Features f11q = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES,
                                             .pNext = &f12q};
    VkPhysicalDeviceFeatures2 fq = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, .pNext = &f11q};
    vkGetPhysicalDeviceFeatures2(g->phys, &fq);
    g->features = (gpu_features){
        .tessellation = fq.features.tessellationShader,
        .multiview = f11q.multiview,
        .multiview_tessellation = f11q.multiviewTessellationShader,
        .timestamps = g->props.limits.timestampComputeAndGraphics,
        .fill_mode_non_solid = fq.features.fillModeNonSolid,
        .multi_draw_indirect = fq.features.multiDrawIndirect,
        .draw_indirect_count = f12q.drawIndirectCount,
    };

    /* Tests pretend a feature is missing, and make the device fail (core/fault.h). */
    vg_status fst = vg_fault_check();
    if (fst != VG_OK)
        return fst;
    if (vg_fault_disabled("tessellation"))
        g->features.tessellation = g->features.multiview_tessellation = false;
    if (vg_fault_disabled("multiview"))
        g->features.multiview = g->features.multiview_tessellation = false;
    if (vg_fault_disabled("timestamps"))
        g->features.timestamps = false;
    if (vg_fault_disabled("indirect"))
        g->features.multi_draw_indirect = g->features.draw_indirect_count = false;
    const char *off = getenv("VERGENCE_DISABLE");
    if (off && *off)
        vg_warn("VERGENCE_DISABLE=%s: pretending the device lacks these features", off);
    long lost = vg_fault("device-lost");
    if (lost >= 1) {
        g->lost_at = lost;
        vg_warn("VERGENCE_FAULT: queue submission %ld and later will fail as a lost device", lost);
    }

    VkPhysicalDeviceVulkan13Features f13 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES,
        .dynamicRendering = VK_TRUE,
        .synchronization2 = VK_TRUE,
        .maintenance4 = VK_TRUE,
    };
    VkPhysicalDeviceVulkan12Features f12 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
        .pNext = &f13,
        .hostQueryReset = VK_TRUE,
        .scalarBlockLayout = VK_TRUE,
        .drawIndirectCount = g->features.draw_indirect_count,
    };
    VkPhysicalDeviceVulkan11Features f11 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES,
        .pNext = &f12,
        .multiview = g->features.multiview,
        .multiviewTessellationShader = g->features.multiview_tessellation,
    };
    VkPhysicalDeviceFeatures2 f = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
        .pNext = &f11,
        .features = {
            .tessellationShader = g->features.tessellation,
            .fillModeNonSolid = g->features.fill_mode_non_solid,
            .multiDrawIndirect = g->features.multi_draw_indirect,
            .shaderStorageImageWriteWithoutFormat = VK_TRUE,
            .drawIndirectFirstInstance = VK_TRUE, /* the warp's patch index (warp.compact) */
        },
    };
    const char *exts[2] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME, VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
        .queueFamilyIndex = g->queue_family,
        .queueCount = 1,
        .pQueuePriorities = &priority,
    };
    VkDeviceCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .pNext = &f,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &queue,
        .enabledExtensionCount = desc->need_swapchain ? 2 : 1,
        .ppEnabledExtensionNames = exts,
    };
    VK_TRY(vkCreateDevice(g->phys, &info, NULL, &g->device));
    vkGetDeviceQueue(g->device, g->queue_family, 0, &g->queue);
    g->cmd_push_descriptor_set =
        (PFN_vkCmdPushDescriptorSetKHR)vkGetDeviceProcAddr(g->device, "vkCmdPushDescriptorSetKHR");
    if (g->debug_utils)
        load_debug_utils(g);
    GPU_NAME(g, VK_OBJECT_TYPE_DEVICE, g->device, "vergence device");
    GPU_NAME(g, VK_OBJECT_TYPE_QUEUE, g->queue, "main queue");

    VkCommandPoolCreateInfo pool = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
        .queueFamilyIndex = g->queue_family,
    };
    VK_TRY(vkCreateCommandPool(g->device, &pool, NULL, &g->pool));
    GPU_NAME(g, VK_OBJECT_TYPE_COMMAND_POOL, g->pool, "main command pool");
    return VG_OK;
}

vg_status gpu_create(const gpu_desc *desc, gpu **out)
{
    *out = NULL;
    gpu *g = calloc(1, sizeof *g);
    if (!g)
        return VG_ERR_NOMEM;
    g->validation = desc->validate || env_flag("VERGENCE_VALIDATE", false);
    g->sync_validation = env_flag("VERGENCE_SYNC_VALIDATION", true);
    vg_status st = create_instance(g, desc);
    if (st == VG_OK)
        st = pick_device(g, desc);
    if (st == VG_OK)
        st = create_device(g, desc);
    if (st != VG_OK) {
        gpu_destroy(g);
        return st;
    }
    *out = g;
    return VG_OK;
}

vg_status gpu_import(const gpu_import_desc *desc, gpu **out)
{
    *out = NULL;
    const char *missing = gpu_missing_feature(desc->physical_device, false);
    if (missing) {
        vg_error("the host's device lacks %s, which vergence needs", missing);
        return VG_ERR_DEVICE;
    }
    gpu *g = calloc(1, sizeof *g);
    if (!g)
        return VG_ERR_NOMEM;
    g->imported = true;
    g->alloc = desc->alloc;
    if (desc->hooks.allocate && desc->hooks.free)
        g->hooks = desc->hooks;
    g->instance = desc->instance;
    g->phys = desc->physical_device;
    g->device = desc->device;
    g->queue_family = desc->queue_family;
    vkGetPhysicalDeviceProperties(g->phys, &g->props);
    vkGetPhysicalDeviceMemoryProperties(g->phys, &g->mem);
    g->is_cpu = g->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    g->features.timestamps = g->props.limits.timestampComputeAndGraphics;
    vkGetDeviceQueue(g->device, g->queue_family, desc->queue_index, &g->queue);
    g->cmd_push_descriptor_set =
        (PFN_vkCmdPushDescriptorSetKHR)vkGetDeviceProcAddr(g->device, "vkCmdPushDescriptorSetKHR");
    /* Names and labels only when the host says its instance enabled debug
     * utils (VGX_CONTEXT_DEBUG_UTILS): its entry points are not to be called
     * otherwise. */
    g->debug_utils = desc->debug_utils;
    if (g->debug_utils)
        load_debug_utils(g);
    VkCommandPoolCreateInfo pool = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
        .queueFamilyIndex = g->queue_family,
    };
    if (!g->cmd_push_descriptor_set) {
        vg_error("the host's device was created without %s, which vergence needs",
                 VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME);
        free(g);
        return VG_ERR_DEVICE;
    }
    VkResult r = vkCreateCommandPool(g->device, &pool, g->alloc, &g->pool);
    if (r != VK_SUCCESS) {
        gpu_report_failure(__FILE__, __LINE__, "vkCreateCommandPool", r);
        free(g);
        return VG_ERR_VULKAN;
    }
    GPU_NAME(g, VK_OBJECT_TYPE_COMMAND_POOL, g->pool, "vgx command pool");
    *out = g;
    return VG_OK;
}

void gpu_destroy(gpu *g)
{
    if (!g)
        return;
    if (g->imported) {
        if (g->pool)
            vkDestroyCommandPool(g->device, g->pool, g->alloc);
        free(g);
        return;
    }
    if (g->device) {
        vkDeviceWaitIdle(g->device);
        if (g->pool)
            vkDestroyCommandPool(g->device, g->pool, NULL);
        vkDestroyDevice(g->device, NULL);
    }
    if (g->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT destroy = (PFN_vkDestroyDebugUtilsMessengerEXT)
            vkGetInstanceProcAddr(g->instance, "vkDestroyDebugUtilsMessengerEXT");
        destroy(g->instance, g->messenger, NULL);
    }
    if (g->instance)
        vkDestroyInstance(g->instance, NULL);
    free(g);
}

int gpu_validation_messages(void)
{
    return __atomic_load_n(&g_validation_messages, __ATOMIC_RELAXED);
}
