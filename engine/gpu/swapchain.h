/* vergence — a window's swapchain: creation, recreation when the window
 * changes size or the surface goes out of date, acquire and present.
 *
 * The images are B8G8R8A8_UNORM (or R8G8B8A8_UNORM): the engine's output is
 * already sRGB-encoded, so presenting copies bytes. FIFO (vsync) unless the
 * desc asks for immediate. Each image has its own acquire and render-done
 * semaphores (indexed by a rotating frame counter for acquire, by image for
 * present), so no semaphore is reused while in flight. */
#pragma once
#include <stdbool.h>

#include "gpu.h"

#define SWAPCHAIN_MAX_IMAGES 8

typedef struct swapchain_desc {
    VkSurfaceKHR surface;        /* owned by the swapchain from here on */
    uint32_t width, height;      /* framebuffer size of the window */
    bool no_vsync;               /* IMMEDIATE or MAILBOX when available */
} swapchain_desc;

typedef struct swapchain {
    gpu *gpu;
    VkSurfaceKHR surface;
    VkSwapchainKHR handle;
    VkFormat format;
    VkExtent2D extent;
    VkPresentModeKHR mode;
    uint32_t image_count;
    VkImage images[SWAPCHAIN_MAX_IMAGES];
    VkImageView views[SWAPCHAIN_MAX_IMAGES];
    VkSemaphore acquired[SWAPCHAIN_MAX_IMAGES]; /* rotating */
    VkSemaphore rendered[SWAPCHAIN_MAX_IMAGES]; /* per image */
    uint32_t acquire_index;      /* which acquired semaphore the next acquire uses */
    uint32_t image;              /* the image of the last acquire */
    bool no_vsync;
} swapchain;

vg_status swapchain_create(gpu *g, const swapchain_desc *desc, swapchain *out);
void swapchain_destroy(swapchain *sc);
/* New size (0 x 0: minimised, nothing to do until it grows again). */
vg_status swapchain_resize(swapchain *sc, uint32_t width, uint32_t height);

/* Acquires the next image. *out_of_date is set (and VG_OK returned) when the
 * swapchain must be resized first. */
vg_status swapchain_acquire(swapchain *sc, VkSemaphore *acquired, bool *out_of_date);
/* Presents the acquired image once `rendered` is signalled. */
vg_status swapchain_present(swapchain *sc, bool *out_of_date);
