/* vergence — the public API (include/vergence/vergence.h) over the engine's
 * passes: a small frame graph of its own whose imported resources are the
 * host's images, recorded into the host's command buffer. */
#include "vergence/vergence.h"
#include "vgx_engine.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "disparity/gpu/disparity_gpu.h"
#include "disparity/mid_shared.h"
#include "disparity/mid_window.h"
#include "graph/graph.h"
#include "warp/screen/curve_gpu.h"
#include "warp/screen/eyes_gpu.h"
#include "warp/warp_settings.h"

#include "vgx_depth_comp.h"
#include "shared.h"
#include "stereo/stereo_display.h"

#define VGX_LIBRARY_VERSION VGX_MAKE_VERSION(VERGENCE_VERSION_MAJOR, VERGENCE_VERSION_MINOR, VERGENCE_VERSION_PATCH)

#define VGX_INPUTS 9 /* frame depth, saliency, motion, ids; the atlas's four; the shaded colour (eyes) */
#define VGX_COLOR 8

/* The size of the vgx_context_desc a host built against header 0.1 passes:
 * the 0.1 members end where 0.2's begin (vergence.h, "How the ABI grows"). */
#define VGX_CONTEXT_DESC_SIZE_0_1 offsetof(vgx_context_desc, frames_in_flight)
#define VGX_DISPATCH_DESC_SIZE_0_1 offsetof(vgx_dispatch_desc, color)
#define VGX_KNOWN_FLAGS (VGX_CONTEXT_SALIENCY | VGX_CONTEXT_OPTIMIZE | VGX_CONTEXT_WARP | VGX_CONTEXT_KEYFRAMES | \
                         VGX_CONTEXT_DEBUG_UTILS | VGX_CONTEXT_EYES)
_Static_assert(sizeof(void *) != 8 || VGX_CONTEXT_DESC_SIZE_0_1 == 208, "the 0.1 vgx_context_desc is 208 bytes on LP64");
_Static_assert(VGX_MAX_FRAMES_IN_FLIGHT <= RG_MAX_SLOTS, "a graph keeps timestamps for every frame in flight");

/* Graphs of configurations replaced while frames that used them were in
 * flight, each freed once the GPU has passed the last such frame. */
#define VGX_RETIRED 8
typedef struct vgx_retired {
    rg_graph *graph;
    uint32_t last;                    /* the serial of the last dispatch that recorded it */
} vgx_retired;

/* The public enums are the engine's, value for value (vgx_context_create
 * casts one to the other). */
_Static_assert((int)VGX_OPERATOR_DEFAULT == (int)DISP_OPERATOR_DEFAULT &&
                   (int)VGX_OPERATOR_NONE == (int)DISP_OPERATOR_NONE &&
                   (int)VGX_OPERATOR_LINEAR == (int)DISP_OPERATOR_LINEAR &&
                   (int)VGX_OPERATOR_LANG == (int)DISP_OPERATOR_LANG &&
                   (int)VGX_OPERATOR_LANG_SMOOTHED == (int)DISP_OPERATOR_LANG_SMOOTHED,
               "vgx_operator and disp_operator_kind differ");
_Static_assert((int)VGX_PRESET_DEFAULT == (int)DISP_PRESET_DEFAULT &&
                   (int)VGX_PRESET_STUDY == (int)DISP_PRESET_STUDY,
               "vgx_preset and disp_operator_preset differ");

/* include/vergence/warp.glsl's VgxWarpConstants (std140). */
typedef struct warp_constants {
    float view_proj[16];
    float viewport[4], rig[4], display[4], warp[4], warp2[4];
} warp_constants;

struct vgx_context {
    vgx_context_desc desc;
    gpu *gpu;
    stereo_display display;
    disparity_gpu *d;
    disparity_gpu_info info;
    uint32_t atlas_w, atlas_h;
    VkDeviceSize graph_bytes;         /* device memory of the first configuration's graph */
    gpu_buffer ubo;                   /* vg_frame_ubo: rig, display, viewport (device-local, updated in the command buffer) */
    gpu_image out[3];                 /* g, h, f */
    gpu_image blank[2];               /* where the host gives no saliency: the frame's and the atlas's */
    bool initialised;                 /* the context's images were moved to their steady layouts */

    /* VGX_DEPTH_DEVICE: the host's z-buffer made linear (vgx.depth). */
    gpu_compute_kit depth_kit;
    VkSampler nearest;
    gpu_image linear;
    float depth_m[4];                 /* m10, m11, m14, m15 of the host's projection */
    bool device_depth;                /* the last dispatch's */

    /* The stereo pair without tessellation (VGX_CONTEXT_EYES). */
    eyes_gpu *eyes;
    gpu_image eye[2];
    rg_res r_eye[2];
    bool v01;                         /* the host was built against header 0.1: its descs have 0.1's members */

    /* The warp (VGX_CONTEXT_WARP). */
    curve_gpu *curve;
    gpu_buffer warp_ubo, curve_buf;
    warp_constants warp;
    int warp_map;                     /* the output it reads (VGX_OUTPUT_*) */

    /* Frames in flight: `serial` numbers the dispatches (the first is 1),
     * each of which writes its number into `progress` when the GPU has run
     * it (gpu_cmd_mark); a graph last used at serial s waits in `retired`
     * until the dispatch s + frames_in_flight (free_retired). */
    uint32_t frames_in_flight;
    uint32_t serial;
    gpu_buffer progress;
    vgx_retired retired[VGX_RETIRED];
    int retired_count;

    /* The graph for the host's current input layouts and warp map. */
    rg_graph *graph;
    VkImageLayout layouts[VGX_INPUTS];
    int graph_warp_map;
    vgx_depth_kind graph_depth_kind;
    VkFormat graph_depth_format;
    rg_res r_warp_ubo, r_curve, r_linear;
    rg_res inputs[VGX_INPUTS];
    frame_resources res;
    vg_frame_ubo constants;

    /* The frame planned by vgx_begin_frame. */
    bool planned;
    uint32_t next_pass;               /* a dispatch recorded pass by pass: the next one due */
    int64_t next_index;               /* without a plan: the dispatch's frame */
    vgx_frame_plan plan;
    long key_first;
};

uint32_t vgx_version(void)
{
    return VGX_LIBRARY_VERSION;
}

const char *vgx_result_name(vgx_result result)
{
    switch (result) {
    case VGX_SUCCESS: return "VGX_SUCCESS";
    case VGX_ERROR_INVALID_ARGUMENT: return "VGX_ERROR_INVALID_ARGUMENT";
    case VGX_ERROR_OUT_OF_MEMORY: return "VGX_ERROR_OUT_OF_MEMORY";
    case VGX_ERROR_VULKAN: return "VGX_ERROR_VULKAN";
    case VGX_ERROR_DEVICE: return "VGX_ERROR_DEVICE";
    case VGX_ERROR_VERSION: return "VGX_ERROR_VERSION";
    }
    return "unknown";
}

static vgx_result result_of(vg_status st)
{
    switch (st) {
    case VG_OK: return VGX_SUCCESS;
    case VG_ERR_NOMEM: return VGX_ERROR_OUT_OF_MEMORY;
    case VG_ERR_VULKAN: return VGX_ERROR_VULKAN;
    case VG_ERR_DEVICE: return VGX_ERROR_DEVICE;
    default: return VGX_ERROR_INVALID_ARGUMENT;
    }
}

vg_status vgx_engine_status(vgx_result r)
{
    switch (r) {
    case VGX_SUCCESS: return VG_OK;
    case VGX_ERROR_OUT_OF_MEMORY: return VG_ERR_NOMEM;
    case VGX_ERROR_VULKAN: return VG_ERR_VULKAN;
    case VGX_ERROR_DEVICE: return VG_ERR_DEVICE;
    case VGX_ERROR_VERSION: return VG_ERR_UNSUPPORTED;
    default: return VG_ERR_ARG;
    }
}

/* ------------------------------------------------------------------------- */
/* Messages: the engine's log lines go to the host's callback while a vgx_   */
/* call runs (core/log.h's sink is per thread).                              */
/* ------------------------------------------------------------------------- */

typedef struct message_to {
    vgx_message_fn fn;
    void *user;
} message_to;

static void to_host(vg_log_level level, const char *line, void *user)
{
    const message_to *m = user;
    vgx_severity s = level == VG_LOG_ERROR ? VGX_SEVERITY_ERROR
                     : level == VG_LOG_WARN ? VGX_SEVERITY_WARNING : VGX_SEVERITY_INFO;
    if (level <= VG_LOG_INFO)
        m->fn(s, line, m->user);
}

static vg_log_sink sink_begin(message_to *m, vgx_message_fn fn, void *user)
{
    m->fn = fn;
    m->user = user;
    return vg_log_set_sink(fn ? (vg_log_sink){to_host, m} : (vg_log_sink){0});
}

/* ------------------------------------------------------------------------- */
/* Device requirements                                                       */
/* ------------------------------------------------------------------------- */

const char *const *vgx_device_extensions(uint32_t *count)
{
    static const char *const exts[] = {VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
    if (count)
        *count = 1;
    return exts;
}

vgx_result vgx_check_physical_device(VkPhysicalDevice physical_device, const char **missing)
{
    const char *m = physical_device ? gpu_missing_feature(physical_device, false) : "a physical device";
    if (missing)
        *missing = m;
    return m ? VGX_ERROR_DEVICE : VGX_SUCCESS;
}

vgx_result vgx_get_missing_requirements(VkPhysicalDevice physical_device, uint32_t context_flags,
                                        const char **missing, uint32_t capacity, uint32_t *missing_count)
{
    uint32_t known = VGX_KNOWN_FLAGS;
    if (!physical_device || !missing_count || (capacity && !missing) || (context_flags & ~known))
        return VGX_ERROR_INVALID_ARGUMENT;
    *missing_count = gpu_missing_features(physical_device, false, (context_flags & VGX_CONTEXT_WARP) != 0, missing,
                                          capacity);
    return *missing_count ? VGX_ERROR_DEVICE : VGX_SUCCESS;
}

/* ------------------------------------------------------------------------- */
/* Context                                                                   */
/* ------------------------------------------------------------------------- */

static vg_status check_desc(const vgx_context_desc *d)
{
    uint32_t v = d->header_version, lib = VGX_LIBRARY_VERSION;
    if (VGX_VERSION_MAJOR(v) != VGX_VERSION_MAJOR(lib) || VGX_VERSION_MINOR(v) > VGX_VERSION_MINOR(lib) ||
        (VGX_VERSION_MAJOR(v) == 0 && VGX_VERSION_MINOR(v) == 0)) {
        vg_error("vgx_context_desc.header_version is %u.%u.%u; this library is %u.%u.%u and runs hosts built "
                 "against its major version, up to its minor (set VGX_HEADER_VERSION)",
                 VGX_VERSION_MAJOR(v), VGX_VERSION_MINOR(v), VGX_VERSION_PATCH(v), VGX_VERSION_MAJOR(lib),
                 VGX_VERSION_MINOR(lib), VGX_VERSION_PATCH(lib));
        return VG_ERR_UNSUPPORTED;
    }
    const char *null = !d->instance ? "instance" : !d->physical_device ? "physical_device" : !d->device ? "device" : NULL;
    if (null) {
        vg_error("vgx_context_desc.%s is null", null);
        return VG_ERR_ARG;
    }
    if (d->width < 8 || d->height < 8 || d->width > 16384 || d->height > 16384) {
        vg_error("vgx_context_desc.width x height is %u x %u (8 to 16384 each)", d->width, d->height);
        return VG_ERR_ARG;
    }
    if ((unsigned)d->op > VGX_OPERATOR_LANG_SMOOTHED || (unsigned)d->preset > VGX_PRESET_STUDY ||
        (unsigned)d->look_ahead > VGX_LOOK_AHEAD_CAUSAL) {
        vg_error("vgx_context_desc.op (%d), .preset (%d) or .look_ahead (%d) is not one of its enum's values",
                 (int)d->op, (int)d->preset, (int)d->look_ahead);
        return VG_ERR_ARG;
    }
    if (!(d->target_range_arcmin >= 0 && d->target_range_arcmin < 600)) {
        vg_error("vgx_context_desc.target_range_arcmin (%g) must be in [0, 600)", d->target_range_arcmin);
        return VG_ERR_ARG;
    }
    if (!(d->fps >= 0 && d->fps <= 1000) || d->keyframe_stride < 0 || d->keyframe_stride > 1000 ||
        !(d->window_seconds >= 0 && d->window_seconds <= 60)) {
        vg_error("vgx_context_desc.fps (%g, 0 to 1000), .keyframe_stride (%d, 0 to 1000) or .window_seconds "
                 "(%g, 0 to 60) is out of range", d->fps, d->keyframe_stride, d->window_seconds);
        return VG_ERR_ARG;
    }
    const vgx_warp_settings *w = &d->warp;
    if (!(w->tess_px >= 0 && w->tess_px <= 1024) || !(w->tess_error_px >= 0 && w->tess_error_px <= 1024) ||
        w->max_tess_level > 64 || !(w->depth_epsilon >= 0 && w->depth_epsilon < 1) ||
        !(w->halton_radius_px >= 0 && w->halton_radius_px <= 4096)) {
        vg_error("vgx_context_desc.warp: tess_px (%g) and tess_error_px (%g) in [0, 1024], max_tess_level (%u) at "
                 "most 64, depth_epsilon (%g) in [0, 1), halton_radius_px (%g) in [0, 4096]", w->tess_px,
                 w->tess_error_px, w->max_tess_level, w->depth_epsilon, w->halton_radius_px);
        return VG_ERR_ARG;
    }
    uint32_t known = VGX_KNOWN_FLAGS;
    if (d->flags & ~known) {
        vg_error("vgx_context_desc.flags has unknown bits 0x%x", d->flags & ~known);
        return VG_ERR_ARG;
    }
    if (!d->memory.allocate != !d->memory.free) {
        vg_error("vgx_context_desc.memory: set both allocate and free, or neither");
        return VG_ERR_ARG;
    }
    if (d->frames_in_flight > VGX_MAX_FRAMES_IN_FLIGHT) {
        vg_error("vgx_context_desc.frames_in_flight is %u (1 to %d; 0 = 2)", d->frames_in_flight,
                 VGX_MAX_FRAMES_IN_FLIGHT);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

static bool has_keyframes(const vgx_context *c)
{
    return c->desc.flags & (VGX_CONTEXT_OPTIMIZE | VGX_CONTEXT_KEYFRAMES);
}

static vg_status build_graph(vgx_context *c, const VkImageLayout layouts[VGX_INPUTS], int warp_map);
static bool input_used(const vgx_context *c, int i);

/* The host's memory hooks, as the gpu module calls them. */
static VkResult hook_allocate(void *user, const char *name, const VkMemoryRequirements *requirements,
                              VkMemoryPropertyFlags properties, gpu_memory_block *block)
{
    const vgx_memory_hooks *h = user;
    vgx_memory_block b = {0};
    VkResult r = h->allocate(h->user, &(vgx_memory_request){name, *requirements, properties}, &b);
    *block = (gpu_memory_block){b.memory, b.offset, b.mapped, b.user};
    return r;
}

static void hook_free(void *user, const gpu_memory_block *block)
{
    const vgx_memory_hooks *h = user;
    h->free(h->user, &(vgx_memory_block){block->memory, block->offset, block->mapped, block->user});
}

static vg_status create(vgx_context *c, const disparity_gpu_desc *tuning)
{
    const vgx_context_desc *d = &c->desc;
    bool optimize = d->flags & VGX_CONTEXT_OPTIMIZE, keyframes = has_keyframes(c);
    vg_status st = gpu_import(&(gpu_import_desc){.instance = d->instance, .physical_device = d->physical_device,
                                                 .device = d->device, .queue_family = d->queue_family,
                                                 .alloc = d->allocator,
                                                 .debug_utils = (d->flags & VGX_CONTEXT_DEBUG_UTILS) != 0,
                                                 .hooks = d->memory.allocate
                                                     ? (gpu_memory_hooks){hook_allocate, hook_free,
                                                                          (void *)&c->desc.memory}
                                                     : (gpu_memory_hooks){0}},
                     &c->gpu);
    if (st != VG_OK)
        return st;
    stereo_display_init(&c->display, &(stereo_display_desc){
        .diagonal_in = d->display.diagonal_in, .aspect_w = d->display.aspect_w, .aspect_h = d->display.aspect_h,
        .res_x = d->display.res_x, .res_y = d->display.res_y, .distance_m = d->display.distance_m,
        .ipd_m = d->display.ipd_m});
    /* Zero is each setting's default (disparity_gpu_desc_defaults, which
     * the engine's frame resolves through too); the frame tunes what the
     * public desc does not name (vgx_engine.h). */
    disparity_gpu_desc dd = {
        .gpu = c->gpu, .width = d->width, .height = d->height, .fps = d->fps,
        .keyframe_stride = d->keyframe_stride, .window_seconds = d->window_seconds,
        .op = (disp_operator_kind)d->op, .op_preset = (disp_operator_preset)d->preset,
        .target_range = d->target_range_arcmin, .screen_vergence = c->display.screen_vergence,
        .no_saliency = !(d->flags & VGX_CONTEXT_SALIENCY), .causal = d->look_ahead == VGX_LOOK_AHEAD_CAUSAL,
        .keyframes = keyframes, .f = optimize};
    if (tuning) {
        dd.coarse_stride = tuning->coarse_stride;
        dd.window_future = tuning->window_future;
        dd.solver = tuning->solver;
        dd.solver_iterations = tuning->solver_iterations;
        dd.temporal_depth_only = tuning->temporal_depth_only;
        dd.readback = tuning->readback;
        dd.budgeted = tuning->budgeted;
    }
    dd = disparity_gpu_desc_defaults(&dd);
    c->desc.fps = dd.fps; /* the frame times (begin_frame, vgx_get_keyframe) */
    c->desc.keyframe_stride = dd.keyframe_stride;
    st = disparity_gpu_create(&dd, &c->d);
    if (st != VG_OK)
        return st;
    disparity_gpu_get_info(c->d, &c->info);
    c->atlas_w = c->info.nx;
    c->atlas_h = c->info.ny * c->info.max_tiles;
    st = gpu_buffer_create(c->gpu, &(gpu_buffer_desc){.name = "vgx constants", .size = sizeof(vg_frame_ubo),
                                                      .usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                                                               VK_BUFFER_USAGE_TRANSFER_DST_BIT}, &c->ubo);
    if (st == VG_OK)
        st = gpu_buffer_create(c->gpu, &(gpu_buffer_desc){.name = "vgx progress", .size = 4,
                                                          .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                          .host_visible = true}, &c->progress);
    if (st == VG_OK)
        memset(c->progress.mapped, 0, 4);
    static const char *const names[3] = {"vgx g", "vgx h", "vgx f"};
    for (int i = 0; i < (optimize ? 3 : 2) && st == VG_OK; i++)
        st = gpu_image_create(c->gpu, &(gpu_image_desc){.name = names[i], .format = VK_FORMAT_R32_SFLOAT,
                                                        .width = d->width, .height = d->height,
                                                        .usage = VK_IMAGE_USAGE_STORAGE_BIT |
                                                                 VK_IMAGE_USAGE_SAMPLED_BIT |
                                                                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT}, &c->out[i]);
    static const VkDescriptorType depth_types[2] = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                                    VK_DESCRIPTOR_TYPE_STORAGE_IMAGE};
    if (st == VG_OK)
        st = gpu_compute_kit_create(c->gpu, &(gpu_compute_kit_desc){
            .name = "vgx.depth", .types = depth_types, .count = 2, .push_size = 4 * sizeof(float),
            .kernels = {GPU_KERNEL(spv_vgx_depth_comp, "vgx.depth")}}, &c->depth_kit);
    if (st == VG_OK) {
        VkSamplerCreateInfo si = {.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO, .magFilter = VK_FILTER_NEAREST,
                                  .minFilter = VK_FILTER_NEAREST, .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                                  .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                                  .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE};
        VkResult r = vkCreateSampler(c->gpu->device, &si, c->gpu->alloc, &c->nearest);
        if (r != VK_SUCCESS) {
            gpu_report_failure(__FILE__, __LINE__, "vkCreateSampler", r);
            st = VG_ERR_VULKAN;
        }
        GPU_NAME(c->gpu, VK_OBJECT_TYPE_SAMPLER, c->nearest, "vgx nearest sampler");
    }
    if (st == VG_OK)
        st = gpu_image_create(c->gpu, &(gpu_image_desc){.name = "vgx linear depth", .format = VK_FORMAT_R32_SFLOAT,
                                                        .width = d->width, .height = d->height,
                                                        .usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT},
                              &c->linear);
    c->warp_map = optimize ? VGX_OUTPUT_F : VGX_OUTPUT_H; /* the default warp map (vgx_get_warp) */
    if (st == VG_OK && (d->flags & VGX_CONTEXT_WARP)) {
        st = curve_gpu_create(c->gpu, d->width, d->height, &c->curve);
        if (st == VG_OK)
            st = gpu_buffer_create(c->gpu, &(gpu_buffer_desc){.name = "vgx warp constants", .size = sizeof(warp_constants),
                                                              .usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                                                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT}, &c->warp_ubo);
        if (st == VG_OK)
            st = gpu_buffer_create(c->gpu, &(gpu_buffer_desc){.name = "vgx warp curve", .size = sizeof(vgx_curve_data),
                                                              .usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT},
                                   &c->curve_buf);
    }
    static const char *const eye_names[2] = {"vgx left eye", "vgx right eye"};
    for (int i = 0; i < 2 && st == VG_OK && (d->flags & VGX_CONTEXT_EYES); i++)
        st = gpu_image_create(c->gpu, &(gpu_image_desc){.name = eye_names[i], .format = VK_FORMAT_R8G8B8A8_UNORM,
                                                        .width = d->width, .height = d->height,
                                                        .usage = VK_IMAGE_USAGE_STORAGE_BIT |
                                                                 VK_IMAGE_USAGE_SAMPLED_BIT |
                                                                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT}, &c->eye[i]);
    if (st == VG_OK && (d->flags & VGX_CONTEXT_EYES))
        st = eyes_gpu_create(c->gpu, d->width, d->height, c->nearest, &c->eyes);
    for (int i = 0; i < (keyframes ? 2 : 1) && st == VG_OK && !(d->flags & VGX_CONTEXT_SALIENCY); i++)
        st = gpu_image_create(c->gpu, &(gpu_image_desc){.name = "vgx no saliency", .format = VK_FORMAT_R8G8B8A8_UNORM,
                                                        .width = i ? c->atlas_w : d->width,
                                                        .height = i ? c->atlas_h : d->height,
                                                        .usage = VK_IMAGE_USAGE_STORAGE_BIT}, &c->blank[i]);
    /* The passes are known from the start (vgx_pass_name): a graph for
     * inputs in GENERAL; a dispatch with other layouts compiles its own. */
    VkImageLayout general[VGX_INPUTS];
    for (int i = 0; i < VGX_INPUTS; i++)
        general[i] = input_used(c, i) ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_UNDEFINED;
    c->graph_depth_kind = VGX_DEPTH_LINEAR;
    VkDeviceSize before = c->gpu->memory_bytes;
    if (st == VG_OK)
        st = build_graph(c, general, c->warp_map);
    c->graph_bytes = c->gpu->memory_bytes - before;
    return st;
}

static vgx_result context_create(const vgx_context_desc *desc, const disparity_gpu_desc *tuning, vgx_context **out)
{
    if (!out)
        return VGX_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    message_to m;
    vg_log_sink was = sink_begin(&m, desc ? desc->message : NULL, desc ? desc->message_user : NULL);
    vg_status st = VG_ERR_ARG;
    vgx_context *c = NULL;
    /* The host's desc has the members of the header it was built with
     * (its header_version, the first member of every version); the newer
     * ones stay zero: their defaults. Of a header this library does not
     * know (check_desc refuses it), nothing past header_version is read. */
    vgx_context_desc d = {0};
    if (!desc)
        vg_error("vgx_context_create: desc is null");
    else {
        uint32_t v = desc->header_version, lib = VGX_LIBRARY_VERSION;
        bool known = VGX_VERSION_MAJOR(v) == VGX_VERSION_MAJOR(lib) && VGX_VERSION_MINOR(v) >= 1 &&
                     VGX_VERSION_MINOR(v) <= VGX_VERSION_MINOR(lib);
        bool v01 = known && VGX_VERSION_MAJOR(v) == 0 && VGX_VERSION_MINOR(v) == 1;
        memcpy(&d, desc, !known ? sizeof d.header_version : v01 ? VGX_CONTEXT_DESC_SIZE_0_1 : sizeof d);
        if ((st = check_desc(&d)) == VG_OK) {
            c = calloc(1, sizeof *c);
            st = c ? VG_OK : VG_ERR_NOMEM;
        }
    }
    if (st == VG_OK) {
        c->desc = d;
        c->v01 = VGX_VERSION_MAJOR(d.header_version) == 0 && VGX_VERSION_MINOR(d.header_version) == 1;
        c->frames_in_flight = d.frames_in_flight ? d.frames_in_flight : 2;
        st = create(c, tuning);
        if (st != VG_OK) {
            vgx_context_destroy(c);
            c = NULL;
        }
    }
    vg_log_set_sink(was);
    *out = c;
    return st == VG_ERR_UNSUPPORTED ? VGX_ERROR_VERSION : result_of(st);
}

vgx_result vgx_context_create(const vgx_context_desc *desc, vgx_context **out)
{
    return context_create(desc, NULL, out);
}

vgx_result vgx_get_memory_footprint(const vgx_context_desc *desc, vgx_memory_footprint *footprint)
{
    if (!footprint)
        return VGX_ERROR_INVALID_ARGUMENT;
    *footprint = (vgx_memory_footprint){0};
    vgx_context *c = NULL;
    vgx_result r = context_create(desc, NULL, &c);
    if (r != VGX_SUCCESS)
        return r;
    *footprint = (vgx_memory_footprint){.bytes = c->gpu->memory_bytes, .host_visible_bytes = c->gpu->host_visible_bytes,
                                        .blocks = c->gpu->allocations, .configuration_bytes = c->graph_bytes};
    vgx_context_destroy(c);
    return VGX_SUCCESS;
}

vgx_result vgx_engine_context_create(const vgx_context_desc *desc, const disparity_gpu_desc *tuning, vgx_context **out)
{
    return context_create(desc, tuning, out);
}

disparity_gpu *vgx_engine_disparity(const vgx_context *c)
{
    return c->d;
}

void vgx_context_destroy(vgx_context *c)
{
    if (!c)
        return;
    message_to m;
    vg_log_sink was = sink_begin(&m, c->desc.message, c->desc.message_user);
    if (c->gpu) {
        rg_destroy(c->graph);
        for (int i = 0; i < c->retired_count; i++)
            rg_destroy(c->retired[i].graph);
        gpu_buffer_destroy(c->gpu, &c->progress);
        for (int i = 0; i < 3; i++)
            gpu_image_destroy(c->gpu, &c->out[i]);
        for (int i = 0; i < 2; i++)
            gpu_image_destroy(c->gpu, &c->blank[i]);
        gpu_buffer_destroy(c->gpu, &c->ubo);
        gpu_buffer_destroy(c->gpu, &c->warp_ubo);
        gpu_image_destroy(c->gpu, &c->linear);
        gpu_compute_kit_destroy(c->gpu, &c->depth_kit);
        if (c->nearest)
            vkDestroySampler(c->gpu->device, c->nearest, c->gpu->alloc);
        gpu_buffer_destroy(c->gpu, &c->curve_buf);
        curve_gpu_destroy(c->curve);
        eyes_gpu_destroy(c->eyes);
        for (int i = 0; i < 2; i++)
            gpu_image_destroy(c->gpu, &c->eye[i]);
        disparity_gpu_destroy(c->d);
        gpu_destroy(c->gpu);
    }
    vg_log_set_sink(was);
    free(c);
}

void vgx_get_info(const vgx_context *c, vgx_context_info *info)
{
    if (!c || !info)
        return;
    bool optimize = c->desc.flags & VGX_CONTEXT_OPTIMIZE;
    *info = (vgx_context_info){.range_lo_arcmin = c->info.range_lo, .range_hi_arcmin = c->info.range_hi,
                               .grid_width = c->info.nx, .grid_height = c->info.ny, .grid_stride = c->info.stride,
                               .window_past = c->info.past, .window_future = c->info.future,
                               .atlas_width = optimize ? c->atlas_w : 0, .atlas_height = optimize ? c->atlas_h : 0,
                               .atlas_tiles = optimize ? c->info.max_tiles : 0};
}

vgx_result vgx_get_output(const vgx_context *c, vgx_output which, vgx_image *out)
{
    if (!c || !out || (unsigned)which > VGX_OUTPUT_F || !c->out[which].image)
        return VGX_ERROR_INVALID_ARGUMENT;
    *out = (vgx_image){c->out[which].image, c->out[which].view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    return VGX_SUCCESS;
}

/* ------------------------------------------------------------------------- */
/* The frame's plan                                                          */
/* ------------------------------------------------------------------------- */

static vg_status begin_frame(vgx_context *c, int64_t index, int slot)
{
    if (index < 0 || index > ((int64_t)1 << 40)) {
        vg_error("vgx_begin_frame: frame_index %lld is out of range (0 to 2^40)", (long long)index);
        return VG_ERR_ARG;
    }
    int stride = c->desc.keyframe_stride;
    double fps = c->desc.fps;
    if (c->next_pass) {
        vg_error("vgx_begin_frame: the last dispatch stopped after pass %u of %u", c->next_pass,
                 rg_order_count(c->graph));
        return VG_ERR_ARG;
    }
    vg_status st = disparity_gpu_prepare(c->d, (long)index, slot);
    if (st != VG_OK)
        return st;
    int count;
    disparity_gpu_keyframes(c->d, &c->key_first, &count);
    frame_times t = frame_times_at((long)index, fps, stride);
    c->plan = (vgx_frame_plan){.frame_index = index, .time_s = t.t, .prev_key_time_s = t.t_prev,
                               .next_key_time_s = t.t_next, .keyframe_count = (uint32_t)count};
    c->planned = true;
    c->next_index = index + 1;
    return VG_OK;
}

vgx_result vgx_begin_frame(vgx_context *c, int64_t frame_index, vgx_frame_plan *plan)
{
    if (!c)
        return VGX_ERROR_INVALID_ARGUMENT;
    message_to m;
    vg_log_sink was = sink_begin(&m, c->desc.message, c->desc.message_user);
    vg_status st = begin_frame(c, frame_index, (int)((c->serial + 1) % c->frames_in_flight));
    vg_log_set_sink(was);
    if (st == VG_OK && plan)
        *plan = c->plan;
    return result_of(st);
}

vgx_result vgx_engine_begin_frame(vgx_context *c, int64_t frame_index, int slot, vgx_frame_plan *plan)
{
    vg_status st = begin_frame(c, frame_index, slot);
    if (st == VG_OK && plan)
        *plan = c->plan;
    return result_of(st);
}

vgx_result vgx_get_keyframe(const vgx_context *c, uint32_t i, vgx_keyframe *out)
{
    if (!c || !out || !c->planned || i >= c->plan.keyframe_count)
        return VGX_ERROR_INVALID_ARGUMENT;
    int stride = c->desc.keyframe_stride;
    double fps = c->desc.fps, step = stride / fps;
    long k = c->key_first + (long)i;
    /* The times the frame at that keyframe would be rendered at, and its
     * neighbouring keyframes (keyframe_gpu, the engine's renderer of the atlas). */
    double t = (double)(k * stride) / fps;
    *out = (vgx_keyframe){.index = k, .time_s = t, .prev_time_s = t - step, .next_time_s = t + step,
                          .scissor = {{0, (int32_t)(i * c->info.ny)}, {c->info.nx, c->info.ny}}};
    disparity_gpu_atlas_matrix(c->d, (int)i, out->atlas_from_clip);
    return VGX_SUCCESS;
}

void vgx_restart(vgx_context *c)
{
    if (c)
        disparity_gpu_restart(c->d);
}

/* ------------------------------------------------------------------------- */
/* The frame's graph                                                         */
/* ------------------------------------------------------------------------- */

/* The graph usage a host layout stands for: how the dispatch finds the
 * image and how it leaves it. */
static rg_usage usage_of_layout(VkImageLayout layout)
{
    switch (layout) {
    case VK_IMAGE_LAYOUT_GENERAL: return RG_STORAGE_READ;
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL: return RG_SAMPLED;
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL: return RG_COLOR_WRITE;
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL: return RG_TRANSFER_SRC;
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL: return RG_TRANSFER_DST;
    case VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL: return RG_SAMPLED;   /* of a depth format */
    case VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL: return RG_DEPTH_WRITE;
    default: return RG_USAGE_NONE;
    }
}

static void depth_execute(const rg_context *ctx, void *user)
{
    vgx_context *c = user;
    VkDescriptorImageInfo z = rg_ctx_sampled_info(ctx, c->inputs[0], c->nearest);
    VkDescriptorImageInfo l = rg_ctx_image_info(ctx, c->r_linear);
    gpu_binding b[2] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &z, VK_NULL_HANDLE, NULL}, GPU_STORAGE_IMAGE(&l)};
    gpu_compute_kit_bind_list(c->gpu, rg_ctx_cmd(ctx), &c->depth_kit, 0, b, 2, c->depth_m);
    vkCmdDispatch(rg_ctx_cmd(ctx), (c->desc.width + 7) / 8, (c->desc.height + 7) / 8, 1);
}

static void constants_execute(const rg_context *ctx, void *user)
{
    vgx_context *c = user;
    vkCmdUpdateBuffer(rg_ctx_cmd(ctx), c->ubo.buffer, 0, sizeof c->constants, &c->constants);
    if (c->curve)
        vkCmdUpdateBuffer(rg_ctx_cmd(ctx), c->warp_ubo.buffer, 0, sizeof c->warp, &c->warp);
}

/* The inputs in a fixed order: the frame's G-buffer, then the atlas's. */
static const char *const input_names[VGX_INPUTS] = {
    "frame.depth", "frame.saliency", "frame.motion", "frame.ids",
    "keyframes.depth", "keyframes.saliency", "keyframes.motion", "keyframes.ids", "color",
};
static const VkFormat input_formats[4] = {VK_FORMAT_R32_SFLOAT, VK_FORMAT_R8G8B8A8_UNORM,
                                          VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32_UINT};

static void inputs_of(const vgx_dispatch_desc *d, vgx_image out[VGX_INPUTS])
{
    const vgx_gbuffer *gb[2] = {&d->frame, &d->keyframes};
    for (int i = 0; i < 2; i++) {
        out[4 * i + 0] = gb[i]->depth;
        out[4 * i + 1] = gb[i]->saliency;
        out[4 * i + 2] = gb[i]->motion;
        out[4 * i + 3] = gb[i]->ids;
    }
    out[VGX_COLOR] = d->color;
}

/* Which inputs the context reads: the frame's depth always, saliency with
 * VGX_CONTEXT_SALIENCY, the frame's motion and ids with f, the atlas with
 * keyframes. */
static bool input_used(const vgx_context *c, int i)
{
    bool optimize = c->desc.flags & VGX_CONTEXT_OPTIMIZE, saliency = c->desc.flags & VGX_CONTEXT_SALIENCY;
    int kind = i % 4;
    if (i == VGX_COLOR)
        return c->desc.flags & VGX_CONTEXT_EYES;
    if (i >= 4 && !has_keyframes(c))
        return false;
    return kind == 0 || (kind == 1 ? saliency : i >= 4 || optimize);
}

/* The GPU's progress: the serial of the last dispatch it has run (every
 * one before it has run too). */
static uint32_t progress(const vgx_context *c)
{
    return *(const volatile uint32_t *)c->progress.mapped;
}

/* Frees the retired graphs whose last frame has completed: the host waited
 * for its fence (the frames-in-flight contract: frame serial - N before
 * recording frame serial), so the GPU has run it and Vulkan knows it has
 * (the GPU's own mark alone would free it before the host's wait tells the
 * validation layer so). */
static void free_retired(vgx_context *c, uint32_t serial)
{
    uint32_t done = progress(c);
    int kept = 0;
    for (int i = 0; i < c->retired_count; i++) {
        uint32_t last = c->retired[i].last;
        if ((int32_t)(serial - last) >= (int32_t)c->frames_in_flight && (int32_t)(done - last) >= 0)
            rg_destroy(c->retired[i].graph);
        else
            c->retired[kept++] = c->retired[i];
    }
    c->retired_count = kept;
}

static vg_status build_graph(vgx_context *c, const VkImageLayout layouts[VGX_INPUTS], int warp_map)
{
    /* What the replaced graph's dispatches still in flight use stays until
     * the GPU has run the last of them. */
    if (c->graph) {
        free_retired(c, c->serial + 1);
        if (c->retired_count == VGX_RETIRED) {
            vg_error("vgx_dispatch: %d configurations were replaced within the frames in flight; dispatch with "
                     "one configuration until the GPU catches up", VGX_RETIRED);
            return VG_ERR_ARG;
        }
        c->retired[c->retired_count++] = (vgx_retired){c->graph, c->serial};
        c->graph = NULL;
    }
    rg_graph *g = c->graph = rg_create();
    if (!g)
        return VG_ERR_NOMEM;
    bool optimize = c->desc.flags & VGX_CONTEXT_OPTIMIZE;
    frame_resources *res = &c->res;
    *res = (frame_resources){0};
    res->ubo = rg_import_buffer(g, &(rg_buffer_desc){"vgx.constants", sizeof(vg_frame_ubo)},
                                &(rg_import_desc){RG_UNIFORM, RG_UNIFORM});
    bool device = c->graph_depth_kind == VGX_DEPTH_DEVICE;
    for (int i = 0; i < VGX_INPUTS; i++) {
        c->inputs[i] = (rg_res){0};
        bool blank = i % 4 == 1 && !(c->desc.flags & VGX_CONTEXT_SALIENCY) && (i < 4 || has_keyframes(c));
        if (!input_used(c, i) && !blank)
            continue;
        bool frame = i < 4 || i == VGX_COLOR;
        uint32_t w = frame ? c->desc.width : c->atlas_w, h = frame ? c->desc.height : c->atlas_h;
        rg_usage u = blank ? RG_STORAGE_READ : usage_of_layout(layouts[i]);
        VkFormat format = i == 0 && device ? c->graph_depth_format
                          : i == VGX_COLOR  ? VK_FORMAT_R8G8B8A8_UNORM
                                            : input_formats[i % 4];
        c->inputs[i] = rg_import_image(g, &(rg_image_desc){input_names[i], format, w, h, 1},
                                       &(rg_import_desc){u, u});
    }
    res->depth = c->inputs[0], res->color = c->inputs[1], res->motion = c->inputs[2], res->ids = c->inputs[3];
    c->r_linear = (rg_res){0};
    if (device) /* the z-buffer made linear: what every later pass reads */
        res->depth = c->r_linear = rg_import_image(g, &(rg_image_desc){"vgx.depth.linear", VK_FORMAT_R32_SFLOAT,
                                                                       c->desc.width, c->desc.height, 1},
                                                   &(rg_import_desc){RG_SAMPLED, RG_SAMPLED});
    disparity_gpu_atlas atlas = {.depth = c->inputs[4], .color = c->inputs[5], .motion = c->inputs[6],
                                 .ids = c->inputs[7]};
    rg_import_desc out = {RG_SAMPLED, RG_SAMPLED};
    static const char *const names[3] = {"disparity.g", "disparity.h", "disparity.f"};
    rg_res *maps[3] = {&res->g, &res->h, &res->f};
    for (int i = 0; i < (optimize ? 3 : 2); i++)
        *maps[i] = rg_import_image(g, &(rg_image_desc){names[i], VK_FORMAT_R32_SFLOAT, c->desc.width,
                                                       c->desc.height, 1}, &out);

    if (c->curve) {
        c->r_warp_ubo = rg_import_buffer(g, &(rg_buffer_desc){"vgx.warp.constants", sizeof(warp_constants)},
                                         &(rg_import_desc){RG_UNIFORM, RG_UNIFORM});
        c->r_curve = rg_import_buffer(g, &(rg_buffer_desc){"warp.curve", sizeof(vgx_curve_data)},
                                      &(rg_import_desc){RG_STORAGE_READ, RG_STORAGE_READ});
    }
    rg_pass p = rg_pass_add(g, &(rg_pass_desc){"vgx.constants", RG_PASS_TRANSFER, constants_execute, c, false});
    rg_use(g, p, res->ubo, RG_TRANSFER_DST);
    if (c->curve)
        rg_use(g, p, c->r_warp_ubo, RG_TRANSFER_DST);
    if (device) {
        p = rg_pass_add(g, &(rg_pass_desc){"vgx.depth", RG_PASS_COMPUTE, depth_execute, c, false});
        rg_use(g, p, c->inputs[0], RG_SAMPLED);
        rg_use(g, p, c->r_linear, RG_STORAGE_WRITE);
    }
    disparity_gpu_add(c->d, g, res, has_keyframes(c) ? &atlas : NULL);
    /* The warp's global curve, of the map it reads. */
    if (c->curve)
        curve_gpu_add(c->curve, g, res->depth, *maps[warp_map], c->r_curve);
    /* The eyes, moved by the same map. */
    if (c->eyes) {
        static const char *const eye_names[2] = {"vgx.eyes.left", "vgx.eyes.right"};
        for (int i = 0; i < 2; i++)
            c->r_eye[i] = rg_import_image(g, &(rg_image_desc){eye_names[i], VK_FORMAT_R8G8B8A8_UNORM, c->desc.width,
                                                                c->desc.height, 1}, &out);
        eyes_gpu_add(c->eyes, g, res->ubo, res->depth, *maps[warp_map], c->inputs[VGX_COLOR], c->r_eye[0],
                     c->r_eye[1]);
    }
    vg_status st = rg_compile(g);
    if (st == VG_OK)
        st = rg_realize(g, c->gpu);
    if (st != VG_OK)
        return st;
    rg_bind_buffer(g, res->ubo, c->ubo.buffer);
    for (int i = 0; i < (optimize ? 3 : 2); i++)
        rg_bind_image(g, *maps[i], c->out[i].image, c->out[i].view);
    if (device)
        rg_bind_image(g, c->r_linear, c->linear.image, c->linear.view);
    if (c->curve) {
        rg_bind_buffer(g, c->r_warp_ubo, c->warp_ubo.buffer);
        rg_bind_buffer(g, c->r_curve, c->curve_buf.buffer);
    }
    for (int i = 0; i < 2 && c->eyes; i++)
        rg_bind_image(g, c->r_eye[i], c->eye[i].image, c->eye[i].view);
    disparity_gpu_bind(c->d, g);
    memcpy(c->layouts, layouts, sizeof c->layouts);
    c->graph_warp_map = warp_map;
    return VG_OK;
}

/* The first dispatch finds the context's own images undefined: they enter
 * the layouts every later dispatch finds them in. */
static void first_transitions(vgx_context *c, VkCommandBuffer cmd)
{
    for (int i = 0; i < 8; i++) {
        const gpu_image *img = i < 3 ? &c->out[i] : i == 5 ? &c->linear : i < 5 ? &c->blank[i - 3] : &c->eye[i - 6];
        if (img->image)
            gpu_cmd_enter_layout(cmd, img->image, VK_IMAGE_ASPECT_COLOR_BIT,
                                 i == 3 || i == 4 ? VK_IMAGE_LAYOUT_GENERAL : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
}

static vg_status check_image(const char *field, const vgx_image *img, bool device_depth)
{
    if (!img->image || !img->view) {
        vg_error("vgx_dispatch_desc.%s: image or view is null", field);
        return VG_ERR_ARG;
    }
    bool depth_layout = img->layout == VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL ||
                        img->layout == VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    if (device_depth != depth_layout) {
        vg_error("vgx_dispatch_desc.%s.layout is %d; %s", field, (int)img->layout,
                 device_depth ? "a z-buffer (VGX_DEPTH_DEVICE) is read in DEPTH_READ_ONLY_OPTIMAL or "
                                "DEPTH_ATTACHMENT_OPTIMAL"
                              : "only a z-buffer (VGX_DEPTH_DEVICE) is given in a depth layout");
        return VG_ERR_ARG;
    }
    if (usage_of_layout(img->layout) == RG_USAGE_NONE) {
        vg_error("vgx_dispatch_desc.%s.layout is %d; give GENERAL, SHADER_READ_ONLY_OPTIMAL, "
                 "COLOR_ATTACHMENT_OPTIMAL, TRANSFER_SRC_OPTIMAL or TRANSFER_DST_OPTIMAL", field, (int)img->layout);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

static void fill_warp(vgx_context *c, const vgx_dispatch_desc *d)
{
    const vgx_warp_settings *s = &c->desc.warp;
    warp_constants *w = &c->warp;
    memcpy(w->view_proj, d->view_proj, sizeof w->view_proj);
    memcpy(w->viewport, c->constants.viewport.v, 16);
    memcpy(w->rig, c->constants.rig.v, 16);
    memcpy(w->display, c->constants.display.v, 16);
    /* The engine's defaults (warp/warp_settings.h), as its frame resolves them. */
    warp_settings ws = warp_settings_defaults((warp_settings){s->tess_px, s->tess_error_px, s->max_tess_level,
                                                              s->depth_epsilon, s->halton_radius_px});
    uint32_t level = ws.max_level;
    if (level > c->gpu->props.limits.maxTessellationGenerationLevel)
        level = c->gpu->props.limits.maxTessellationGenerationLevel;
    w->warp[0] = (float)ws.tess_px;
    w->warp[1] = (float)ws.tess_error_px;
    w->warp[2] = (float)ws.depth_epsilon;
    w->warp[3] = (float)ws.halton_radius_px;
    w->warp2[0] = (float)level;
    curve_gpu_set_background(c->curve, d->background_depth_m);
}

static void fill_constants(vgx_context *c, const vgx_rig *rig)
{
    stereo_camera cam;
    stereo_camera_init(&cam, &(stereo_camera_desc){.interaxial_m = rig->interaxial_m,
                                                   .convergence_m = rig->convergence_m, .hfov_deg = rig->hfov_deg,
                                                   .image_width = (int)c->desc.width}, &c->display);
    vg_frame_ubo *u = &c->constants;
    memset(u, 0, sizeof *u);
    float w = (float)c->desc.width, h = (float)c->desc.height;
    memcpy(u->viewport.v, (float[4]){w, h, 1.0f / w, 1.0f / h}, 16);
    frame_ctx_ubo_stereo(u, &cam, &c->display, c->desc.width);
}

static vg_status dispatch(vgx_context *c, const vgx_dispatch_desc *d)
{
    if (!d->command_buffer) {
        vg_error("vgx_dispatch_desc.command_buffer is null");
        return VG_ERR_ARG;
    }
    vgx_image in[VGX_INPUTS];
    inputs_of(d, in);
    VkImageLayout layouts[VGX_INPUTS] = {0};
    for (int i = 0; i < VGX_INPUTS; i++) {
        if (!input_used(c, i))
            continue;
        vg_status st = check_image(input_names[i], &in[i], i == 0 && d->depth_kind == VGX_DEPTH_DEVICE);
        if (st != VG_OK)
            return st;
        layouts[i] = in[i].layout;
    }
    if (!(d->rig.hfov_deg > 0 && d->rig.hfov_deg < 180) || !(d->rig.interaxial_m >= 0 && d->rig.interaxial_m < 1e3) ||
        !(d->rig.convergence_m >= 0 && d->rig.convergence_m < 1e6)) {
        vg_error("vgx_dispatch_desc.rig: hfov_deg (%g) must be in (0, 180), interaxial_m (%g) and convergence_m (%g) "
                 "not negative", d->rig.hfov_deg, d->rig.interaxial_m, d->rig.convergence_m);
        return VG_ERR_ARG;
    }
    bool optimize = c->desc.flags & VGX_CONTEXT_OPTIMIZE;
    VkFormat depth_format = d->depth_format ? d->depth_format : VK_FORMAT_D32_SFLOAT;
    if ((unsigned)d->depth_kind > VGX_DEPTH_DEVICE ||
        (d->depth_kind == VGX_DEPTH_DEVICE && gpu_format_aspect(depth_format) != VK_IMAGE_ASPECT_DEPTH_BIT &&
         depth_format != VK_FORMAT_D24_UNORM_S8_UINT && depth_format != VK_FORMAT_D32_SFLOAT_S8_UINT)) {
        vg_error("vgx_dispatch_desc.depth_kind (%d) or .depth_format (%d) is not one vergence reads",
                 (int)d->depth_kind, (int)d->depth_format);
        return VG_ERR_ARG;
    }
    if (d->depth_kind == VGX_DEPTH_DEVICE) {
        const float *m = d->projection;
        bool finite = true;
        for (int i = 0; i < 16; i++)
            finite = finite && isfinite(m[i]);
        if (!finite || (m[10] == 0 && m[11] == 0)) {
            vg_error("vgx_dispatch_desc.projection: VGX_DEPTH_DEVICE needs the finite projection the z-buffer was "
                     "drawn with");
            return VG_ERR_ARG;
        }
    }
    /* A new frame: the one frames_in_flight before it has completed (the
     * host waited for its fence), so the GPU wrote its serial. */
    uint32_t serial = c->serial + 1, in_flight = c->frames_in_flight;
    if (d->first_pass == 0 && serial > in_flight && (int32_t)(progress(c) - (serial - in_flight)) < 0) {
        vg_error("vgx_dispatch: this would be frame %u and the GPU has not completed frame %u: "
                 "vgx_context_desc.frames_in_flight is %u; wait for that frame's fence before recording this one",
                 serial, serial - in_flight, in_flight);
        return VG_ERR_ARG;
    }
    if (!c->planned) {
        if (optimize) {
            vg_error("vgx_dispatch: call vgx_begin_frame first (a context with VGX_CONTEXT_OPTIMIZE plans each "
                     "frame's keyframes)");
            return VG_ERR_ARG;
        }
        vg_status st = begin_frame(c, c->next_index, (int)((c->serial + 1) % c->frames_in_flight));
        if (st != VG_OK)
            return st;
    }
    uint32_t first = d->first_pass;
    int warp_map = d->warp_map == VGX_WARP_MAP_G ? VGX_OUTPUT_G : d->warp_map == VGX_WARP_MAP_H ? VGX_OUTPUT_H
                   : d->warp_map == VGX_WARP_MAP_F || optimize                               ? VGX_OUTPUT_F
                                                                                             : VGX_OUTPUT_H;
    if (c->curve) {
        bool finite = true;
        for (int i = 0; i < 16; i++)
            finite = finite && isfinite(d->view_proj[i]);
        if (!finite || !(d->background_depth_m > 0) || (unsigned)d->warp_map > VGX_WARP_MAP_F ||
            (warp_map == VGX_OUTPUT_F && !optimize)) {
            vg_error("vgx_dispatch_desc: the warp needs a finite view_proj, a positive background_depth_m (%g) and "
                     "a warp_map the context makes (%d; f needs VGX_CONTEXT_OPTIMIZE)", d->background_depth_m,
                     (int)d->warp_map);
            return VG_ERR_ARG;
        }
    }
    if (c->eyes && ((unsigned)d->warp_map > VGX_WARP_MAP_F || (warp_map == VGX_OUTPUT_F && !optimize))) {
        vg_error("vgx_dispatch_desc.warp_map (%d): the eyes need a map the context makes (f needs "
                 "VGX_CONTEXT_OPTIMIZE)", (int)d->warp_map);
        return VG_ERR_ARG;
    }
    bool rebuild = memcmp(c->layouts, layouts, sizeof layouts) != 0 || warp_map != c->graph_warp_map ||
                   d->depth_kind != c->graph_depth_kind ||
                   (d->depth_kind == VGX_DEPTH_DEVICE && depth_format != c->graph_depth_format);
    if (rebuild && first > 0) {
        vg_error("vgx_dispatch_desc: pass %u was given other images' layouts or another warp_map than pass 0", first);
        return VG_ERR_ARG;
    }
    if (rebuild) {
        c->graph_depth_kind = d->depth_kind;
        c->graph_depth_format = depth_format;
        vg_status st = build_graph(c, layouts, warp_map);
        if (st != VG_OK)
            return st;
    }
    /* The passes of this configuration (a z-buffer adds vgx.depth). */
    uint32_t passes = rg_order_count(c->graph);
    uint32_t end = d->pass_count ? first + d->pass_count : passes;
    if (first != c->next_pass || end > passes || end <= first) {
        vg_error("vgx_dispatch_desc: passes %u..%u of %u; the next one due is %u", first, end - 1, passes,
                 c->next_pass);
        return VG_ERR_ARG;
    }
    if (first > 0) {
        rg_execute_range(c->graph, d->command_buffer, first, end);
        if (end == passes)
            gpu_cmd_mark(d->command_buffer, c->progress.buffer, c->serial);
        c->next_pass = end == passes ? 0 : end;
        c->planned = c->next_pass != 0;
        return VG_OK;
    }
    for (int i = 0; i < VGX_INPUTS; i++) {
        if (input_used(c, i))
            rg_bind_image(c->graph, c->inputs[i], in[i].image, in[i].view);
        else if (c->inputs[i].id)
            rg_bind_image(c->graph, c->inputs[i], c->blank[i / 4].image, c->blank[i / 4].view);
    }
    fill_constants(c, &d->rig);
    c->device_depth = d->depth_kind == VGX_DEPTH_DEVICE;
    if (c->device_depth) {
        const float *m = d->projection;
        memcpy(c->depth_m, (float[4]){m[10], m[11], m[14], m[15]}, sizeof c->depth_m);
    }
    if (c->curve) {
        fill_warp(c, d);
        c->warp_map = warp_map;
    }

    VkCommandBuffer cmd = d->command_buffer;
    if (!c->initialised) {
        first_transitions(c, cmd);
        c->initialised = true;
    }
    /* The host's earlier writes to its images, whichever stage made them:
     * the graph's first barrier. */
    c->serial = serial;
    free_retired(c, serial);
    rg_execute_range(c->graph, cmd, 0, end);
    if (end == passes)
        gpu_cmd_mark(cmd, c->progress.buffer, serial);
    c->next_pass = end == passes ? 0 : end;
    c->planned = c->next_pass != 0;
    return VG_OK;
}

uint32_t vgx_pass_count(const vgx_context *c)
{
    return c && c->graph ? rg_order_count(c->graph) : 0;
}

const char *vgx_pass_name(const vgx_context *c, uint32_t pass)
{
    if (!c || !c->graph || pass >= rg_order_count(c->graph))
        return NULL;
    return rg_pass_name(c->graph, rg_order_pass(c->graph, pass));
}

vgx_result vgx_get_warp(const vgx_context *c, vgx_warp *out)
{
    if (!c || !out || !c->curve)
        return VGX_ERROR_INVALID_ARGUMENT;
    const gpu_image *t = &c->out[c->warp_map];
    *out = (vgx_warp){.constants = c->warp_ubo.buffer, .constants_size = sizeof(warp_constants),
                      .depth = c->device_depth ? (vgx_image){c->linear.image, c->linear.view,
                                                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}
                                               : (vgx_image){0},
                      .target = {t->image, t->view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                      .curve = c->curve_buf.buffer, .curve_size = sizeof(vgx_curve_data)};
    return VGX_SUCCESS;
}

void vgx_warp_bindings(VkShaderStageFlags stages, VkDescriptorSetLayoutBinding b[4])
{
    static const VkDescriptorType types[4] = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                                              VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                              VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                              VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    for (uint32_t i = 0; i < 4; i++)
        b[i] = (VkDescriptorSetLayoutBinding){.binding = i, .descriptorType = types[i], .descriptorCount = 1,
                                              .stageFlags = stages};
}

vgx_result vgx_dispatch(vgx_context *c, const vgx_dispatch_desc *desc)
{
    if (!c || !desc)
        return VGX_ERROR_INVALID_ARGUMENT;
    message_to m;
    vg_log_sink was = sink_begin(&m, c->desc.message, c->desc.message_user);
    /* A host built against 0.1 gives 0.1's members; the newer stay zero. */
    vgx_dispatch_desc d = {0};
    memcpy(&d, desc, c->v01 ? VGX_DISPATCH_DESC_SIZE_0_1 : sizeof d);
    vg_status st = dispatch(c, &d);
    vg_log_set_sink(was);
    return result_of(st);
}

vgx_result vgx_get_eye(const vgx_context *c, uint32_t eye, vgx_image *out)
{
    if (!c || !out || eye > 1 || !c->eye[eye].image)
        return VGX_ERROR_INVALID_ARGUMENT;
    *out = (vgx_image){c->eye[eye].image, c->eye[eye].view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    return VGX_SUCCESS;
}
