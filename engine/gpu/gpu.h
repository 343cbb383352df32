/* vergence — the Vulkan 1.3 context: instance, device, queue, validation.
 *
 * One graphics+compute queue, dynamic rendering and synchronization2 (core
 * 1.3), push descriptors. Picks a discrete GPU when there is one, else the
 * best other device (lavapipe on CI); desc.device_index overrides. Every
 * feature the engine needs is checked up front and a missing one is named
 * in the error. With validation on, every WARNING/ERROR message of the
 * validation layer is printed and counted; callers turn a count > 0 into a
 * failure (tests always run with validation). */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include <vulkan/vulkan.h>

#include "core/status.h"

typedef struct gpu_desc {
    bool validate;          /* Khronos validation layer (also env VERGENCE_VALIDATE=1), with
                               synchronization validation (env VERGENCE_SYNC_VALIDATION=0: without) */
    bool use_device;        /* use Vulkan device device_index; false (zero) = pick one: a
                               discrete GPU if present, else the best other */
    int device_index;
    const char *const *instance_extensions; /* e.g. from glfwGetRequiredInstanceExtensions */
    uint32_t instance_extension_count;
    bool need_swapchain;    /* enable VK_KHR_swapchain on the device */
} gpu_desc;

/* Optional features: used when present, reported by `vergence info`. */
typedef struct gpu_features {
    bool tessellation;          /* tessellationShader (required by warp.stereo) */
    bool multiview;             /* multiview */
    bool multiview_tessellation;/* multiviewTessellationShader */
    bool timestamps;            /* timestampComputeAndGraphics */
    bool fill_mode_non_solid;   /* wireframe debug views */
    bool multi_draw_indirect;   /* several indirect draws per call */
    bool draw_indirect_count;   /* the GPU decides how many indirect draws run */
} gpu_features;

/* A range of device memory a host's allocator gave (the SDK's memory
 * hooks, vgx_memory_hooks): bound at `offset`; `mapped` for host-visible
 * requests; `user` is the host's handle, given back to free. */
typedef struct gpu_memory_block {
    VkDeviceMemory memory;
    VkDeviceSize offset;
    void *mapped;
    void *user;
} gpu_memory_block;

typedef struct gpu_memory_hooks {
    VkResult (*allocate)(void *user, const char *name, const VkMemoryRequirements *requirements,
                         VkMemoryPropertyFlags properties, gpu_memory_block *block);
    void (*free)(void *user, const gpu_memory_block *block);
    void *user;
} gpu_memory_hooks;

typedef struct gpu {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice phys;
    VkPhysicalDeviceProperties props;
    VkPhysicalDeviceMemoryProperties mem;
    VkDevice device;
    VkQueue queue;
    uint32_t queue_family;
    VkCommandPool pool;
    gpu_features features;
    bool is_cpu;                /* a CPU rasteriser (lavapipe): pick cheaper settings */
    bool validation;
    bool sync_validation;
    bool debug_utils;           /* object names available */
    uint32_t device_index;
    PFN_vkCmdPushDescriptorSetKHR cmd_push_descriptor_set;
    PFN_vkSetDebugUtilsObjectNameEXT set_object_name;   /* these three with debug_utils, else NULL */
    PFN_vkCmdBeginDebugUtilsLabelEXT cmd_begin_label;
    PFN_vkCmdEndDebugUtilsLabelEXT cmd_end_label;
    VkDeviceSize memory_bytes;  /* device memory allocated through gpu_*_create now */
    VkDeviceSize memory_peak;   /* ... and at most so far */
    VkDeviceSize host_visible_bytes; /* of memory_bytes: host-visible */
    uint32_t allocations;       /* resources holding memory now (one allocation each) */
    gpu_memory_hooks hooks;     /* allocate set: device memory comes from the host (gpu_import) */
    long submits;               /* queue submissions so far */
    long lost_at;               /* VERGENCE_FAULT=device-lost:N (tests): submission N and later fail as
                                   VK_ERROR_DEVICE_LOST without reaching the queue; 0 = never */
    const VkAllocationCallbacks *alloc; /* host allocator of every object created (NULL: the driver's) */
    bool imported;              /* a host's instance and device (gpu_import): never destroyed here */
} gpu;

vg_status gpu_create(const gpu_desc *desc, gpu **out);
void gpu_destroy(gpu *g);

/* A context over a host engine's Vulkan objects (the SDK, include/vergence):
 * nothing is created but a command pool, and gpu_destroy leaves the host's
 * device and instance alone. The host enabled on the device what
 * gpu_missing_feature checks (features and extensions). */
typedef struct gpu_import_desc {
    VkInstance instance;
    VkPhysicalDevice physical_device;
    VkDevice device;
    uint32_t queue_family, queue_index;
    const VkAllocationCallbacks *alloc;
    bool debug_utils;           /* the host's instance enabled VK_EXT_debug_utils: name and label */
    gpu_memory_hooks hooks;     /* allocate and free set: every resource's memory from the host's allocator */
} gpu_import_desc;
vg_status gpu_import(const gpu_import_desc *desc, gpu **out);
/* Every requirement physical device p lacks: Vulkan 1.3, the features and
 * extensions create_device enables, a graphics+compute queue; with
 * need_swapchain the swapchain extension, with need_tessellation
 * tessellationShader (which VERGENCE_DISABLE=tessellation takes away). At
 * most cap names (static strings) into names; returns how many it lacks. */
uint32_t gpu_missing_features(VkPhysicalDevice p, bool need_swapchain, bool need_tessellation, const char **names,
                              uint32_t cap);
/* The first of them, or NULL when it has them all. */
const char *gpu_missing_feature(VkPhysicalDevice p, bool need_swapchain);

/* One command buffer on the context's queue (vkQueueSubmit2): waiting on
 * `wait` at `wait_stage` and signalling `signal` (each VK_NULL_HANDLE for
 * none), then `fence`. Every submission goes through here so tests can make
 * the device fail (lost_at). */
VkResult gpu_queue_submit(gpu *g, VkCommandBuffer cmd, VkSemaphore wait, VkPipelineStageFlags2 wait_stage,
                          VkSemaphore signal, VkFence fence);

/* Validation WARNING/ERROR messages so far in this process, including those
 * raised while a context was destroyed (leaked objects). */
int gpu_validation_messages(void);

/* Debug name for any Vulkan object (no-op without VK_EXT_debug_utils). */
void gpu_set_name(const gpu *g, VkObjectType type, uint64_t handle, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
#define GPU_NAME(g, type, handle, ...) gpu_set_name((g), (type), (uint64_t)(handle), __VA_ARGS__)
/* A command-buffer label around what is recorded until gpu_cmd_label_end
 * (RenderDoc, Nsight; no-op without VK_EXT_debug_utils). */
void gpu_cmd_label_begin(const gpu *g, VkCommandBuffer cmd, const char *name);
void gpu_cmd_label_end(const gpu *g, VkCommandBuffer cmd);

const char *gpu_result_text(VkResult r);
const char *gpu_device_type_text(VkPhysicalDeviceType t);

/* Runs the call; on failure logs file:line, the call and the VkResult, and
 * returns VG_ERR_VULKAN from the enclosing function (which returns vg_status).
 * VK_ERROR_DEVICE_LOST gets its own clear message. */
#define VK_TRY(call)                                                              \
    do {                                                                          \
        VkResult vk_try_r_ = (call);                                              \
        if (vk_try_r_ != VK_SUCCESS) {                                            \
            gpu_report_failure(__FILE__, __LINE__, #call, vk_try_r_);             \
            return VG_ERR_VULKAN;                                                 \
        }                                                                         \
    } while (0)

void gpu_report_failure(const char *file, int line, const char *call, VkResult r);

/* ------------------------------------------------------------------------- */
/* Resources                                                                 */
/* ------------------------------------------------------------------------- */

typedef struct gpu_buffer_desc {
    const char *name;
    VkDeviceSize size;
    VkBufferUsageFlags usage;
    bool host_visible;          /* mapped for the buffer's life */
} gpu_buffer_desc;

typedef struct gpu_buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    VkDeviceSize size;
    VkDeviceSize memory_size;   /* bytes of its allocation */
    void *mapped;
    VkDeviceSize memory_offset; /* within `memory`: a host's block (gpu.hooks), else 0 */
    void *memory_user;          /* the host's handle of the block */
    bool host_visible;
} gpu_buffer;

typedef struct gpu_image_desc {
    const char *name;
    VkFormat format;
    uint32_t width, height;
    uint32_t layers;            /* 0 = 1 */
    VkImageUsageFlags usage;
} gpu_image_desc;

typedef struct gpu_image {
    VkImage image;
    VkImageView view;
    VkDeviceMemory memory;
    VkDeviceSize memory_size;   /* bytes of its allocation */
    VkDeviceSize memory_offset; /* within `memory`: a host's block (gpu.hooks), else 0 */
    void *memory_user;          /* the host's handle of the block */
    VkFormat format;
    uint32_t width, height, layers;
} gpu_image;

vg_status gpu_buffer_create(gpu *g, const gpu_buffer_desc *desc, gpu_buffer *out);
void gpu_buffer_destroy(gpu *g, gpu_buffer *b);
/* A texel view of a buffer's first `range` bytes (created with a TEXEL_BUFFER
 * usage): shaders read it with texelFetch, which lavapipe gathers where it
 * loads a storage buffer at a varying index lane by lane
 * (docs/PERFORMANCE.md). VG_ERR_DEVICE past maxTexelBufferElements. */
vg_status gpu_buffer_view_create(gpu *g, VkBuffer buffer, VkFormat format, VkDeviceSize range, const char *name,
                                 VkBufferView *out);
vg_status gpu_image_create(gpu *g, const gpu_image_desc *desc, gpu_image *out);
void gpu_image_destroy(gpu *g, gpu_image *img);
VkImageAspectFlags gpu_format_aspect(VkFormat f);
uint32_t gpu_format_size(VkFormat f); /* bytes per texel of the formats the engine uses */

/* One-shot command buffer: begin, record, submit and wait. */
vg_status gpu_oneshot_begin(gpu *g, VkCommandBuffer *cmd);
vg_status gpu_oneshot_submit(gpu *g, VkCommandBuffer cmd);

/* Records an image's first transition, from UNDEFINED (contents discarded)
 * into the layout every later use finds it in: for the images that live
 * across frames outside the frame graph (created once, imported after). */
void gpu_cmd_enter_layout(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout layout);

/* Records, after every command before it in cmd, the write of `value`
 * into the first 4 bytes of a host-visible buffer (TRANSFER_DST usage),
 * made available to the host: once the submission's fence has signalled,
 * the host reads it. How far the GPU got, without a fence of one's own. */
void gpu_cmd_mark(VkCommandBuffer cmd, VkBuffer buffer, uint32_t value);

/* Uploads pixels into a sampled image (layout SHADER_READ_ONLY_OPTIMAL after). */
vg_status gpu_image_upload(gpu *g, gpu_image *img, const void *pixels, size_t size);

/* ------------------------------------------------------------------------- */
/* Shaders and pipelines                                                     */
/* ------------------------------------------------------------------------- */

vg_status gpu_shader_create(gpu *g, const uint32_t *code, size_t size, const char *name,
                            VkShaderModule *out);
