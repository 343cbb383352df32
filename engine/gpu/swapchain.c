/* vergence — swapchain. */
#include "swapchain.h"

#include <string.h>

#include "core/log.h"

static void release(swapchain *sc, bool keep_handle)
{
    VkDevice dev = sc->gpu->device;
    vkDeviceWaitIdle(dev);
    for (uint32_t i = 0; i < SWAPCHAIN_MAX_IMAGES; i++) {
        if (sc->views[i])
            vkDestroyImageView(dev, sc->views[i], NULL);
        if (sc->acquired[i])
            vkDestroySemaphore(dev, sc->acquired[i], NULL);
        if (sc->rendered[i])
            vkDestroySemaphore(dev, sc->rendered[i], NULL);
        sc->views[i] = VK_NULL_HANDLE;
        sc->acquired[i] = sc->rendered[i] = VK_NULL_HANDLE;
        sc->images[i] = VK_NULL_HANDLE;
    }
    if (!keep_handle && sc->handle) {
        vkDestroySwapchainKHR(dev, sc->handle, NULL);
        sc->handle = VK_NULL_HANDLE;
    }
}

static VkSurfaceFormatKHR pick_format(gpu *g, VkSurfaceKHR surface)
{
    uint32_t n = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(g->phys, surface, &n, NULL);
    VkSurfaceFormatKHR formats[64];
    n = n > 64 ? 64 : n;
    vkGetPhysicalDeviceSurfaceFormatsKHR(g->phys, surface, &n, formats);
    for (uint32_t i = 0; i < n; i++)
        if (formats[i].format == VK_FORMAT_B8G8R8A8_UNORM || formats[i].format == VK_FORMAT_R8G8B8A8_UNORM)
            return formats[i];
    return n ? formats[0] : (VkSurfaceFormatKHR){VK_FORMAT_B8G8R8A8_UNORM, VK_COLOR_SPACE_SRGB_NONLINEAR_KHR};
}

static VkPresentModeKHR pick_mode(gpu *g, VkSurfaceKHR surface, bool no_vsync)
{
    if (!no_vsync)
        return VK_PRESENT_MODE_FIFO_KHR; /* always supported */
    uint32_t n = 0;
    vkGetPhysicalDeviceSurfacePresentModesKHR(g->phys, surface, &n, NULL);
    VkPresentModeKHR modes[16];
    n = n > 16 ? 16 : n;
    vkGetPhysicalDeviceSurfacePresentModesKHR(g->phys, surface, &n, modes);
    VkPresentModeKHR best = VK_PRESENT_MODE_FIFO_KHR;
    for (uint32_t i = 0; i < n; i++)
        if (modes[i] == VK_PRESENT_MODE_MAILBOX_KHR || (modes[i] == VK_PRESENT_MODE_IMMEDIATE_KHR && best == VK_PRESENT_MODE_FIFO_KHR))
            best = modes[i];
    return best;
}

static vg_status build(swapchain *sc, uint32_t width, uint32_t height)
{
    gpu *g = sc->gpu;
    VkSurfaceCapabilitiesKHR caps;
    VK_TRY(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(g->phys, sc->surface, &caps));
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == UINT32_MAX) {
        extent.width = width < caps.minImageExtent.width ? caps.minImageExtent.width
                       : width > caps.maxImageExtent.width ? caps.maxImageExtent.width : width;
        extent.height = height < caps.minImageExtent.height ? caps.minImageExtent.height
                        : height > caps.maxImageExtent.height ? caps.maxImageExtent.height : height;
    }
    if (extent.width == 0 || extent.height == 0) {
        sc->extent = extent;
        return VG_OK; /* minimised */
    }
    uint32_t count = caps.minImageCount + 1;
    if (caps.maxImageCount && count > caps.maxImageCount)
        count = caps.maxImageCount;
    if (count > SWAPCHAIN_MAX_IMAGES)
        count = SWAPCHAIN_MAX_IMAGES;
    VkSurfaceFormatKHR format = pick_format(g, sc->surface);
    VkSwapchainKHR old = sc->handle;
    VkSwapchainCreateInfoKHR info = {
        .sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
        .surface = sc->surface,
        .minImageCount = count,
        .imageFormat = format.format,
        .imageColorSpace = format.colorSpace,
        .imageExtent = extent,
        .imageArrayLayers = 1,
        .imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
        .imageSharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .preTransform = caps.currentTransform,
        .compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR,
        .presentMode = pick_mode(g, sc->surface, sc->no_vsync),
        .clipped = VK_TRUE,
        .oldSwapchain = old,
    };
    VK_TRY(vkCreateSwapchainKHR(g->device, &info, NULL, &sc->handle));
    GPU_NAME(g, VK_OBJECT_TYPE_SWAPCHAIN_KHR, sc->handle, "swapchain %ux%u", extent.width, extent.height);
    if (old)
        vkDestroySwapchainKHR(g->device, old, NULL);
    sc->format = format.format;
    sc->extent = extent;
    sc->mode = info.presentMode;
    sc->image_count = SWAPCHAIN_MAX_IMAGES;
    VK_TRY(vkGetSwapchainImagesKHR(g->device, sc->handle, &sc->image_count, sc->images));
    for (uint32_t i = 0; i < sc->image_count; i++) {
        GPU_NAME(g, VK_OBJECT_TYPE_IMAGE, sc->images[i], "swapchain image %u", i);
        VkImageViewCreateInfo view = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
            .image = sc->images[i],
            .viewType = VK_IMAGE_VIEW_TYPE_2D,
            .format = sc->format,
            .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1},
        };
        VK_TRY(vkCreateImageView(g->device, &view, NULL, &sc->views[i]));
        GPU_NAME(g, VK_OBJECT_TYPE_IMAGE_VIEW, sc->views[i], "swapchain view %u", i);
        VkSemaphoreCreateInfo si = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VK_TRY(vkCreateSemaphore(g->device, &si, NULL, &sc->acquired[i]));
        GPU_NAME(g, VK_OBJECT_TYPE_SEMAPHORE, sc->acquired[i], "image acquired %u", i);
        VK_TRY(vkCreateSemaphore(g->device, &si, NULL, &sc->rendered[i]));
        GPU_NAME(g, VK_OBJECT_TYPE_SEMAPHORE, sc->rendered[i], "image rendered %u", i);
    }
    sc->acquire_index = 0;
    return VG_OK;
}

vg_status swapchain_create(gpu *g, const swapchain_desc *desc, swapchain *out)
{
    *out = (swapchain){.gpu = g, .surface = desc->surface, .no_vsync = desc->no_vsync};
    VkBool32 supported = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(g->phys, g->queue_family, desc->surface, &supported);
    if (!supported) {
        vg_error("%s cannot present to this window", g->props.deviceName);
        vkDestroySurfaceKHR(g->instance, desc->surface, NULL);
        out->surface = VK_NULL_HANDLE;
        return VG_ERR_DEVICE;
    }
    return build(out, desc->width, desc->height);
}

void swapchain_destroy(swapchain *sc)
{
    if (!sc || !sc->gpu)
        return;
    release(sc, false);
    if (sc->surface)
        vkDestroySurfaceKHR(sc->gpu->instance, sc->surface, NULL);
    *sc = (swapchain){0};
}

vg_status swapchain_resize(swapchain *sc, uint32_t width, uint32_t height)
{
    release(sc, true);
    return build(sc, width, height);
}

vg_status swapchain_acquire(swapchain *sc, VkSemaphore *acquired, bool *out_of_date)
{
    *out_of_date = false;
    if (!sc->handle || sc->extent.width == 0) {
        *out_of_date = true;
        return VG_OK;
    }
    VkSemaphore sem = sc->acquired[sc->acquire_index];
    VkResult r = vkAcquireNextImageKHR(sc->gpu->device, sc->handle, UINT64_MAX, sem, VK_NULL_HANDLE, &sc->image);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        *out_of_date = true;
        return VG_OK;
    }
    if (r != VK_SUCCESS && r != VK_SUBOPTIMAL_KHR) {
        gpu_report_failure(__FILE__, __LINE__, "vkAcquireNextImageKHR", r);
        return VG_ERR_VULKAN;
    }
    sc->acquire_index = (sc->acquire_index + 1) % sc->image_count;
    *acquired = sem;
    return VG_OK;
}

vg_status swapchain_present(swapchain *sc, bool *out_of_date)
{
    *out_of_date = false;
    VkPresentInfoKHR info = {
        .sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
        .waitSemaphoreCount = 1,
        .pWaitSemaphores = &sc->rendered[sc->image],
        .swapchainCount = 1,
        .pSwapchains = &sc->handle,
        .pImageIndices = &sc->image,
    };
    VkResult r = vkQueuePresentKHR(sc->gpu->queue, &info);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        *out_of_date = true;
        return VG_OK;
    }
    if (r != VK_SUCCESS) {
        gpu_report_failure(__FILE__, __LINE__, "vkQueuePresentKHR", r);
        return VG_ERR_VULKAN;
    }
    return VG_OK;
}
