/* vergence — the frame: graph, passes and submission. */
#include "frame.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CGLM_FORCE_DEPTH_ZERO_TO_ONE
#include <cglm/cglm.h>

#include "core/log.h"
#include "gpu/pipeline.h"
#include "scene_gpu.h"
#include "shared.h"

#include "gbuffer_frag.h"
#include "gbuffer_vert.h"
#include "shadow_vert.h"
#include "sky_frag.h"
#include "sky_vert.h"

struct frame {
    gpu *gpu;
    const scene *scene;
    frame_desc desc;
    scene_gpu sg;

    VkDescriptorSetLayout push_layout;   /* set 0: frame UBO, shadow map */
    VkPipelineLayout layout;
    VkPipeline shadow, sky, gbuffer;
    VkSampler shadow_sampler;
    gpu_buffer ubo[VG_FRAMES_IN_FLIGHT];
    gpu_buffer readback;
    VkCommandBuffer cmd[VG_FRAMES_IN_FLIGHT];
    VkFence fence[VG_FRAMES_IN_FLIGHT];
    bool submitted[VG_FRAMES_IN_FLIGHT];
    int slot;

    rg_graph *graph;
    rg_res r_ubo, r_vertices, r_statics, r_indices;
    rg_res r_shadow, r_color, r_depth, r_ids, r_motion, r_zbuffer, r_readback;

    frame_times times;
    vg_camera cam, cam_prev, cam_next;
    frame_outputs outputs;
};

static const VkFormat k_gbuffer_formats[4] = {
    [VG_GBUFFER_COLOR] = VK_FORMAT_R8G8B8A8_SRGB,
    [VG_GBUFFER_DEPTH] = VK_FORMAT_R32_SFLOAT,
    [VG_GBUFFER_ID] = VK_FORMAT_R32_UINT,
    [VG_GBUFFER_MOTION] = VK_FORMAT_R32G32B32A32_SFLOAT,
};
static const VkFormat k_depth_format = VK_FORMAT_D32_SFLOAT;

/* ------------------------------------------------------------------------- */
/* Times                                                                     */
/* ------------------------------------------------------------------------- */

static long floor_div(long a, long b)
{
    long q = a / b;
    return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
}

frame_times frame_times_at(long index, double fps, int stride)
{
    /* Neighbouring keyframes strictly before and after: on a keyframe these
     * are the keyframes one stride away, as the keyframe window needs. */
    long prev = floor_div(index - 1, stride) * stride;
    long next = prev + stride;
    if (next <= index)
        next += stride;
    return (frame_times){
        .index = index, .prev_key = prev, .next_key = next,
        .t = (double)index / fps, .t_prev = (double)prev / fps, .t_next = (double)next / fps,
    };
}

/* ------------------------------------------------------------------------- */
/* Passes                                                                    */
/* ------------------------------------------------------------------------- */

static void push_frame_descriptors(frame *f, const rg_context *ctx, bool with_shadow)
{
    VkDescriptorBufferInfo ubo = {f->ubo[f->slot].buffer, 0, sizeof(vg_frame_ubo)};
    VkDescriptorImageInfo shadow = {
        .sampler = f->shadow_sampler,
        .imageView = rg_ctx_view(ctx, f->r_shadow),
        .imageLayout = rg_ctx_layout(ctx, f->r_shadow),
    };
    VkWriteDescriptorSet writes[2] = {
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 0, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, .pBufferInfo = &ubo},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = 1, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, .pImageInfo = &shadow},
    };
    f->gpu->cmd_push_descriptor_set(rg_ctx_cmd(ctx), VK_PIPELINE_BIND_POINT_GRAPHICS, f->layout, 0,
                                    with_shadow ? 2 : 1, writes);
}

static void shadow_execute(const rg_context *ctx, void *user)
{
    frame *f = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, f->shadow);
    push_frame_descriptors(f, ctx, false);
    /* Slope-scaled bias keeps grazing surfaces free of acne. */
    vkCmdSetDepthBias(cmd, 1.0f, 0.0f, 1.75f);
    scene_gpu_draw(&f->sg, cmd, f->slot, f->layout, true);
}

static void gbuffer_execute(const rg_context *ctx, void *user)
{
    frame *f = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    push_frame_descriptors(f, ctx, true);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, f->layout, 1, 1, &f->sg.texture_set, 0, NULL);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, f->sky);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, f->gbuffer);
    scene_gpu_draw(&f->sg, cmd, f->slot, f->layout, false);
}

static void readback_execute(const rg_context *ctx, void *user)
{
    frame *f = user;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    VkDeviceSize pixels = (VkDeviceSize)f->desc.width * f->desc.height, offset = 0;
    const rg_res images[4] = {f->r_color, f->r_depth, f->r_ids, f->r_motion};
    const VkDeviceSize texel[4] = {4, 4, 4, 16};
    for (int i = 0; i < 4; i++) {
        VkBufferImageCopy region = {
            .bufferOffset = offset,
            .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
            .imageExtent = {f->desc.width, f->desc.height, 1},
        };
        vkCmdCopyImageToBuffer(cmd, rg_ctx_image(ctx, images[i]), rg_ctx_layout(ctx, images[i]),
                               rg_ctx_buffer(ctx, f->r_readback), 1, &region);
        offset += pixels * texel[i];
    }
}

/* ------------------------------------------------------------------------- */
/* Graph                                                                     */
/* ------------------------------------------------------------------------- */

static vg_status build_graph(frame *f)
{
    rg_graph *g = f->graph = rg_create();
    if (!g)
        return VG_ERR_NOMEM;
    uint32_t w = f->desc.width, h = f->desc.height, sz = f->desc.shadow_size;
    rg_import_desc ready_vertex = {.initial = RG_VERTEX}, ready_index = {.initial = RG_INDEX},
                   ready_uniform = {.initial = RG_UNIFORM};
    f->r_ubo = rg_import_buffer(g, &(rg_buffer_desc){"frame.ubo", sizeof(vg_frame_ubo)}, &ready_uniform);
    f->r_vertices = rg_import_buffer(g, &(rg_buffer_desc){"scene.vertices", f->sg.dynamic[0].size}, &ready_vertex);
    f->r_statics = rg_import_buffer(g, &(rg_buffer_desc){"scene.statics", f->sg.statics.size}, &ready_vertex);
    f->r_indices = rg_import_buffer(g, &(rg_buffer_desc){"scene.indices", f->sg.indices.size}, &ready_index);
    f->r_shadow = rg_image(g, &(rg_image_desc){"shadow.map", k_depth_format, sz, sz, 1});
    f->r_color = rg_image(g, &(rg_image_desc){"gbuffer.color", k_gbuffer_formats[VG_GBUFFER_COLOR], w, h, 1});
    f->r_depth = rg_image(g, &(rg_image_desc){"gbuffer.depth", k_gbuffer_formats[VG_GBUFFER_DEPTH], w, h, 1});
    f->r_ids = rg_image(g, &(rg_image_desc){"gbuffer.ids", k_gbuffer_formats[VG_GBUFFER_ID], w, h, 1});
    f->r_motion = rg_image(g, &(rg_image_desc){"gbuffer.motion", k_gbuffer_formats[VG_GBUFFER_MOTION], w, h, 1});
    f->r_zbuffer = rg_image(g, &(rg_image_desc){"gbuffer.zbuffer", k_depth_format, w, h, 1});

    rg_pass shadow = rg_pass_add(g, &(rg_pass_desc){.name = "shadow", .type = RG_PASS_GRAPHICS,
                                                    .execute = shadow_execute, .user = f});
    rg_use(g, shadow, f->r_ubo, RG_UNIFORM);
    rg_use(g, shadow, f->r_vertices, RG_VERTEX);
    rg_use(g, shadow, f->r_indices, RG_INDEX);
    rg_use_clear(g, shadow, f->r_shadow, RG_DEPTH_WRITE, (VkClearValue){.depthStencil = {1.0f, 0}});

    rg_pass gbuf = rg_pass_add(g, &(rg_pass_desc){.name = "gbuffer", .type = RG_PASS_GRAPHICS,
                                                  .execute = gbuffer_execute, .user = f});
    rg_use(g, gbuf, f->r_ubo, RG_UNIFORM);
    rg_use(g, gbuf, f->r_vertices, RG_VERTEX);
    rg_use(g, gbuf, f->r_statics, RG_VERTEX);
    rg_use(g, gbuf, f->r_indices, RG_INDEX);
    rg_use(g, gbuf, f->r_shadow, RG_SAMPLED);
    /* Attachment order = shader output locations (shared.h). */
    rg_use(g, gbuf, f->r_color, RG_COLOR_WRITE);
    rg_use(g, gbuf, f->r_depth, RG_COLOR_WRITE);
    rg_use(g, gbuf, f->r_ids, RG_COLOR_WRITE);
    rg_use(g, gbuf, f->r_motion, RG_COLOR_WRITE);
    rg_use_clear(g, gbuf, f->r_zbuffer, RG_DEPTH_WRITE, (VkClearValue){.depthStencil = {1.0f, 0}});

    if (f->desc.readback) {
        uint64_t size = f->readback.size;
        f->r_readback = rg_import_buffer(g, &(rg_buffer_desc){"readback", size},
                                         &(rg_import_desc){.final = RG_HOST_READ});
        rg_pass rb = rg_pass_add(g, &(rg_pass_desc){.name = "readback", .type = RG_PASS_TRANSFER,
                                                    .execute = readback_execute, .user = f});
        rg_use(g, rb, f->r_color, RG_TRANSFER_SRC);
        rg_use(g, rb, f->r_depth, RG_TRANSFER_SRC);
        rg_use(g, rb, f->r_ids, RG_TRANSFER_SRC);
        rg_use(g, rb, f->r_motion, RG_TRANSFER_SRC);
        rg_use(g, rb, f->r_readback, RG_TRANSFER_DST);
    } else {
        rg_export(g, f->r_color);
        rg_export(g, f->r_depth);
        rg_export(g, f->r_ids);
        rg_export(g, f->r_motion);
    }
    vg_status st = rg_compile(g);
    if (st == VG_OK)
        st = rg_realize(g, f->gpu);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Pipelines                                                                 */
/* ------------------------------------------------------------------------- */

static vg_status create_pipelines(frame *f)
{
    gpu *g = f->gpu;
    VkDescriptorSetLayoutBinding bindings[2] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_ALL_GRAPHICS, NULL},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_ALL_GRAPHICS, NULL},
    };
    VkDescriptorSetLayoutCreateInfo set0 = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR,
        .bindingCount = 2,
        .pBindings = bindings,
    };
    VK_TRY(vkCreateDescriptorSetLayout(g->device, &set0, NULL, &f->push_layout));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, f->push_layout, "frame push layout");
    VkDescriptorSetLayout sets[2] = {f->push_layout, f->sg.texture_layout};
    VkPushConstantRange push = {VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(vg_draw_push)};
    VkPipelineLayoutCreateInfo layout = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = 2,
        .pSetLayouts = sets,
        .pushConstantRangeCount = 1,
        .pPushConstantRanges = &push,
    };
    VK_TRY(vkCreatePipelineLayout(g->device, &layout, NULL, &f->layout));
    GPU_NAME(g, VK_OBJECT_TYPE_PIPELINE_LAYOUT, f->layout, "scene pipeline layout");

    VkSamplerCreateInfo shadow_sampler = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = VK_FILTER_LINEAR,
        .minFilter = VK_FILTER_LINEAR,
        .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
        .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
        .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_BORDER,
        .compareEnable = VK_TRUE,
        .compareOp = VK_COMPARE_OP_LESS_OR_EQUAL,
        .borderColor = VK_BORDER_COLOR_FLOAT_OPAQUE_WHITE,
    };
    VK_TRY(vkCreateSampler(g->device, &shadow_sampler, NULL, &f->shadow_sampler));
    GPU_NAME(g, VK_OBJECT_TYPE_SAMPLER, f->shadow_sampler, "shadow compare sampler");

    VkShaderModule gvert = 0, gfrag = 0, svert = 0, skyv = 0, skyf = 0;
    vg_status st = GPU_SHADER(g, spv_gbuffer_vert, &gvert);
    if (st == VG_OK) st = GPU_SHADER(g, spv_gbuffer_frag, &gfrag);
    if (st == VG_OK) st = GPU_SHADER(g, spv_shadow_vert, &svert);
    if (st == VG_OK) st = GPU_SHADER(g, spv_sky_vert, &skyv);
    if (st == VG_OK) st = GPU_SHADER(g, spv_sky_frag, &skyf);

    VkVertexInputBindingDescription vb[4];
    VkVertexInputAttributeDescription va[6];
    uint32_t nb, na;
    if (st == VG_OK) {
        scene_gpu_vertex_input(true, vb, &nb, va, &na);
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "shadow", .layout = f->layout, .vert = svert, .bindings = vb, .binding_count = nb,
            .attributes = va, .attribute_count = na, .depth_test = true, .depth_write = true,
            .depth_bias = true, .depth_format = k_depth_format}, &f->shadow);
    }
    if (st == VG_OK)
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "sky", .layout = f->layout, .vert = skyv, .frag = skyf,
            .color_formats = k_gbuffer_formats, .color_count = 4, .depth_format = k_depth_format}, &f->sky);
    if (st == VG_OK) {
        scene_gpu_vertex_input(false, vb, &nb, va, &na);
        /* No culling: single-sided glTF surfaces seen from behind flip their
         * normal in the shader instead of leaving holes in depth and ids. */
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "gbuffer", .layout = f->layout, .vert = gvert, .frag = gfrag, .bindings = vb,
            .binding_count = nb, .attributes = va, .attribute_count = na, .depth_test = true,
            .depth_write = true, .color_formats = k_gbuffer_formats, .color_count = 4,
            .depth_format = k_depth_format}, &f->gbuffer);
    }
    VkShaderModule mods[] = {gvert, gfrag, svert, skyv, skyf};
    for (size_t i = 0; i < sizeof mods / sizeof mods[0]; i++)
        if (mods[i])
            vkDestroyShaderModule(g->device, mods[i], NULL);
    return st;
}

/* ------------------------------------------------------------------------- */
/* Lifetime                                                                  */
/* ------------------------------------------------------------------------- */

vg_status frame_create(gpu *g, const scene *s, const frame_desc *desc, frame **out)
{
    *out = NULL;
    frame *f = calloc(1, sizeof *f);
    if (!f)
        return VG_ERR_NOMEM;
    f->gpu = g;
    f->scene = s;
    f->desc = *desc;
    if (!f->desc.width || !f->desc.height) {
        f->desc.width = 960;
        f->desc.height = 540;
    }
    if (f->desc.fps <= 0)
        f->desc.fps = 60;
    if (f->desc.keyframe_stride <= 0)
        f->desc.keyframe_stride = 10;
    if (!f->desc.shadow_size)
        f->desc.shadow_size = 2048;

    vg_status st = scene_gpu_create(g, s, &f->sg);
    if (st == VG_OK)
        st = create_pipelines(f);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT && st == VG_OK; i++) {
        char name[32];
        snprintf(name, sizeof name, "frame ubo slot %d", i);
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = name, .size = sizeof(vg_frame_ubo),
                                                     .usage = VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                                     .host_visible = true}, &f->ubo[i]);
    }
    if (st == VG_OK && f->desc.readback)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){
            .name = "gbuffer readback", .size = (VkDeviceSize)f->desc.width * f->desc.height * 28,
            .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT, .host_visible = true}, &f->readback);
    if (st == VG_OK) {
        VkCommandBufferAllocateInfo alloc = {
            .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
            .commandPool = g->pool,
            .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
            .commandBufferCount = VG_FRAMES_IN_FLIGHT,
        };
        VkResult r = vkAllocateCommandBuffers(g->device, &alloc, f->cmd);
        for (int i = 0; i < VG_FRAMES_IN_FLIGHT && r == VK_SUCCESS; i++) {
            GPU_NAME(g, VK_OBJECT_TYPE_COMMAND_BUFFER, f->cmd[i], "frame commands slot %d", i);
            r = vkCreateFence(g->device, &(VkFenceCreateInfo){.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO},
                              NULL, &f->fence[i]);
            GPU_NAME(g, VK_OBJECT_TYPE_FENCE, f->fence[i], "frame fence slot %d", i);
        }
        if (r != VK_SUCCESS) {
            gpu_report_failure(__FILE__, __LINE__, "frame command buffers", r);
            st = VG_ERR_VULKAN;
        }
    }
    if (st == VG_OK)
        st = build_graph(f);
    if (st != VG_OK) {
        frame_destroy(f);
        return st;
    }
    if (f->desc.readback) {
        size_t pixels = (size_t)f->desc.width * f->desc.height;
        const uint8_t *base = f->readback.mapped;
        f->outputs = (frame_outputs){
            .color = base,
            .depth = (const float *)(base + pixels * 4),
            .ids = (const uint32_t *)(base + pixels * 8),
            .motion = (const float *)(base + pixels * 12),
        };
    }
    *out = f;
    return VG_OK;
}

void frame_destroy(frame *f)
{
    if (!f)
        return;
    gpu *g = f->gpu;
    vkDeviceWaitIdle(g->device);
    rg_destroy(f->graph);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT; i++) {
        gpu_buffer_destroy(g, &f->ubo[i]);
        if (f->fence[i])
            vkDestroyFence(g->device, f->fence[i], NULL);
    }
    if (f->cmd[0])
        vkFreeCommandBuffers(g->device, g->pool, VG_FRAMES_IN_FLIGHT, f->cmd);
    gpu_buffer_destroy(g, &f->readback);
    VkPipeline pipes[] = {f->shadow, f->sky, f->gbuffer};
    for (size_t i = 0; i < sizeof pipes / sizeof pipes[0]; i++)
        if (pipes[i])
            vkDestroyPipeline(g->device, pipes[i], NULL);
    if (f->shadow_sampler)
        vkDestroySampler(g->device, f->shadow_sampler, NULL);
    if (f->layout)
        vkDestroyPipelineLayout(g->device, f->layout, NULL);
    if (f->push_layout)
        vkDestroyDescriptorSetLayout(g->device, f->push_layout, NULL);
    scene_gpu_destroy(g, &f->sg);
    free(f);
}

/* ------------------------------------------------------------------------- */
/* Rendering                                                                 */
/* ------------------------------------------------------------------------- */

/* Sun: low in the sky to the left and behind the viewer, so shadows fall
 * into the scene and give depth cues (a fixed light keeps captures stable). */
static void light_setup(const frame *f, vg_frame_ubo *u)
{
    vec3 sun = {-0.42f, 0.74f, 0.52f};
    glm_vec3_normalize(sun);
    const scene_state *st = &f->sg.now;
    vec3 lo, hi, centre;
    glm_vec3_copy((float *)st->bounds_min, lo);
    glm_vec3_copy((float *)st->bounds_max, hi);
    glm_vec3_center(lo, hi, centre);
    float radius = 0.5f * glm_vec3_distance(lo, hi) + 0.01f;
    vec3 eye, up = {0, 1, 0};
    glm_vec3_scale(sun, 2.0f * radius, eye);
    glm_vec3_add(centre, eye, eye);
    if (fabsf(sun[1]) > 0.99f)
        glm_vec3_copy((vec3){0, 0, 1}, up);
    mat4 view, proj, vp;
    glm_lookat(eye, centre, up, view);
    glm_ortho(-radius, radius, -radius, radius, 0.0f, 4.0f * radius, proj);
    glm_mat4_mul(proj, view, vp);
    memcpy(u->light_view_proj.m, vp, sizeof vp);
    memcpy(u->sun_dir.v, (float[4]){sun[0], sun[1], sun[2], 2.0f * radius / (float)f->desc.shadow_size}, 16);
    memcpy(u->sun_color.v, (float[4]){3.1f, 2.9f, 2.6f, 0.55f}, 16);
    memcpy(u->sky_zenith.v, (float[4]){0.23f, 0.42f, 0.78f, 0.0035f}, 16);
    memcpy(u->sky_horizon.v, (float[4]){0.78f, 0.86f, 0.95f, 0.85f}, 16);
    memcpy(u->ground_color.v, (float[4]){0.30f, 0.27f, 0.22f, 0.0f}, 16);
}

static void fill_ubo(frame *f, vg_frame_ubo *u)
{
    memset(u, 0, sizeof *u);
    memcpy(u->view_proj.m, f->cam.view_proj, 64);
    memcpy(u->view_proj_prev.m, f->cam_prev.view_proj, 64);
    memcpy(u->view_proj_next.m, f->cam_next.view_proj, 64);
    memcpy(u->view.m, f->cam.view, 64);
    mat4 vp, inv; /* cglm's SIMD paths need its own aligned matrices */
    memcpy(vp, f->cam.view_proj, sizeof vp);
    glm_mat4_inv(vp, inv);
    memcpy(u->inv_view_proj.m, inv, 64);
    memcpy(u->camera_pos.v, (float[4]){f->cam.position[0], f->cam.position[1], f->cam.position[2], f->cam.zfar}, 16);
    memcpy(u->viewport.v, (float[4]){(float)f->desc.width, (float)f->desc.height, 1.0f / (float)f->desc.width,
                                     1.0f / (float)f->desc.height}, 16);
    light_setup(f, u);
}

vg_status frame_render(frame *f, long index)
{
    gpu *g = f->gpu;
    f->slot = (f->slot + 1) % VG_FRAMES_IN_FLIGHT;
    int slot = f->slot;
    if (f->submitted[slot]) {
        VK_TRY(vkWaitForFences(g->device, 1, &f->fence[slot], VK_TRUE, UINT64_MAX));
        VK_TRY(vkResetFences(g->device, 1, &f->fence[slot]));
        f->submitted[slot] = false;
    }
    f->times = frame_times_at(index, f->desc.fps, f->desc.keyframe_stride);
    scene_gpu_update(&f->sg, slot, (float)f->times.t, (float)f->times.t_prev, (float)f->times.t_next);
    float aspect = (float)f->desc.width / (float)f->desc.height;
    scene_camera_resolve(f->scene, &f->sg.now, f->desc.camera, aspect, &f->cam);
    scene_camera_resolve(f->scene, &f->sg.prev, f->desc.camera, aspect, &f->cam_prev);
    scene_camera_resolve(f->scene, &f->sg.next, f->desc.camera, aspect, &f->cam_next);
    fill_ubo(f, f->ubo[slot].mapped);

    rg_bind_buffer(f->graph, f->r_ubo, f->ubo[slot].buffer);
    rg_bind_buffer(f->graph, f->r_vertices, f->sg.dynamic[slot].buffer);
    rg_bind_buffer(f->graph, f->r_statics, f->sg.statics.buffer);
    rg_bind_buffer(f->graph, f->r_indices, f->sg.indices.buffer);
    if (f->desc.readback)
        rg_bind_buffer(f->graph, f->r_readback, f->readback.buffer);

    VkCommandBuffer cmd = f->cmd[slot];
    VK_TRY(vkResetCommandBuffer(cmd, 0));
    VK_TRY(vkBeginCommandBuffer(cmd, &(VkCommandBufferBeginInfo){
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT}));
    rg_execute(f->graph, cmd);
    VK_TRY(vkEndCommandBuffer(cmd));
    VkSubmitInfo submit = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .commandBufferCount = 1,
        .pCommandBuffers = &cmd,
    };
    VK_TRY(vkQueueSubmit(g->queue, 1, &submit, f->fence[slot]));
    f->submitted[slot] = true;
    /* Headless: wait, so outputs and timings belong to this frame. */
    VK_TRY(vkWaitForFences(g->device, 1, &f->fence[slot], VK_TRUE, UINT64_MAX));
    return VG_OK;
}

const frame_outputs *frame_get_outputs(const frame *f) { return &f->outputs; }
const frame_times *frame_get_times(const frame *f) { return &f->times; }
const vg_camera *frame_get_camera(const frame *f) { return &f->cam; }
const frame_desc *frame_get_desc(const frame *f) { return &f->desc; }
rg_graph *frame_get_graph(frame *f) { return f->graph; }

uint32_t frame_pass_timings(frame *f, const char **names, double *ms, uint32_t cap)
{
    uint32_t n = rg_timings(f->graph, ms, cap);
    for (uint32_t i = 0; i < n; i++)
        names[i] = rg_pass_name(f->graph, rg_order_pass(f->graph, i));
    return n;
}
