/* The public API (include/vergence/vergence.h) as a host uses it, compiled
 * as C99 (the header's promise). The device comes from the engine's own
 * gpu module, as any host's would from its renderer; everything else goes
 * through vgx_ calls only. */
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <vergence/vergence.h>

#include "core/log.h"
#include "gpu/gpu.h"
#include "stereo/stereo_display.h"
#include "test.h"

/* ------------------------------------------------------------------------- */
/* A host's side                                                             */
/* ------------------------------------------------------------------------- */

typedef struct messages {
    int errors, others;
    char last[512];
} messages;

static void on_message(vgx_severity severity, const char *message, void *user)
{
    messages *m = user;
    if (severity == VGX_SEVERITY_ERROR)
        m->errors++;
    else
        m->others++;
    snprintf(m->last, sizeof m->last, "%s", message);
}

static vgx_context_desc context_desc(const gpu *g, uint32_t w, uint32_t h, messages *m)
{
    vgx_context_desc d;
    memset(&d, 0, sizeof d);
    d.header_version = VGX_HEADER_VERSION;
    d.instance = g->instance;
    d.physical_device = g->phys;
    d.device = g->device;
    d.queue_family = g->queue_family;
    d.width = w;
    d.height = h;
    d.message = on_message;
    d.message_user = m;
#ifdef VGX_CONTEXT_DEBUG_UTILS /* 0.2 */
    /* Under validation the instance has debug utils: every context names its
     * objects and labels its passes, and the layer checks each call. */
    d.flags = g->debug_utils ? VGX_CONTEXT_DEBUG_UTILS : 0u;
#endif
    return d;
}

/* Copies an output map (SHADER_READ_ONLY_OPTIMAL after a dispatch) into out. */
static int read_map(gpu *g, const vgx_image *img, uint32_t w, uint32_t h, float *out)
{
    gpu_buffer buf;
    CHECK(gpu_buffer_create(g, &(gpu_buffer_desc){.name = "test readback", .size = (VkDeviceSize)w * h * 4,
                                                  .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT, .host_visible = true},
                            &buf) == VG_OK, "readback buffer");
    VkCommandBuffer cmd;
    CHECK(gpu_oneshot_begin(g, &cmd) == VG_OK, "begin");
    VkImageMemoryBarrier2 b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
        .srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
        .dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
        .dstAccessMask = VK_ACCESS_2_TRANSFER_READ_BIT,
        .oldLayout = img->layout,
        .newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = img->image,
        .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1},
    };
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .imageMemoryBarrierCount = 1,
                            .pImageMemoryBarriers = &b};
    vkCmdPipelineBarrier2(cmd, &dep);
    VkBufferImageCopy region = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1}, .imageExtent = {w, h, 1}};
    vkCmdCopyImageToBuffer(cmd, img->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buf.buffer, 1, &region);
    b.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    b.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    b.dstAccessMask = 0;
    b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    b.newLayout = img->layout;
    vkCmdPipelineBarrier2(cmd, &dep);
    VkMemoryBarrier2 host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2, .srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
                             .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
                             .dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT, .dstAccessMask = VK_ACCESS_2_HOST_READ_BIT};
    VkDependencyInfo hd = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                           .pMemoryBarriers = &host};
    vkCmdPipelineBarrier2(cmd, &hd);
    CHECK(gpu_oneshot_submit(g, cmd) == VG_OK, "submit");
    memcpy(out, buf.mapped, (size_t)w * h * 4);
    gpu_buffer_destroy(g, &buf);
    return 0;
}

/* The host's own barrier moving its image to another layout (reads after it). */
static void host_layout(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                        VkImageLayout to)
{
    VkImageMemoryBarrier2 b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
        .srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
        .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
        .dstAccessMask = VK_ACCESS_2_SHADER_READ_BIT,
        .oldLayout = from,
        .newLayout = to,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = image,
        .subresourceRange = {aspect, 0, 1, 0, 1},
    };
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .imageMemoryBarrierCount = 1,
                            .pImageMemoryBarriers = &b};
    vkCmdPipelineBarrier2(cmd, &dep);
}

/* A dispatch of the frame's depth alone, through the test rig (70 degrees,
 * 25 cm converged at 6 m). */
static vgx_dispatch_desc depth_dispatch(VkCommandBuffer cmd, const gpu_image *depth, VkImageLayout layout)
{
    vgx_dispatch_desc dd;
    memset(&dd, 0, sizeof dd);
    dd.command_buffer = cmd;
    dd.frame.depth = (vgx_image){depth->image, depth->view, layout};
    dd.rig.hfov_deg = 70;
    dd.rig.interaxial_m = 0.25;
    dd.rig.convergence_m = 6.0;
    return dd;
}

/* The tests' depth: four vertical bands at k_bands metres. */
static const double k_bands[4] = {2.0, 4.5, 9.0, 40.0};

/* An image of w x h depths (R32_SFLOAT, storage and sampled: a host's
 * linear depth), uploaded; depth NULL: the four bands. */
static int depth_image(gpu *g, uint32_t w, uint32_t h, const float *depth, gpu_image *img)
{
    float *bands = NULL;
    if (!depth) {
        CHECK((bands = malloc((size_t)w * h * sizeof(float))) != NULL, "memory");
        for (uint32_t y = 0; y < h; y++)
            for (uint32_t x = 0; x < w; x++)
                bands[y * w + x] = (float)k_bands[x * 4 / w];
        depth = bands;
    }
    CHECK(gpu_image_create(g, &(gpu_image_desc){.name = "test depth", .format = VK_FORMAT_R32_SFLOAT, .width = w,
                                                .height = h, .usage = VK_IMAGE_USAGE_STORAGE_BIT |
                                                                      VK_IMAGE_USAGE_SAMPLED_BIT |
                                                                      VK_IMAGE_USAGE_TRANSFER_DST_BIT},
                           img) == VG_OK, "depth image");
    CHECK(gpu_image_upload(g, img, depth, (size_t)w * h * sizeof(float)) == VG_OK, "upload");
    free(bands);
    return 0;
}

/* The display and the test rig of depth_dispatch for images w pixels wide. */
static void test_rig(uint32_t w, stereo_display *disp, stereo_camera *cam)
{
    stereo_display_init(disp, NULL);
    stereo_camera_init(cam, &(stereo_camera_desc){.interaxial_m = 0.25, .convergence_m = 6.0, .hfov_deg = 70,
                                                  .image_width = (int)w}, disp);
}

static gpu *make_gpu(void)
{
    gpu *g = NULL;
    if (gpu_create(&(gpu_desc){0}, &g) != VG_OK)
        return NULL;
    return g;
}

/* ------------------------------------------------------------------------- */
/* Cases                                                                     */
/* ------------------------------------------------------------------------- */

/* The library runs a host built against this header: the same major
 * version, a minor version at least the header's (the compat_0_1 build of
 * this file is such a host, built against release 0.1's header). */
static int version(void)
{
    uint32_t lib = vgx_version();
    CHECK(VGX_VERSION_MAJOR(lib) == VGX_VERSION_MAJOR(VGX_HEADER_VERSION) &&
              VGX_VERSION_MINOR(lib) >= VGX_VERSION_MINOR(VGX_HEADER_VERSION),
          "library %u.%u.%u, header %u.%u.%u",
          VGX_VERSION_MAJOR(vgx_version()), VGX_VERSION_MINOR(vgx_version()), VGX_VERSION_PATCH(vgx_version()),
          VGX_VERSION_MAJOR(VGX_HEADER_VERSION), VGX_VERSION_MINOR(VGX_HEADER_VERSION),
          VGX_VERSION_PATCH(VGX_HEADER_VERSION));
    printf("library %u.%u.%u runs this host (header %u.%u.%u)\n", VGX_VERSION_MAJOR(lib), VGX_VERSION_MINOR(lib),
           VGX_VERSION_PATCH(lib), VGX_VERSION_MAJOR(VGX_HEADER_VERSION), VGX_VERSION_MINOR(VGX_HEADER_VERSION),
           VGX_VERSION_PATCH(VGX_HEADER_VERSION));
    CHECK(strcmp(vgx_result_name(VGX_SUCCESS), "VGX_SUCCESS") == 0, "%s", vgx_result_name(VGX_SUCCESS));
    CHECK(strcmp(vgx_result_name(VGX_ERROR_VERSION), "VGX_ERROR_VERSION") == 0, "%s",
          vgx_result_name(VGX_ERROR_VERSION));
    CHECK(strcmp(vgx_result_name((vgx_result)42), "unknown") == 0, "%s", vgx_result_name((vgx_result)42));
    uint32_t n = 0;
    const char *const *exts = vgx_device_extensions(&n);
    CHECK(n == 1 && strcmp(exts[0], VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME) == 0, "%u extensions", n);
    return 0;
}

/* The requirements query lists every missing item at once: nothing on
 * lavapipe, tessellationShader for a warp context once
 * VERGENCE_DISABLE=tessellation takes it away, and a count past the
 * capacity it was given. */
#if VGX_HEADER_VERSION_MINOR >= 2 /* 0.2 */
static int requirements(void)
{
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    const char *names[8] = {0};
    uint32_t n = 99;
    CHECK(vgx_get_missing_requirements(g->phys, VGX_CONTEXT_WARP, names, 8, &n) == VGX_SUCCESS && n == 0,
          "lavapipe lacks %u: %s", n, n ? names[0] : "");
    CHECK(vgx_get_missing_requirements(VK_NULL_HANDLE, 0, names, 8, &n) == VGX_ERROR_INVALID_ARGUMENT, "no device");
    CHECK(vgx_get_missing_requirements(g->phys, 0, NULL, 8, &n) == VGX_ERROR_INVALID_ARGUMENT, "no array");
    CHECK(vgx_get_missing_requirements(g->phys, 0x80, names, 8, &n) == VGX_ERROR_INVALID_ARGUMENT, "unknown flags");
    setenv("VERGENCE_DISABLE", "tessellation", 1);
    CHECK(vgx_get_missing_requirements(g->phys, 0, names, 8, &n) == VGX_SUCCESS && n == 0,
          "without a warp nothing needs tessellation: %u", n);
    CHECK(vgx_get_missing_requirements(g->phys, VGX_CONTEXT_WARP, names, 8, &n) == VGX_ERROR_DEVICE && n == 1 &&
              strcmp(names[0], "tessellationShader") == 0,
          "%u missing, first %s", n, n ? names[0] : "-");
    CHECK(vgx_get_missing_requirements(g->phys, VGX_CONTEXT_WARP, NULL, 0, &n) == VGX_ERROR_DEVICE && n == 1,
          "counted without names: %u", n);
    /* Several missing at once, of each kind (a Vulkan 1.3 feature, a
     * Vulkan 1.0 feature, an extension): every one listed, in one call. */
    setenv("VERGENCE_DISABLE", "tessellation,synchronization2,scalarBlockLayout,VK_KHR_push_descriptor", 1);
    static const char *const want[] = {"synchronization2", "scalarBlockLayout", "tessellationShader",
                                       "VK_KHR_push_descriptor"};
    memset(names, 0, sizeof names);
    CHECK(vgx_get_missing_requirements(g->phys, VGX_CONTEXT_WARP, names, 8, &n) == VGX_ERROR_DEVICE && n == 4,
          "%u missing, want 4", n);
    for (int i = 0; i < 4; i++)
        CHECK(names[i] && strcmp(names[i], want[i]) == 0, "missing item %d is %s, want %s", i, names[i], want[i]);
    CHECK(vgx_get_missing_requirements(g->phys, 0, names, 2, &n) == VGX_ERROR_DEVICE && n == 3 &&
              strcmp(names[1], "scalarBlockLayout") == 0,
          "a plain context: %u missing (want 3: all but tessellation), two named", n);
    unsetenv("VERGENCE_DISABLE");
    printf("requirements: lavapipe has everything; VERGENCE_DISABLE=tessellation: a warp context lacks "
           "tessellationShader; with three more taken away it lists %s, %s, %s and %s at once\n",
           want[0], want[1], want[2], want[3]);
    gpu_destroy(g);
    return 0;
}
#endif

/* Every bad field: one error line through the host's callback naming it,
 * the documented result, no context. */
static int errors(void)
{
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    messages m = {0};
    vgx_context *c = (vgx_context *)1;
    CHECK(vgx_context_create(NULL, &c) == VGX_ERROR_INVALID_ARGUMENT && c == NULL, "null desc");
    CHECK(vgx_context_create(NULL, NULL) == VGX_ERROR_INVALID_ARGUMENT, "null out");


    vgx_context_desc d = context_desc(g, 64, 48, &m);
    d.header_version = VGX_MAKE_VERSION(VGX_VERSION_MAJOR(VGX_HEADER_VERSION) + 1, 0, 0);
    CHECK(vgx_context_create(&d, &c) == VGX_ERROR_VERSION && c == NULL, "version");
    CHECK(m.errors == 1 && strstr(m.last, "header_version"), "%d errors, last '%s'", m.errors, m.last);

    /* A header newer than the library. */
    d = context_desc(g, 64, 48, &m);
    d.header_version = VGX_MAKE_VERSION(VGX_VERSION_MAJOR(vgx_version()), VGX_VERSION_MINOR(vgx_version()) + 1, 0);
    CHECK(vgx_context_create(&d, &c) == VGX_ERROR_VERSION && c == NULL, "newer header");
    CHECK(m.errors == 2 && strstr(m.last, "header_version"), "%d errors, last '%s'", m.errors, m.last);
    m.errors = 1;

    d = context_desc(g, 0, 48, &m);
    CHECK(vgx_context_create(&d, &c) == VGX_ERROR_INVALID_ARGUMENT && c == NULL, "width 0");
    CHECK(m.errors == 2 && strstr(m.last, "width"), "%d errors, last '%s'", m.errors, m.last);

    d = context_desc(g, 64, 48, &m);
    d.device = VK_NULL_HANDLE;
    CHECK(vgx_context_create(&d, &c) == VGX_ERROR_INVALID_ARGUMENT && c == NULL, "null device");
    CHECK(m.errors == 3 && strstr(m.last, "device"), "%d errors, last '%s'", m.errors, m.last);

    d = context_desc(g, 64, 48, &m);
    d.flags = 0x80;
    CHECK(vgx_context_create(&d, &c) == VGX_ERROR_INVALID_ARGUMENT && c == NULL, "flags");
    CHECK(m.errors == 4 && strstr(m.last, "flags"), "%d errors, last '%s'", m.errors, m.last);

    d = context_desc(g, 64, 48, &m);
    d.op = (vgx_operator)9;
    CHECK(vgx_context_create(&d, &c) == VGX_ERROR_INVALID_ARGUMENT && c == NULL, "op");
    CHECK(m.errors == 5 && strstr(m.last, ".op"), "%d errors, last '%s'", m.errors, m.last);
#if VGX_HEADER_VERSION_MINOR >= 2 /* 0.2 */
    d = context_desc(g, 64, 48, &m);
    d.frames_in_flight = VGX_MAX_FRAMES_IN_FLIGHT + 1;
    CHECK(vgx_context_create(&d, &c) == VGX_ERROR_INVALID_ARGUMENT && c == NULL, "frames in flight");
    CHECK(m.errors == 6 && strstr(m.last, "frames_in_flight"), "%d errors, last '%s'", m.errors, m.last);
    m.errors = 5;
#endif

    /* A good context, then bad dispatches: nothing is recorded. */
    d = context_desc(g, 64, 48, &m);
    CHECK(vgx_context_create(&d, &c) == VGX_SUCCESS && c, "create: %s", m.last);
    VkCommandBuffer cmd;
    CHECK(gpu_oneshot_begin(g, &cmd) == VG_OK, "begin");
    vgx_dispatch_desc dd;
    memset(&dd, 0, sizeof dd);
    dd.rig.hfov_deg = 60;
    CHECK(vgx_dispatch(c, &dd) == VGX_ERROR_INVALID_ARGUMENT, "null command buffer");
    CHECK(m.errors == 6 && strstr(m.last, "command_buffer"), "%d errors, last '%s'", m.errors, m.last);
    dd.command_buffer = cmd;
    CHECK(vgx_dispatch(c, &dd) == VGX_ERROR_INVALID_ARGUMENT, "null depth");
    CHECK(m.errors == 7 && strstr(m.last, "depth"), "%d errors, last '%s'", m.errors, m.last);
    vgx_image out;
    CHECK(vgx_get_output(c, VGX_OUTPUT_G, &out) == VGX_SUCCESS, "output");
    dd.frame.depth = out; /* any image will do for the checks before recording */
    dd.frame.depth.layout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    CHECK(vgx_dispatch(c, &dd) == VGX_ERROR_INVALID_ARGUMENT, "layout");
    CHECK(m.errors == 8 && strstr(m.last, "frame.depth.layout"), "%d errors, last '%s'", m.errors, m.last);
    dd.frame.depth.layout = VK_IMAGE_LAYOUT_GENERAL;
    dd.rig.hfov_deg = 0;
    CHECK(vgx_dispatch(c, &dd) == VGX_ERROR_INVALID_ARGUMENT, "hfov");
    CHECK(m.errors == 9 && strstr(m.last, "hfov_deg"), "%d errors, last '%s'", m.errors, m.last);
    CHECK(vgx_get_output(c, (vgx_output)7, &out) == VGX_ERROR_INVALID_ARGUMENT, "output 7");
    CHECK(gpu_oneshot_submit(g, cmd) == VG_OK, "empty submit");
    vgx_context_destroy(c);
    vgx_context_destroy(NULL);
    gpu_destroy(g);
    return gpu_validation_messages() != 0;
}

/* g is the rig's vergence at each depth (stereo_camera_vergence), h lies in
 * the target range and keeps the order of depths; the input found in
 * SHADER_READ_ONLY_OPTIMAL, then (a new graph) in GENERAL, and the dispatch
 * recorded one pass per submission give the same bits. */
static int maps(void)
{
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    enum { W = 64, H = 48 };
    messages m = {0};
    vgx_context_desc d = context_desc(g, W, H, &m);
    vgx_context *c = NULL;
    CHECK(vgx_context_create(&d, &c) == VGX_SUCCESS, "create: %s", m.last);

    const double *z = k_bands;
    gpu_image img;
    CHECK(depth_image(g, W, H, NULL, &img) == 0, "depth");

    stereo_display disp;
    stereo_camera cam;
    test_rig(W, &disp, &cam);
    vgx_context_info info;
    vgx_get_info(c, &info);
    double lo = info.range_lo_arcmin, hi = info.range_hi_arcmin;
    /* Run 2: the GENERAL input again, one pass per submission (a profiler's view). */
    static float gmap[3][W * H], hmap[3][W * H];
    VkImageLayout layouts[3] = {VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL,
                                VK_IMAGE_LAYOUT_GENERAL};
    uint32_t passes = vgx_pass_count(c);
    CHECK(passes >= 4 && strcmp(vgx_pass_name(c, 0), "vgx.constants") == 0 && vgx_pass_name(c, passes) == NULL,
          "%u passes, the first %s", passes, vgx_pass_name(c, 0));
    for (int run = 0; run < 3; run++) {
        VkCommandBuffer cmd;
        CHECK(gpu_oneshot_begin(g, &cmd) == VG_OK, "begin");
        if (run == 1) /* the host moves its image to GENERAL itself */
            host_layout(cmd, img.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                        VK_IMAGE_LAYOUT_GENERAL);
        vgx_dispatch_desc dd = depth_dispatch(cmd, &img, layouts[run]);
        for (uint32_t p = 0; p < (run == 2 ? passes : 1); p++) {
            if (run == 2) {
                dd.first_pass = p, dd.pass_count = 1;
                if (p > 0) {
                    CHECK(gpu_oneshot_begin(g, &cmd) == VG_OK, "begin");
                    dd.command_buffer = cmd;
                }
            }
            CHECK(vgx_dispatch(c, &dd) == VGX_SUCCESS, "dispatch %d: %s", run, m.last);
            CHECK(gpu_oneshot_submit(g, cmd) == VG_OK, "submit");
            if (run == 2 && p == 0) { /* out of order: refused, and nothing recorded */
                vgx_dispatch_desc late = dd;
                late.first_pass = 2;
                CHECK(vgx_dispatch(c, &late) == VGX_ERROR_INVALID_ARGUMENT && strstr(m.last, "next one due is 1"),
                      "pass 2 before 1: '%s'", m.last);
                m.errors = 0;
            }
        }
        vgx_image og, oh;
        CHECK(vgx_get_output(c, VGX_OUTPUT_G, &og) == VGX_SUCCESS && vgx_get_output(c, VGX_OUTPUT_H, &oh) == VGX_SUCCESS,
              "outputs");
        CHECK(og.layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, "layout %d", (int)og.layout);
        CHECK(read_map(g, &og, W, H, gmap[run]) == 0 && read_map(g, &oh, W, H, hmap[run]) == 0, "read");
    }
    double prev_h = 1e9;
    for (int band = 0; band < 4; band++) {
        int i = (H / 2) * W + band * (W / 4) + 3;
        double want = stereo_camera_vergence(&cam, &disp, z[band]);
        /* GLSL's atan is allowed 4096 ULP (Vulkan spec, "Precision and
         * Operation of SPIR-V Instructions"); llvmpipe is 0.008 arcmin off. */
        EXPECT_NEAR(gmap[0][i], want, 0.05, "g at %g m", z[band]);
        EXPECT(hmap[0][i] >= lo - 1e-3 && hmap[0][i] <= hi + 1e-3, "h %g at %g m outside [%g, %g]", hmap[0][i],
               z[band], lo, hi);
        EXPECT(hmap[0][i] < prev_h, "h %g at %g m not below the nearer band's %g", hmap[0][i], z[band], prev_h);
        prev_h = hmap[0][i];
    }
    EXPECT(gmap[0][0] - gmap[0][W - 1] > 20, "g spans %g arcmin", gmap[0][0] - gmap[0][W - 1]);
    EXPECT(memcmp(gmap[0], gmap[1], sizeof gmap[0]) == 0 && memcmp(hmap[0], hmap[1], sizeof hmap[0]) == 0,
           "the two input layouts gave different maps");
    EXPECT(memcmp(gmap[1], gmap[2], sizeof gmap[0]) == 0 && memcmp(hmap[1], hmap[2], sizeof hmap[0]) == 0,
           "recorded pass by pass, the maps differ");
    EXPECT(m.errors == 0, "%d errors: %s", m.errors, m.last);
    vgx_context_destroy(c);
    gpu_image_destroy(g, &img);
    gpu_destroy(g);
    return gpu_validation_messages() != 0;
}

/* A host that gives its z-buffer (VGX_DEPTH_DEVICE) gets the g of the
 * linear depth it stands for, with a standard and with a reversed depth
 * range. */
static int device_depth(void)
{
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    enum { W = 64, H = 48 };
    messages m = {0};
    vgx_context_desc d = context_desc(g, W, H, &m);
    vgx_context *c = NULL;
    CHECK(vgx_context_create(&d, &c) == VGX_SUCCESS, "create: %s", m.last);
    stereo_display disp;
    stereo_camera cam;
    test_rig(W, &disp, &cam);
    const double z[4] = {2.0, 4.5, 9.0, 40.0}, n = 0.1, far = 150.0;
    for (int reversed = 0; reversed < 2; reversed++) {
        /* Vulkan clip: x right, y down, the view looking down -z; depth 0..1 (or 1..0). */
        float proj[16] = {0};
        proj[0] = 1.0f, proj[5] = -1.0f, proj[11] = -1.0f;
        proj[10] = reversed ? (float)(n / (far - n)) : (float)(far / (n - far));
        proj[14] = reversed ? (float)(n * far / (far - n)) : (float)(n * far / (n - far));
        static float zbuf[W * H];
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                double zv = -z[x * 4 / W];
                zbuf[y * W + x] = (float)((proj[10] * zv + proj[14]) / -zv);
            }
        gpu_image img;
        CHECK(gpu_image_create(g, &(gpu_image_desc){.name = "test z-buffer", .format = VK_FORMAT_D32_SFLOAT, .width = W,
                                                    .height = H, .usage = VK_IMAGE_USAGE_SAMPLED_BIT |
                                                                          VK_IMAGE_USAGE_TRANSFER_DST_BIT},
                               &img) == VG_OK, "z-buffer");
        CHECK(gpu_image_upload(g, &img, zbuf, sizeof zbuf) == VG_OK, "upload");
        VkCommandBuffer cmd;
        CHECK(gpu_oneshot_begin(g, &cmd) == VG_OK, "begin");
        host_layout(cmd, img.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                    VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
        vgx_dispatch_desc dd = depth_dispatch(cmd, &img, VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL);
        dd.depth_kind = VGX_DEPTH_DEVICE;
        memcpy(dd.projection, proj, sizeof proj);
        CHECK(vgx_dispatch(c, &dd) == VGX_SUCCESS, "dispatch: %s", m.last);
        CHECK(gpu_oneshot_submit(g, cmd) == VG_OK, "submit");
        vgx_image og;
        CHECK(vgx_get_output(c, VGX_OUTPUT_G, &og) == VGX_SUCCESS, "output");
        static float gmap[W * H];
        CHECK(read_map(g, &og, W, H, gmap) == 0, "read");
        for (int band = 0; band < 4; band++) {
            int i = (H / 2) * W + band * (W / 4) + 3;
            /* float depth loses precision far away: 40 m is 1e-4 from 1 in the standard range */
            EXPECT_NEAR(gmap[i], stereo_camera_vergence(&cam, &disp, z[band]), band == 3 ? 0.5 : 0.05,
                        "g at %g m from a %s z-buffer", z[band], reversed ? "reversed" : "standard");
        }
        gpu_image_destroy(g, &img);
    }
    EXPECT(m.errors == 0, "%d errors: %s", m.errors, m.last);
    vgx_context_destroy(c);
    gpu_destroy(g);
    return gpu_validation_messages() != 0;
}

/* The host's allocator gets every allocation of the context's objects back. */
typedef struct counting {
    long live, total;
} counting;

static void *VKAPI_PTR count_alloc(void *user, size_t size, size_t align, VkSystemAllocationScope scope)
{
    (void)scope;
    void *p = NULL;
    if (posix_memalign(&p, align < sizeof(void *) ? sizeof(void *) : align, size ? size : 1) != 0)
        return NULL;
    ((counting *)user)->live++;
    ((counting *)user)->total++;
    return p;
}

static void *VKAPI_PTR count_realloc(void *user, void *old, size_t size, size_t align, VkSystemAllocationScope scope)
{
    (void)scope;
    if (!old)
        return count_alloc(user, size, align, scope);
    if (size == 0) {
        free(old);
        ((counting *)user)->live--;
        return NULL;
    }
    void *p = count_alloc(user, size, align, scope);
    if (p) {
        memcpy(p, old, size); /* the test's objects are small; a real host keeps the old size */
        free(old);
        ((counting *)user)->live--;
    }
    return p;
}

static void VKAPI_PTR count_free(void *user, void *p)
{
    if (!p)
        return;
    free(p);
    ((counting *)user)->live--;
}

static int allocator(void)
{
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    counting n = {0, 0};
    VkAllocationCallbacks cb = {.pUserData = &n, .pfnAllocation = count_alloc, .pfnReallocation = count_realloc,
                                .pfnFree = count_free};
    messages m = {0};
    vgx_context_desc d = context_desc(g, 32, 32, &m);
    d.allocator = &cb;
    vgx_context *c = NULL;
    CHECK(vgx_context_create(&d, &c) == VGX_SUCCESS, "create: %s", m.last);
    long during = n.live;
    vgx_context_destroy(c);
    gpu_destroy(g);
    CHECK(n.total > 0 && during > 0, "the driver never used the host's allocator (%ld allocations)", n.total);
    CHECK(n.live == 0, "%ld of %ld allocations not freed", n.live, n.total);
    return gpu_validation_messages() != 0;
}

/* Two contexts on two threads: each one's messages reach its own callback. */
typedef struct worker {
    gpu *g;
    messages m;
    int bad_calls;
} worker;

static void *work(void *arg)
{
    worker *w = arg;
    vgx_context_desc d = context_desc(w->g, 32, 32, &w->m);
    vgx_context *c = NULL;
    if (vgx_context_create(&d, &c) != VGX_SUCCESS)
        return NULL;
    vgx_dispatch_desc dd;
    memset(&dd, 0, sizeof dd);
    for (int i = 0; i < w->bad_calls; i++)
        vgx_dispatch(c, &dd); /* no command buffer: one error each */
    vgx_context_destroy(c);
    return NULL;
}

static int threads(void)
{
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    worker w[2] = {{g, {0, 0, ""}, 3}, {g, {0, 0, ""}, 5}};
    pthread_t t[2];
    for (int i = 0; i < 2; i++)
        CHECK(pthread_create(&t[i], NULL, work, &w[i]) == 0, "thread");
    for (int i = 0; i < 2; i++)
        pthread_join(t[i], NULL);
    gpu_destroy(g);
    CHECK(w[0].m.errors == 3 && w[1].m.errors == 5, "errors %d and %d (want 3 and 5)", w[0].m.errors, w[1].m.errors);
    return gpu_validation_messages() != 0;
}

#if VGX_HEADER_VERSION_MINOR >= 2 /* 0.2 */
/* Frames in flight (issue 42). A warp context declares three. The host
 * submits each frame without waiting, waiting only for the frame three
 * before it (its fence) before it records the next; after each dispatch it
 * reads the warp's target map (copied, as a screenshot would). Midway it
 * moves its depth image to another layout and changes the warp map twice:
 * each change is a new configuration whose graph replaces one that frames
 * in flight still use. Under synchronization validation a missing
 * dependency between the frames would be a message. Then a fourth frame in
 * flight, the GPU held back by an event the host sets later, is refused
 * with one message line. */
enum { FLIGHT = 3, FLIGHT_FRAMES = 12 };

/* The host's read of a frame's warp map into `to`. */
static void host_reads(VkCommandBuffer cmd, const vgx_warp *w, VkBuffer to, uint32_t width, uint32_t height)
{
    VkImageMemoryBarrier2 b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
        .srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
        .dstStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
        .dstAccessMask = VK_ACCESS_2_TRANSFER_READ_BIT,
        .oldLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
        .newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = w->target.image,
        .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1},
    };
    VkDependencyInfo dep = {.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .imageMemoryBarrierCount = 1,
                            .pImageMemoryBarriers = &b};
    vkCmdPipelineBarrier2(cmd, &dep);
    VkBufferImageCopy region = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                                .imageExtent = {width, height, 1}};
    vkCmdCopyImageToBuffer(cmd, w->target.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, to, 1, &region);
    b.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
    b.dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    b.dstAccessMask = VK_ACCESS_2_SHADER_READ_BIT;
    b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    vkCmdPipelineBarrier2(cmd, &dep);
    VkMemoryBarrier2 host = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2, .srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT,
                             .srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT,
                             .dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT, .dstAccessMask = VK_ACCESS_2_HOST_READ_BIT};
    vkCmdPipelineBarrier2(cmd, &(VkDependencyInfo){.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                                   .memoryBarrierCount = 1, .pMemoryBarriers = &host});
}

static VkResult submit(gpu *g, VkCommandBuffer cmd, VkFence fence)
{
    VkCommandBufferSubmitInfo c = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO, .commandBuffer = cmd};
    VkSubmitInfo2 si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO_2, .commandBufferInfoCount = 1,
                        .pCommandBufferInfos = &c};
    return vkQueueSubmit2(g->queue, 1, &si, fence);
}

static int in_flight(void)
{
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    enum { W = 64, H = 48 };
    messages m = {0};
    vgx_context_desc d = context_desc(g, W, H, &m);
    d.flags |= VGX_CONTEXT_WARP;
    d.frames_in_flight = FLIGHT;
    vgx_context *c = NULL;
    CHECK(vgx_context_create(&d, &c) == VGX_SUCCESS, "create: %s", m.last);
    vgx_warp warp;
    CHECK(vgx_get_warp(c, &warp) == VGX_SUCCESS, "warp");

    const double *z = k_bands;
    gpu_image img;
    CHECK(depth_image(g, W, H, NULL, &img) == 0, "depth");

    /* One command buffer and fence per frame in flight, and a fourth for
     * the frame that would be one too many; a readback per frame. */
    VkCommandPool pool;
    VkCommandPoolCreateInfo pi = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                  .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                  .queueFamilyIndex = g->queue_family};
    CHECK(vkCreateCommandPool(g->device, &pi, NULL, &pool) == VK_SUCCESS, "pool");
    VkCommandBuffer cmds[FLIGHT + 1];
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO, .commandPool = pool,
                                      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY, .commandBufferCount = FLIGHT + 1};
    CHECK(vkAllocateCommandBuffers(g->device, &ai, cmds) == VK_SUCCESS, "command buffers");
    VkFence fences[FLIGHT + 1];
    for (int i = 0; i <= FLIGHT; i++)
        CHECK(vkCreateFence(g->device, &(VkFenceCreateInfo){.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO,
                                                            .flags = VK_FENCE_CREATE_SIGNALED_BIT},
                            NULL, &fences[i]) == VK_SUCCESS, "fence");
    size_t bytes = (size_t)W * H * 4;
    static gpu_buffer readback[FLIGHT_FRAMES + 1];
    for (int i = 0; i <= FLIGHT_FRAMES; i++)
        CHECK(gpu_buffer_create(g, &(gpu_buffer_desc){.name = "test readback", .size = bytes,
                                                      .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                                      .host_visible = true}, &readback[i]) == VG_OK, "readback");
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    /* Frames 0-3 warp g with the depth in SHADER_READ_ONLY_OPTIMAL, 4-5 h,
     * 6-7 h with the depth in GENERAL, 8-11 g again. */
    for (int k = 0; k < FLIGHT_FRAMES; k++) {
        int slot = k % FLIGHT;
        CHECK(vkWaitForFences(g->device, 1, &fences[slot], VK_TRUE, UINT64_MAX) == VK_SUCCESS, "wait");
        CHECK(vkResetFences(g->device, 1, &fences[slot]) == VK_SUCCESS, "reset");
        VkCommandBuffer cmd = cmds[slot];
        CHECK(vkBeginCommandBuffer(cmd, &bi) == VK_SUCCESS, "begin");
        VkImageLayout layout = k < 6 ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_GENERAL;
        if (k == 6)
            host_layout(cmd, img.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                        VK_IMAGE_LAYOUT_GENERAL);
        vgx_dispatch_desc dd = depth_dispatch(cmd, &img, layout);
        for (int i = 0; i < 16; i++)
            dd.view_proj[i] = i % 5 == 0 ? 1.0f : 0.0f;
        dd.background_depth_m = 40.0f;
        dd.warp_map = k >= 4 && k < 8 ? VGX_WARP_MAP_H : VGX_WARP_MAP_G;
        CHECK(vgx_dispatch(c, &dd) == VGX_SUCCESS, "frame %d: %s", k, m.last);
        CHECK(vgx_get_warp(c, &warp) == VGX_SUCCESS, "warp");
        host_reads(cmd, &warp, readback[k].buffer, W, H);
        CHECK(vkEndCommandBuffer(cmd) == VK_SUCCESS, "end");
        CHECK(submit(g, cmd, fences[slot]) == VK_SUCCESS, "submit %d", k);
    }
    CHECK(vkWaitForFences(g->device, FLIGHT, fences, VK_TRUE, UINT64_MAX) == VK_SUCCESS, "wait all");
    CHECK(m.errors == 0, "%d errors: %s", m.errors, m.last);

    stereo_display disp;
    stereo_camera cam;
    test_rig(W, &disp, &cam);
    const float *last = readback[FLIGHT_FRAMES - 1].mapped, *h5 = readback[5].mapped, *h7 = readback[7].mapped;
    for (int band = 0; band < 4; band++) {
        int i = (H / 2) * W + band * (W / 4) + 3;
        EXPECT_NEAR(last[i], stereo_camera_vergence(&cam, &disp, z[band]), 0.05, "g at %g m, frame %d", z[band],
                    FLIGHT_FRAMES - 1);
    }
    EXPECT(memcmp(h5, h7, (size_t)W * H * 4) == 0, "h differs with the depth in GENERAL (frame 7) and in "
                                                     "SHADER_READ_ONLY_OPTIMAL (frame 5)");
    EXPECT(memcmp(readback[3].mapped, last, bytes) == 0, "frame 3 and frame 11 (both g) differ");
    EXPECT(memcmp(h5, last, (size_t)W * H * 4) != 0, "the warp read g where it asked for h");
    printf("%d frames, %d in flight, 3 configurations: g at the bands %.2f %.2f %.2f %.2f arcmin\n", FLIGHT_FRAMES,
           FLIGHT, last[(H / 2) * W + 3], last[(H / 2) * W + W / 4 + 3], last[(H / 2) * W + W / 2 + 3],
           last[(H / 2) * W + 3 * W / 4 + 3]);

    /* Three frames held back by the gate (the first waits for an event the
     * host sets), then a fourth: refused. */
    VkEvent gate;
    CHECK(vkCreateEvent(g->device, &(VkEventCreateInfo){.sType = VK_STRUCTURE_TYPE_EVENT_CREATE_INFO}, NULL,
                        &gate) == VK_SUCCESS, "gate");
    CHECK(vkResetFences(g->device, FLIGHT + 1, fences) == VK_SUCCESS, "reset");
    for (int k = 0; k <= FLIGHT; k++) {
        VkCommandBuffer cmd = cmds[k];
        CHECK(vkBeginCommandBuffer(cmd, &bi) == VK_SUCCESS, "begin");
        if (k == 0) /* set by the host: only host operations in the first scope */
            vkCmdWaitEvents2(cmd, 1, &gate, &(VkDependencyInfo){
                .sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO, .memoryBarrierCount = 1,
                .pMemoryBarriers = &(VkMemoryBarrier2){.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER_2,
                                                       .srcStageMask = VK_PIPELINE_STAGE_2_HOST_BIT,
                                                       .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT}});
        vgx_dispatch_desc dd = depth_dispatch(cmd, &img, VK_IMAGE_LAYOUT_GENERAL);
        for (int i = 0; i < 16; i++)
            dd.view_proj[i] = i % 5 == 0 ? 1.0f : 0.0f;
        dd.background_depth_m = 40.0f;
        if (k == FLIGHT) {
            int before = m.errors;
            CHECK(vgx_dispatch(c, &dd) == VGX_ERROR_INVALID_ARGUMENT, "a fourth frame in flight was recorded");
            CHECK(m.errors == before + 1 && strstr(m.last, "frames_in_flight is 3"), "%d lines, last '%s'",
                  m.errors - before, m.last);
            printf("a fourth frame in flight: %s\n", m.last);
            m.errors = before;
            CHECK(vkSetEvent(g->device, gate) == VK_SUCCESS, "set the gate");
            CHECK(vkWaitForFences(g->device, 1, &fences[0], VK_TRUE, UINT64_MAX) == VK_SUCCESS, "wait frame 1");
        }
        CHECK(vgx_dispatch(c, &dd) == VGX_SUCCESS, "held frame %d: %s", k, m.last);
        CHECK(vkEndCommandBuffer(cmd) == VK_SUCCESS, "end");
        CHECK(submit(g, cmd, fences[k]) == VK_SUCCESS, "submit");
    }
    CHECK(vkWaitForFences(g->device, FLIGHT + 1, fences, VK_TRUE, UINT64_MAX) == VK_SUCCESS, "wait all");
    CHECK(m.errors == 0, "%d errors: %s", m.errors, m.last);
    vgx_context_destroy(c);
    vkDestroyEvent(g->device, gate, NULL);
    for (int i = 0; i <= FLIGHT; i++)
        vkDestroyFence(g->device, fences[i], NULL);
    vkDestroyCommandPool(g->device, pool, NULL);
    for (int i = 0; i <= FLIGHT_FRAMES; i++)
        gpu_buffer_destroy(g, &readback[i]);
    gpu_image_destroy(g, &img);
    gpu_destroy(g);
    return gpu_validation_messages() != 0;
}
#endif

#if VGX_HEADER_VERSION_MINOR >= 2 /* 0.2 */
/* The host's own allocator (issue 42): one 64 MiB block per memory type,
 * handed out in aligned ranges, and counted. */
typedef struct host_pool {
    gpu *g;
    VkDeviceMemory block[VK_MAX_MEMORY_TYPES];
    void *mapped[VK_MAX_MEMORY_TYPES];
    VkDeviceSize used[VK_MAX_MEMORY_TYPES];
    int live, calls, fail_at;   /* fail_at: that call (1-based) fails */
    VkDeviceSize bytes;
} host_pool;
#define HOST_POOL_BYTES ((VkDeviceSize)64 << 20)

static VkResult pool_allocate(void *user, const vgx_memory_request *r, vgx_memory_block *b)
{
    host_pool *p = user;
    if (++p->calls == p->fail_at)
        return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    const VkPhysicalDeviceMemoryProperties *mem = &p->g->mem;
    int t = -1;
    for (int pass = 0; pass < 2 && t < 0; pass++)
        for (uint32_t i = 0; i < mem->memoryTypeCount && t < 0; i++)
            if ((r->requirements.memoryTypeBits & (1u << i)) &&
                (mem->memoryTypes[i].propertyFlags & r->properties) == (pass ? 0 : r->properties))
                t = (int)i;
    bool host = r->properties & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    if (t < 0 || (host && !(mem->memoryTypes[t].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)))
        return VK_ERROR_FEATURE_NOT_PRESENT;
    if (!p->block[t]) {
        VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, .allocationSize = HOST_POOL_BYTES,
                                   .memoryTypeIndex = (uint32_t)t};
        if (vkAllocateMemory(p->g->device, &ai, NULL, &p->block[t]) != VK_SUCCESS)
            return VK_ERROR_OUT_OF_DEVICE_MEMORY;
        if ((mem->memoryTypes[t].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) &&
            vkMapMemory(p->g->device, p->block[t], 0, VK_WHOLE_SIZE, 0, &p->mapped[t]) != VK_SUCCESS)
            return VK_ERROR_MEMORY_MAP_FAILED;
    }
    VkDeviceSize align = r->requirements.alignment, gran = p->g->props.limits.bufferImageGranularity;
    align = align > gran ? align : gran;
    VkDeviceSize at = (p->used[t] + align - 1) / align * align;
    if (at + r->requirements.size > HOST_POOL_BYTES)
        return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    p->used[t] = at + r->requirements.size;
    *b = (vgx_memory_block){p->block[t], at, host ? (uint8_t *)p->mapped[t] + at : NULL,
                            (void *)(uintptr_t)r->requirements.size};
    p->live++;
    p->bytes += r->requirements.size;
    return VK_SUCCESS;
}

static void pool_free(void *user, const vgx_memory_block *b)
{
    host_pool *p = user;
    p->live--;
    p->bytes -= (VkDeviceSize)(uintptr_t)b->user;
}

static void pool_destroy(host_pool *p)
{
    for (uint32_t i = 0; i < VK_MAX_MEMORY_TYPES; i++)
        if (p->block[i])
            vkFreeMemory(p->g->device, p->block[i], NULL);
}

/* h of the depth bands of `maps`, one dispatch. */
static int bands_h(gpu *g, vgx_context *c, const gpu_image *img, uint32_t w, uint32_t h, float *out)
{
    VkCommandBuffer cmd;
    CHECK(gpu_oneshot_begin(g, &cmd) == VG_OK, "begin");
    vgx_dispatch_desc dd = depth_dispatch(cmd, img, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    CHECK(vgx_dispatch(c, &dd) == VGX_SUCCESS, "dispatch");
    CHECK(gpu_oneshot_submit(g, cmd) == VG_OK, "submit");
    vgx_image oh;
    CHECK(vgx_get_output(c, VGX_OUTPUT_H, &oh) == VGX_SUCCESS, "output");
    return read_map(g, &oh, w, h, out);
}

/* Memory (issue 42): the footprint before creation, the host's allocator
 * giving every block (the same maps as the driver's allocations; every
 * block back after destroy; the footprint is what the hooks gave), a hook
 * that fails midway (one line, nothing kept), and the footprint of a warp
 * context with VERGENCE_DISABLE=tessellation (the context itself needs no
 * tessellation: only the host's shaders do). */
static int memory(void)
{
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    enum { W = 64, H = 48 };
    messages m = {0};
    vgx_context_desc d = context_desc(g, W, H, &m);
    vgx_memory_footprint fp, fp_hooked, fp_warp, fp_notess;
    CHECK(vgx_get_memory_footprint(&d, &fp) == VGX_SUCCESS, "footprint: %s", m.last);
    CHECK(fp.blocks > 4 && fp.bytes > 0 && fp.host_visible_bytes >= 4 && fp.configuration_bytes < fp.bytes,
          "footprint %llu bytes, %llu host-visible, %u blocks, %llu per configuration", (unsigned long long)fp.bytes,
          (unsigned long long)fp.host_visible_bytes, fp.blocks, (unsigned long long)fp.configuration_bytes);
    CHECK(vgx_get_memory_footprint(NULL, &fp_hooked) == VGX_ERROR_INVALID_ARGUMENT &&
              vgx_get_memory_footprint(&d, NULL) == VGX_ERROR_INVALID_ARGUMENT, "null arguments");
    m.errors = 0;

    gpu_image img;
    CHECK(depth_image(g, W, H, NULL, &img) == 0, "depth");
    static float h_driver[W * H], h_host[W * H];
    vgx_context *c = NULL;
    CHECK(vgx_context_create(&d, &c) == VGX_SUCCESS, "create: %s", m.last);
    CHECK(bands_h(g, c, &img, W, H, h_driver) == 0, "h, driver's memory");
    vgx_context_destroy(c);

    host_pool pool = {.g = g};
    d.memory = (vgx_memory_hooks){pool_allocate, pool_free, &pool};
    CHECK(vgx_context_create(&d, &c) == VGX_SUCCESS, "create with hooks: %s", m.last);
    CHECK(pool.live == (int)fp.blocks && pool.bytes == fp.bytes, "the hooks gave %d blocks, %llu bytes; the "
          "footprint said %u, %llu", pool.live, (unsigned long long)pool.bytes, fp.blocks,
          (unsigned long long)fp.bytes);
    CHECK(bands_h(g, c, &img, W, H, h_host) == 0, "h, the host's memory");
    /* A configuration allocates at creation and on its first frame, then
     * never within a dispatch (docs/sdk.md "Memory"). */
    int calls = pool.calls;
    for (int k = 0; k < 3; k++)
        CHECK(bands_h(g, c, &img, W, H, h_host) == 0, "h, frame %d", k + 2);
    CHECK(pool.calls == calls, "three more dispatches of the same configuration allocated %d blocks",
          pool.calls - calls);
    vgx_context_destroy(c);
    CHECK(pool.live == 0 && pool.bytes == 0, "%d blocks (%llu bytes) not given back", pool.live,
          (unsigned long long)pool.bytes);
    EXPECT(memcmp(h_driver, h_host, sizeof h_driver) == 0, "h differs in the host's memory");
    CHECK(vgx_get_memory_footprint(&d, &fp_hooked) == VGX_SUCCESS && fp_hooked.bytes == fp.bytes &&
              fp_hooked.blocks == fp.blocks && pool.live == 0, "footprint with hooks");

    pool.calls = 0;
    pool.fail_at = 3;
    CHECK(vgx_context_create(&d, &c) == VGX_ERROR_VULKAN && c == NULL, "a failing hook");
    CHECK(m.errors == 1 && strstr(m.last, "memory hook"), "%d errors, last '%s'", m.errors, m.last);
    CHECK(pool.live == 0, "%d blocks kept after the failed create", pool.live);
    m.errors = 0;
    d.memory.free = NULL;
    CHECK(vgx_context_create(&d, &c) == VGX_ERROR_INVALID_ARGUMENT && strstr(m.last, "memory"), "one hook");
    m.errors = 0;
    d.memory = (vgx_memory_hooks){0};

    d.flags |= VGX_CONTEXT_WARP;
    CHECK(vgx_get_memory_footprint(&d, &fp_warp) == VGX_SUCCESS && fp_warp.bytes > fp.bytes, "warp footprint");
    /* The eyes' graph has scratch of its own (the eyes' depth and work
     * lists): a configuration change makes that much again. */
    vgx_memory_footprint fp_eyes;
    d.flags |= VGX_CONTEXT_EYES;
    CHECK(vgx_get_memory_footprint(&d, &fp_eyes) == VGX_SUCCESS && fp_eyes.configuration_bytes > 0 &&
              fp_eyes.configuration_bytes < fp_eyes.bytes,
          "the eyes' footprint: %llu bytes, %llu per configuration", (unsigned long long)fp_eyes.bytes,
          (unsigned long long)fp_eyes.configuration_bytes);
    d.flags &= ~(uint32_t)VGX_CONTEXT_EYES;
    setenv("VERGENCE_DISABLE", "tessellation", 1);
    CHECK(vgx_get_memory_footprint(&d, &fp_notess) == VGX_SUCCESS && fp_notess.bytes == fp_warp.bytes,
          "warp footprint without tessellation: %s", m.last);
    unsetenv("VERGENCE_DISABLE");
    printf("footprint at %ux%u: %llu bytes in %u blocks (%llu host-visible, %llu per configuration); with the "
           "warp %llu, also without tessellation; with the eyes %llu (%llu per configuration); the host's allocator "
           "gave the same and got all back\n", W, H,
           (unsigned long long)fp.bytes, fp.blocks, (unsigned long long)fp.host_visible_bytes,
           (unsigned long long)fp.configuration_bytes, (unsigned long long)fp_warp.bytes,
           (unsigned long long)fp_eyes.bytes, (unsigned long long)fp_eyes.configuration_bytes);
    pool_destroy(&pool);
    gpu_image_destroy(g, &img);
    gpu_destroy(g);
    return gpu_validation_messages() != 0;
}
#endif

#if VGX_HEADER_VERSION_MINOR >= 2 /* 0.2 */
/* The stereo pair without tessellation (VGX_CONTEXT_EYES, issue 42): a near
 * box (2 m) over a far wall (40 m), each centre pixel's colour saying where
 * it came from (red: its column; green: the box). Every surface pixel of
 * each eye is where the map g puts its source (within half a pixel: the
 * warp error), each disocclusion is filled from the wall, nothing is left
 * empty. */
static int eyes(void)
{
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    enum { W = 128, H = 16, BOX0 = 48, BOX1 = 80 };
    messages m = {0};
    vgx_context_desc d = context_desc(g, W, H, &m);
    d.flags |= VGX_CONTEXT_EYES;
    vgx_context *c = NULL;
    CHECK(vgx_context_create(&d, &c) == VGX_SUCCESS, "create: %s", m.last);
    static float depth[W * H];
    static uint8_t color[W * H * 4];
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            bool box = x >= BOX0 && x < BOX1;
            depth[y * W + x] = box ? 2.0f : 40.0f;
            uint8_t *px = &color[4 * (y * W + x)];
            px[0] = (uint8_t)x, px[1] = box ? 255 : 0, px[2] = 128, px[3] = 255;
        }
    gpu_image dimg, cimg;
    CHECK(depth_image(g, W, H, depth, &dimg) == 0, "depth");
    CHECK(gpu_image_create(g, &(gpu_image_desc){.name = "test colour", .format = VK_FORMAT_R8G8B8A8_UNORM, .width = W,
                                                .height = H, .usage = VK_IMAGE_USAGE_SAMPLED_BIT |
                                                                      VK_IMAGE_USAGE_TRANSFER_DST_BIT},
                           &cimg) == VG_OK, "colour image");
    CHECK(gpu_image_upload(g, &cimg, color, sizeof color) == VG_OK, "upload");
    VkCommandBuffer cmd;
    CHECK(gpu_oneshot_begin(g, &cmd) == VG_OK, "begin");
    vgx_dispatch_desc dd = depth_dispatch(cmd, &dimg, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    dd.warp_map = VGX_WARP_MAP_G;
    CHECK(vgx_dispatch(c, &dd) == VGX_ERROR_INVALID_ARGUMENT && strstr(m.last, "color"), "no colour: '%s'", m.last);
    m.errors = 0;
    dd.color = (vgx_image){cimg.image, cimg.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    CHECK(vgx_dispatch(c, &dd) == VGX_SUCCESS, "dispatch: %s", m.last);
    CHECK(gpu_oneshot_submit(g, cmd) == VG_OK, "submit");
    vgx_image eye;
    CHECK(vgx_get_eye(c, 2, &eye) == VGX_ERROR_INVALID_ARGUMENT, "eye 2");

    stereo_display disp;
    stereo_camera cam;
    test_rig(W, &disp, &cam);
    static float pixels[W * H]; /* RGBA8 read back as 4-byte texels */
    int surface = 0, filled = 0, empty = 0, wrong_fill = 0;
    double worst = 0, sum = 0;
    for (int e = 0; e < 2; e++) {
        CHECK(vgx_get_eye(c, (uint32_t)e, &eye) == VGX_SUCCESS && eye.layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
              "eye %d", e);
        CHECK(read_map(g, &eye, W, H, pixels) == 0, "read eye %d", e);
        const uint8_t *px = (const uint8_t *)pixels;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++) {
                const uint8_t *q = &px[4 * (y * W + x)];
                if (q[3] == 255) {
                    double z = q[1] ? 2.0 : 40.0;
                    double want = q[0] + (e ? 0.5 : -0.5) * stereo_camera_parallax_px(&cam, z);
                    double err = fabs(x - want);
                    worst = err > worst ? err : worst;
                    sum += err;
                    surface++;
                } else if (q[3] == 128) {
                    filled++;
                    wrong_fill += q[1] != 0; /* a disocclusion shows the wall */
                } else {
                    empty++;
                }
            }
    }
    double box = stereo_camera_parallax_px(&cam, 2.0), wall = stereo_camera_parallax_px(&cam, 40.0);
    /* Uncovered per row and eye: beside the box, what it moves against the
     * wall; at the frame's edge, what the wall moves. */
    double uncovered = 0.5 * fabs(box - wall) + 0.5 * fabs(wall);
    printf("eyes: %d surface pixels, warp error mean %.3f px, max %.3f px; %d uncovered pixels filled (%.1f per row "
           "and eye; the box moves %.2f px against the wall, the wall %.2f px at the edge), %d left empty\n", surface,
           sum / surface, worst, filled, filled / (2.0 * H), 0.5 * fabs(box - wall), 0.5 * fabs(wall), empty);
    EXPECT(worst <= 0.5 + 1e-3, "a surface pixel is %.3f px from where g puts it", worst);
    EXPECT(filled > 0 && wrong_fill == 0, "%d filled pixels, %d of them not the wall", filled, wrong_fill);
    EXPECT(empty == 0, "%d eye pixels left empty", empty);
    EXPECT(fabs(filled / (2.0 * H) - uncovered) <= 1.5, "%.1f filled per row and eye, %.2f uncovered",
           filled / (2.0 * H), uncovered);
    EXPECT(m.errors == 0, "%d errors: %s", m.errors, m.last);
    vgx_context_destroy(c);
    gpu_image_destroy(g, &dimg);
    gpu_image_destroy(g, &cimg);
    gpu_destroy(g);
    return gpu_validation_messages() != 0;
}
#endif

#if VGX_HEADER_VERSION_MINOR >= 2 /* 0.2 */
/* Every Vulkan object the SDK makes carries a name (issue 42), checked at
 * run time by the validation layer itself: a context with every flag is
 * left undestroyed, so destroying the device makes the layer report each of
 * its objects (VUID-vkDestroyDevice-device-00378, its name with it when it
 * has one; VK_LAYER_DUPLICATE_MESSAGE_LIMIT lifts the layer's 10 reports a
 * kind). */
typedef struct leak_log {
    int objects, named;
    char unnamed[400];
} leak_log;

static void on_leak(vg_log_level level, const char *line, void *user)
{
    (void)level;
    leak_log *l = user;
    if (!strstr(line, "has not been destroyed")) {
        fprintf(stderr, "%s\n", line);
        return;
    }
    l->objects++;
    const char *o1 = strstr(line, "Object 1:"), *type = o1 ? strstr(o1, "type =") : NULL;
    const char *name = o1 ? strstr(o1, "name = ") : NULL;
    if (name && type && name < type && name[7] != ',')
        l->named++;
    else if (!l->unnamed[0])
        snprintf(l->unnamed, sizeof l->unnamed, "%.300s", o1 ? o1 : line);
}

static int names(void)
{
    setenv("VK_LAYER_DUPLICATE_MESSAGE_LIMIT", "100000", 1);
    gpu *g = make_gpu();
    CHECK(g, "gpu");
    CHECK(g->validation && g->debug_utils, "needs the validation layer (VERGENCE_VALIDATE=1) and debug utils");
    messages m = {0};
    vgx_context_desc d = context_desc(g, 64, 48, &m);
    d.flags |= VGX_CONTEXT_SALIENCY | VGX_CONTEXT_OPTIMIZE | VGX_CONTEXT_WARP | VGX_CONTEXT_EYES |
               VGX_CONTEXT_KEYFRAMES;
    vgx_context *c = NULL;
    CHECK(vgx_context_create(&d, &c) == VGX_SUCCESS, "create: %s", m.last);
    /* A second context with the eyes, two frames, the second with another
     * warp map: the objects a dispatch makes for a configuration (the frame
     * graph's images and buffers, alike with every flag), and those of the
     * one it replaced (retired, not yet freed), are reported too. */
    vgx_context_desc d2 = context_desc(g, 64, 48, &m);
    d2.flags |= VGX_CONTEXT_WARP | VGX_CONTEXT_EYES;
    vgx_context *c2 = NULL;
    CHECK(vgx_context_create(&d2, &c2) == VGX_SUCCESS, "create the eyes' context: %s", m.last);
    enum { W = 64, H = 48 };
    static uint8_t color[W * H * 4];
    gpu_image dimg, cimg;
    CHECK(depth_image(g, W, H, NULL, &dimg) == 0, "depth");
    CHECK(gpu_image_create(g, &(gpu_image_desc){.name = "test colour", .format = VK_FORMAT_R8G8B8A8_UNORM, .width = W,
                                                .height = H, .usage = VK_IMAGE_USAGE_SAMPLED_BIT |
                                                                      VK_IMAGE_USAGE_TRANSFER_DST_BIT},
                           &cimg) == VG_OK &&
              gpu_image_upload(g, &cimg, color, sizeof color) == VG_OK,
          "colour image");
    for (int k = 0; k < 2; k++) {
        VkCommandBuffer cmd;
        CHECK(gpu_oneshot_begin(g, &cmd) == VG_OK, "begin");
        vgx_dispatch_desc dd = depth_dispatch(cmd, &dimg, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        dd.warp_map = k ? VGX_WARP_MAP_H : VGX_WARP_MAP_G;
        for (int i = 0; i < 16; i++)
            dd.view_proj[i] = i % 5 == 0 ? 1.0f : 0.0f;
        dd.background_depth_m = 40.0f;
        dd.color = (vgx_image){cimg.image, cimg.view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        CHECK(vgx_dispatch(c2, &dd) == VGX_SUCCESS, "dispatch %d: %s", k, m.last);
        CHECK(gpu_oneshot_submit(g, cmd) == VG_OK, "submit %d", k);
    }
    gpu_image_destroy(g, &dimg);
    gpu_image_destroy(g, &cimg);
    /* The contexts are left as they are: the device goes first. */
    leak_log log = {0};
    vg_log_sink was = vg_log_set_sink((vg_log_sink){on_leak, &log});
    gpu_destroy(g);
    vg_log_set_sink(was);
    printf("names: the validation layer reported %d objects of the context at the device's destruction, %d of them "
           "named\n", log.objects, log.named);
    CHECK(log.objects > 20, "only %d objects reported: the check sees nothing", log.objects);
    CHECK(log.named == log.objects, "%d of %d objects have no name, e.g. %s", log.objects - log.named, log.objects,
          log.unnamed);
    return 0;
}
#endif

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"version", version}, {"errors", errors}, {"maps", maps}, {"device_depth", device_depth},
        {"allocator", allocator}, {"threads", threads},
#if VGX_HEADER_VERSION_MINOR >= 2 /* 0.2 */
        {"requirements", requirements}, {"in_flight", in_flight}, {"memory", memory},
        {"eyes", eyes}, {"names", names},
#endif
    };
    return vg_test_main(argc, argv, cases, (int)(sizeof cases / sizeof cases[0]));
}
