/* vergence — the public API (include/vergence/vergence.h) over the engine's
 * passes: a small frame graph of its own whose imported resources are the
 * host's images, recorded into the host's command buffer. */
#include "vergence/vergence.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "disparity/gpu/disparity_gpu.h"
#include "disparity/gpu/operator_gpu.h"
#include "disparity/gpu/original_gpu.h"
#include "graph/graph.h"
#include "shared.h"
#include "stereo/stereo_display.h"

#define VGX_LIBRARY_VERSION VGX_MAKE_VERSION(VERGENCE_VERSION_MAJOR, VERGENCE_VERSION_MINOR, VERGENCE_VERSION_PATCH)

struct vgx_context {
    vgx_context_desc desc;
    gpu *gpu;
    stereo_display display;
    original_gpu original;
    operator_gpu *op;
    gpu_buffer ubo;                   /* vg_frame_ubo: rig, display, viewport (device-local, updated in the command buffer) */
    gpu_image out[2];                 /* g, h */
    gpu_image no_saliency;            /* bound where the operator's saliency goes when the host gives none */
    bool initialised;                 /* the outputs were moved to their steady layouts */

    /* The graph for the host's current input layouts. */
    rg_graph *graph;
    VkImageLayout graph_layouts[2];   /* depth, saliency */
    rg_res r_ubo, r_depth, r_saliency, r_state, r_out[2];
    vgx_dispatch_desc frame;          /* this dispatch's (the passes read it) */
    vg_frame_ubo constants;
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

/* ------------------------------------------------------------------------- */
/* Context                                                                   */
/* ------------------------------------------------------------------------- */

static vg_status check_desc(const vgx_context_desc *d)
{
    uint32_t v = d->header_version, lib = VGX_LIBRARY_VERSION;
    if (VGX_VERSION_MAJOR(v) != VGX_VERSION_MAJOR(lib) ||
        (VGX_VERSION_MAJOR(lib) == 0 && VGX_VERSION_MINOR(v) != VGX_VERSION_MINOR(lib))) {
        vg_error("vgx_context_desc.header_version is %u.%u.%u; this library is %u.%u.%u (set VGX_HEADER_VERSION)",
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
    if ((unsigned)d->op > VGX_OPERATOR_LANG_SMOOTHED || (unsigned)d->preset > VGX_PRESET_STUDY) {
        vg_error("vgx_context_desc.op (%d) or .preset (%d) is not one of the enum's values", (int)d->op,
                 (int)d->preset);
        return VG_ERR_ARG;
    }
    if (!(d->target_range_arcmin >= 0 && d->target_range_arcmin < 600) ||
        !(d->frame_seconds >= 0 && d->frame_seconds < 10)) {
        vg_error("vgx_context_desc.target_range_arcmin (%g) must be in [0, 600) and frame_seconds (%g) in [0, 10)",
                 d->target_range_arcmin, d->frame_seconds);
        return VG_ERR_ARG;
    }
    if (d->flags & ~VGX_CONTEXT_SALIENCY) {
        vg_error("vgx_context_desc.flags has unknown bits 0x%x", d->flags & ~VGX_CONTEXT_SALIENCY);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

static vg_status create(vgx_context *c)
{
    const vgx_context_desc *d = &c->desc;
    vg_status st = gpu_import(&(gpu_import_desc){.instance = d->instance, .physical_device = d->physical_device,
                                                 .device = d->device, .queue_family = d->queue_family,
                                                 .alloc = d->allocator}, &c->gpu);
    if (st != VG_OK)
        return st;
    stereo_display_init(&c->display, &(stereo_display_desc){
        .diagonal_in = d->display.diagonal_in, .aspect_w = d->display.aspect_w, .aspect_h = d->display.aspect_h,
        .res_x = d->display.res_x, .res_y = d->display.res_y, .distance_m = d->display.distance_m,
        .ipd_m = d->display.ipd_m});
    st = original_gpu_create(c->gpu, &c->original);
    if (st == VG_OK)
        /* The frame's statistics on the solver's grid, as the engine's frame fits them. */
        st = operator_gpu_create(c->gpu, &(operator_gpu_desc){
            .op = {.kind = (disp_operator_kind)d->op, .preset = (disp_operator_preset)d->preset,
                   .screen_vergence = c->display.screen_vergence, .range = d->target_range_arcmin,
                   .frame_seconds = d->frame_seconds > 0 ? d->frame_seconds : 1.0 / 60.0},
            .stride = disparity_gpu_grid_stride(d->width, d->height, 0),
            .no_saliency = !(d->flags & VGX_CONTEXT_SALIENCY)}, &c->op);
    if (st == VG_OK)
        st = gpu_buffer_create(c->gpu, &(gpu_buffer_desc){.name = "vgx constants", .size = sizeof(vg_frame_ubo),
                                                          .usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT |
                                                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT}, &c->ubo);
    static const char *const names[2] = {"vgx g", "vgx h"};
    for (int i = 0; i < 2 && st == VG_OK; i++)
        st = gpu_image_create(c->gpu, &(gpu_image_desc){.name = names[i], .format = VK_FORMAT_R32_SFLOAT,
                                                        .width = d->width, .height = d->height,
                                                        .usage = VK_IMAGE_USAGE_STORAGE_BIT |
                                                                 VK_IMAGE_USAGE_SAMPLED_BIT |
                                                                 VK_IMAGE_USAGE_TRANSFER_SRC_BIT}, &c->out[i]);
    if (st == VG_OK && !(d->flags & VGX_CONTEXT_SALIENCY))
        st = gpu_image_create(c->gpu, &(gpu_image_desc){.name = "vgx no saliency", .format = VK_FORMAT_R8G8B8A8_UNORM,
                                                        .width = d->width, .height = d->height,
                                                        .usage = VK_IMAGE_USAGE_STORAGE_BIT}, &c->no_saliency);
    return st;
}

vgx_result vgx_context_create(const vgx_context_desc *desc, vgx_context **out)
{
    if (!out)
        return VGX_ERROR_INVALID_ARGUMENT;
    *out = NULL;
    message_to m;
    vg_log_sink was = sink_begin(&m, desc ? desc->message : NULL, desc ? desc->message_user : NULL);
    vg_status st = VG_ERR_ARG;
    vgx_context *c = NULL;
    if (!desc)
        vg_error("vgx_context_create: desc is null");
    else if ((st = check_desc(desc)) == VG_OK) {
        c = calloc(1, sizeof *c);
        st = c ? VG_OK : VG_ERR_NOMEM;
    }
    if (st == VG_OK) {
        c->desc = *desc;
        st = create(c);
        if (st != VG_OK) {
            vgx_context_destroy(c);
            c = NULL;
        }
    }
    vg_log_set_sink(was);
    *out = c;
    return st == VG_ERR_UNSUPPORTED ? VGX_ERROR_VERSION : result_of(st);
}

void vgx_context_destroy(vgx_context *c)
{
    if (!c)
        return;
    message_to m;
    vg_log_sink was = sink_begin(&m, c->desc.message, c->desc.message_user);
    if (c->gpu) {
        rg_destroy(c->graph);
        for (int i = 0; i < 2; i++)
            gpu_image_destroy(c->gpu, &c->out[i]);
        gpu_image_destroy(c->gpu, &c->no_saliency);
        gpu_buffer_destroy(c->gpu, &c->ubo);
        operator_gpu_destroy(c->op);
        original_gpu_destroy(c->gpu, &c->original);
        gpu_destroy(c->gpu);
    }
    vg_log_set_sink(was);
    free(c);
}

void vgx_target_range(const vgx_context *c, double *lo, double *hi)
{
    double l = NAN, h = NAN;
    if (c)
        operator_gpu_range(c->op, &l, &h);
    if (lo)
        *lo = l;
    if (hi)
        *hi = h;
}

vgx_result vgx_get_output(const vgx_context *c, vgx_output which, vgx_image *out)
{
    if (!c || !out || (unsigned)which > VGX_OUTPUT_H)
        return VGX_ERROR_INVALID_ARGUMENT;
    *out = (vgx_image){c->out[which].image, c->out[which].view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    return VGX_SUCCESS;
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
    default: return RG_USAGE_NONE;
    }
}

static VkDescriptorImageInfo image_of(const rg_context *ctx, rg_res r)
{
    return (VkDescriptorImageInfo){.imageView = rg_ctx_view(ctx, r), .imageLayout = rg_ctx_layout(ctx, r)};
}

static void constants_execute(const rg_context *ctx, void *user)
{
    vgx_context *c = user;
    vkCmdUpdateBuffer(rg_ctx_cmd(ctx), c->ubo.buffer, 0, sizeof c->constants, &c->constants);
}

static void original_execute(const rg_context *ctx, void *user)
{
    vgx_context *c = user;
    VkDescriptorImageInfo depth = image_of(ctx, c->r_depth), g = image_of(ctx, c->r_out[0]);
    original_gpu_record(c->gpu, &c->original, rg_ctx_cmd(ctx), c->ubo.buffer, &depth, &g, c->desc.width,
                        c->desc.height);
}

static void fit_execute(const rg_context *ctx, void *user)
{
    vgx_context *c = user;
    VkDescriptorImageInfo g = image_of(ctx, c->r_out[0]), s = image_of(ctx, c->r_saliency);
    operator_gpu_record_fit(c->op, rg_ctx_cmd(ctx), &g, &s, c->desc.width, c->desc.height);
}

static void map_execute(const rg_context *ctx, void *user)
{
    vgx_context *c = user;
    VkDescriptorImageInfo g = image_of(ctx, c->r_out[0]), h = image_of(ctx, c->r_out[1]);
    operator_gpu_record_map(c->op, rg_ctx_cmd(ctx), &g, &h, c->desc.width, c->desc.height);
}

static vg_status build_graph(vgx_context *c, VkImageLayout depth_layout, VkImageLayout saliency_layout)
{
    rg_destroy(c->graph);
    rg_graph *g = c->graph = rg_create();
    if (!g)
        return VG_ERR_NOMEM;
    uint32_t w = c->desc.width, h = c->desc.height;
    rg_usage du = usage_of_layout(depth_layout), su = usage_of_layout(saliency_layout);
    c->r_ubo = rg_import_buffer(g, &(rg_buffer_desc){"vgx.constants", sizeof(vg_frame_ubo)},
                                &(rg_import_desc){RG_UNIFORM, RG_UNIFORM});
    c->r_depth = rg_import_image(g, &(rg_image_desc){"host.depth", VK_FORMAT_R32_SFLOAT, w, h, 1},
                                 &(rg_import_desc){du, du});
    c->r_saliency = rg_import_image(g, &(rg_image_desc){"host.saliency", VK_FORMAT_R8G8B8A8_UNORM, w, h, 1},
                                    &(rg_import_desc){su, su});
    rg_import_desc rw = {RG_STORAGE_READ_WRITE, RG_STORAGE_READ_WRITE}, out = {RG_SAMPLED, RG_SAMPLED};
    c->r_state = rg_import_buffer(g, &(rg_buffer_desc){"disparity.operator.state", operator_gpu_state_size(c->op)}, &rw);
    c->r_out[0] = rg_import_image(g, &(rg_image_desc){"disparity.g", VK_FORMAT_R32_SFLOAT, w, h, 1}, &out);
    c->r_out[1] = rg_import_image(g, &(rg_image_desc){"disparity.h", VK_FORMAT_R32_SFLOAT, w, h, 1}, &out);

    rg_pass p = rg_pass_add(g, &(rg_pass_desc){"vgx.constants", RG_PASS_TRANSFER, constants_execute, c, false});
    rg_use(g, p, c->r_ubo, RG_TRANSFER_DST);
    p = rg_pass_add(g, &(rg_pass_desc){"disparity.original", RG_PASS_COMPUTE, original_execute, c, false});
    rg_use(g, p, c->r_ubo, RG_UNIFORM);
    rg_use(g, p, c->r_depth, RG_STORAGE_READ);
    rg_use(g, p, c->r_out[0], RG_STORAGE_WRITE);
    p = rg_pass_add(g, &(rg_pass_desc){"disparity.operator.fit", RG_PASS_COMPUTE, fit_execute, c, false});
    rg_use(g, p, c->r_out[0], RG_STORAGE_READ);
    rg_use(g, p, c->r_saliency, RG_STORAGE_READ);
    rg_use(g, p, c->r_state, RG_STORAGE_READ_WRITE);
    p = rg_pass_add(g, &(rg_pass_desc){"disparity.operator", RG_PASS_COMPUTE, map_execute, c, false});
    rg_use(g, p, c->r_out[0], RG_STORAGE_READ);
    rg_use(g, p, c->r_state, RG_STORAGE_READ);
    rg_use(g, p, c->r_out[1], RG_STORAGE_WRITE);
    vg_status st = rg_compile(g);
    if (st == VG_OK)
        st = rg_realize(g, c->gpu);
    if (st != VG_OK)
        return st;
    rg_bind_buffer(g, c->r_ubo, c->ubo.buffer);
    rg_bind_buffer(g, c->r_state, operator_gpu_state(c->op));
    for (int i = 0; i < 2; i++)
        rg_bind_image(g, c->r_out[i], c->out[i].image, c->out[i].view);
    c->graph_layouts[0] = depth_layout;
    c->graph_layouts[1] = saliency_layout;
    return VG_OK;
}

/* The first dispatch finds the context's own images undefined: they enter
 * the layouts every later dispatch finds them in. */
static void first_transitions(vgx_context *c, VkCommandBuffer cmd)
{
    VkImageMemoryBarrier2 b[3];
    uint32_t n = 0;
    for (int i = 0; i < 3; i++) {
        const gpu_image *img = i < 2 ? &c->out[i] : &c->no_saliency;
        if (!img->image)
            continue;
        b[n++] = (VkImageMemoryBarrier2){
            .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
            .srcStageMask = VK_PIPELINE_STAGE_2_NONE,
            .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
            .dstAccessMask = VK_ACCESS_2_SHADER_READ_BIT,
            .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
            .newLayout = i < 2 ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_GENERAL,
            .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
            .image = img->image,
            .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1},
        };
    }
    vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                   .imageMemoryBarrierCount = n, .pImageMemoryBarriers = b});
}

static vg_status check_image(const char *name, const vgx_image *img)
{
    if (!img->image || !img->view) {
        vg_error("vgx_dispatch_desc.%s: image or view is null", name);
        return VG_ERR_ARG;
    }
    if (usage_of_layout(img->layout) == RG_USAGE_NONE) {
        vg_error("vgx_dispatch_desc.%s.layout is %d; give GENERAL, SHADER_READ_ONLY_OPTIMAL, "
                 "COLOR_ATTACHMENT_OPTIMAL, TRANSFER_SRC_OPTIMAL or TRANSFER_DST_OPTIMAL", name, (int)img->layout);
        return VG_ERR_ARG;
    }
    return VG_OK;
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
    memcpy(u->rig.v, (float[4]){(float)cam.gain_px, (float)cam.convergence_m, (float)cam.interaxial_m, 0}, 16);
    memcpy(u->display.v, (float[4]){(float)c->display.ipd_m, (float)c->display.distance_m,
                                    (float)(c->display.width_m / c->desc.width), (float)c->display.screen_vergence},
           16);
}

static vg_status dispatch(vgx_context *c, const vgx_dispatch_desc *d)
{
    if (!d->command_buffer) {
        vg_error("vgx_dispatch_desc.command_buffer is null");
        return VG_ERR_ARG;
    }
    bool saliency = c->desc.flags & VGX_CONTEXT_SALIENCY;
    vg_status st = check_image("depth", &d->depth);
    if (st == VG_OK && saliency)
        st = check_image("saliency", &d->saliency);
    if (st != VG_OK)
        return st;
    if (!(d->rig.hfov_deg > 0 && d->rig.hfov_deg < 180) || !(d->rig.interaxial_m >= 0 && d->rig.interaxial_m < 1e3) ||
        !(d->rig.convergence_m >= 0 && d->rig.convergence_m < 1e6)) {
        vg_error("vgx_dispatch_desc.rig: hfov_deg (%g) must be in (0, 180), interaxial_m (%g) and convergence_m (%g) "
                 "not negative", d->rig.hfov_deg, d->rig.interaxial_m, d->rig.convergence_m);
        return VG_ERR_ARG;
    }
    VkImageLayout sl = saliency ? d->saliency.layout : VK_IMAGE_LAYOUT_GENERAL;
    if (!c->graph || c->graph_layouts[0] != d->depth.layout || c->graph_layouts[1] != sl) {
        st = build_graph(c, d->depth.layout, sl);
        if (st != VG_OK)
            return st;
    }
    rg_bind_image(c->graph, c->r_depth, d->depth.image, d->depth.view);
    if (saliency)
        rg_bind_image(c->graph, c->r_saliency, d->saliency.image, d->saliency.view);
    else
        rg_bind_image(c->graph, c->r_saliency, c->no_saliency.image, c->no_saliency.view);
    fill_constants(c, &d->rig);

    VkCommandBuffer cmd = d->command_buffer;
    if (!c->initialised) {
        first_transitions(c, cmd);
        c->initialised = true;
    }
    /* The host's earlier writes to its images, whichever stage made them. */
    VkMemoryBarrier2 host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                             .srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                             .srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT,
                             .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
                             .dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT};
    vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                   .memoryBarrierCount = 1, .pMemoryBarriers = &host});
    for (uint32_t o = 0; o < rg_order_count(c->graph); o++)
        rg_execute_pass(c->graph, cmd, o);
    return VG_OK;
}

vgx_result vgx_dispatch(vgx_context *c, const vgx_dispatch_desc *desc)
{
    if (!c || !desc)
        return VGX_ERROR_INVALID_ARGUMENT;
    message_to m;
    vg_log_sink was = sink_begin(&m, c->desc.message, c->desc.message_user);
    vg_status st = dispatch(c, desc);
    vg_log_set_sink(was);
    return result_of(st);
}
