/* vergence — scene upload and per-frame vertex streams. */
#include "scene_gpu.h"

#include <stdio.h>
#include <string.h>

#include "core/log.h"
#include "shared.h"

_Static_assert(VG_MAX_TEXTURES == SCENE_MAX_TEXTURES, "texture array sizes differ");

/* ------------------------------------------------------------------------- */
/* Textures                                                                  */
/* ------------------------------------------------------------------------- */

static vg_status create_sampler(gpu *g, const scene_texture *t, VkSampler *out)
{
    VkSamplerAddressMode mode_s = t && t->mirror_s ? VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
                                  : t && !t->wrap_repeat_s ? VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE
                                                           : VK_SAMPLER_ADDRESS_MODE_REPEAT;
    VkSamplerAddressMode mode_t = t && t->mirror_t ? VK_SAMPLER_ADDRESS_MODE_MIRRORED_REPEAT
                                  : t && !t->wrap_repeat_t ? VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE
                                                           : VK_SAMPLER_ADDRESS_MODE_REPEAT;
    VkFilter filter = t && t->nearest ? VK_FILTER_NEAREST : VK_FILTER_LINEAR;
    VkSamplerCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = filter,
        .minFilter = VK_FILTER_LINEAR,
        .mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST,
        .addressModeU = mode_s,
        .addressModeV = mode_t,
        .addressModeW = VK_SAMPLER_ADDRESS_MODE_REPEAT,
        .maxLod = 0.0f,
    };
    VK_TRY(vkCreateSampler(g->device, &info, g->alloc, out));
    GPU_NAME(g, VK_OBJECT_TYPE_SAMPLER, *out, "sampler %s", t ? t->name : "default");
    return VG_OK;
}

static vg_status upload_textures(gpu *g, scene_gpu *sg)
{
    const scene *s = sg->scene;
    static const uint8_t white[4] = {255, 255, 255, 255};
    vg_status st = gpu_image_create(g, &(gpu_image_desc){
        .name = "texture white", .format = VK_FORMAT_R8G8B8A8_SRGB, .width = 1, .height = 1,
        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT}, &sg->white);
    if (st == VG_OK)
        st = gpu_image_upload(g, &sg->white, white, 4);
    if (st == VG_OK)
        st = create_sampler(g, NULL, &sg->default_sampler);
    for (int i = 0; i < s->texture_count && i < SCENE_MAX_TEXTURES && st == VG_OK; i++) {
        const scene_texture *t = &s->textures[i];
        char name[96];
        snprintf(name, sizeof name, "texture %d %s", i, t->name);
        st = gpu_image_create(g, &(gpu_image_desc){
            .name = name, .format = VK_FORMAT_R8G8B8A8_SRGB, .width = (uint32_t)t->width,
            .height = (uint32_t)t->height,
            .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT}, &sg->textures[i]);
        if (st == VG_OK)
            st = gpu_image_upload(g, &sg->textures[i], t->rgba, (size_t)t->width * (size_t)t->height * 4);
        if (st == VG_OK)
            st = create_sampler(g, t, &sg->samplers[i]);
    }
    if (st != VG_OK)
        return st;

    VkDescriptorSetLayoutBinding binding = {
        .binding = 0,
        .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        .descriptorCount = SCENE_MAX_TEXTURES,
        .stageFlags = VK_SHADER_STAGE_ALL_GRAPHICS,
    };
    VkDescriptorSetLayoutCreateInfo layout = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .bindingCount = 1,
        .pBindings = &binding,
    };
    VK_TRY(vkCreateDescriptorSetLayout(g->device, &layout, g->alloc, &sg->texture_layout));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, sg->texture_layout, "scene textures layout");
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, SCENE_MAX_TEXTURES};
    VkDescriptorPoolCreateInfo pool = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
        .maxSets = 1,
        .poolSizeCount = 1,
        .pPoolSizes = &size,
    };
    VK_TRY(vkCreateDescriptorPool(g->device, &pool, g->alloc, &sg->pool));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_POOL, sg->pool, "scene textures pool");
    VkDescriptorSetAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
        .descriptorPool = sg->pool,
        .descriptorSetCount = 1,
        .pSetLayouts = &sg->texture_layout,
    };
    VK_TRY(vkAllocateDescriptorSets(g->device, &alloc, &sg->texture_set));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_SET, sg->texture_set, "scene textures");
    /* Unused slots point at a white texel so every array element is valid. */
    VkDescriptorImageInfo images[SCENE_MAX_TEXTURES];
    for (int i = 0; i < SCENE_MAX_TEXTURES; i++) {
        bool has = i < s->texture_count;
        images[i] = (VkDescriptorImageInfo){
            .sampler = has ? sg->samplers[i] : sg->default_sampler,
            .imageView = has ? sg->textures[i].view : sg->white.view,
            .imageLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
        };
    }
    VkWriteDescriptorSet write = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = sg->texture_set,
        .descriptorCount = SCENE_MAX_TEXTURES,
        .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        .pImageInfo = images,
    };
    vkUpdateDescriptorSets(g->device, 1, &write, 0, NULL);
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Buffers                                                                   */
/* ------------------------------------------------------------------------- */

vg_status scene_gpu_create(gpu *g, const scene *s, scene_gpu *sg)
{
    *sg = (scene_gpu){.scene = s};
    if (s->texture_count > SCENE_MAX_TEXTURES) {
        vg_error("%s: %d textures, the renderer binds at most %d", s->path, s->texture_count, SCENE_MAX_TEXTURES);
        return VG_ERR_UNSUPPORTED;
    }
    uint32_t nv = s->vertex_count;
    vg_status st = scene_state_init(s, &sg->now);
    if (st == VG_OK)
        st = scene_state_init(s, &sg->prev);
    if (st == VG_OK)
        st = scene_state_init(s, &sg->next);
    if (st == VG_OK)
        st = scene_state_init(s, &sg->before);
    scene_mean_base_color(s, sg->mean_base);
    if (st == VG_OK)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){
            .name = "scene statics", .size = (VkDeviceSize)nv * 6 * sizeof(float),
            .usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, .host_visible = true}, &sg->statics);
    if (st == VG_OK)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){
            .name = "scene indices", .size = (VkDeviceSize)s->index_count * sizeof(uint32_t),
            .usage = VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
            .host_visible = true}, &sg->indices);
    sg->offset_prev = (VkDeviceSize)nv * 6 * sizeof(float);
    sg->offset_next = sg->offset_prev + (VkDeviceSize)nv * 3 * sizeof(float);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT && st == VG_OK; i++) {
        char name[48];
        snprintf(name, sizeof name, "scene vertices slot %d", i);
        st = gpu_buffer_create(g, &(gpu_buffer_desc){
            .name = name, .size = (VkDeviceSize)nv * 12 * sizeof(float),
            .usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
            .host_visible = true}, &sg->dynamic[i]);
    }
    if (st == VG_OK)
        st = upload_textures(g, sg);
    if (st != VG_OK) {
        scene_gpu_destroy(g, sg);
        return st;
    }
    /* Static attributes of every instance, laid out like the evaluated positions. */
    float *statics = sg->statics.mapped;
    for (int i = 0; i < s->instance_count; i++) {
        const scene_instance *in = &s->instances[i];
        const scene_primitive *p = &s->primitives[in->primitive];
        for (uint32_t v = 0; v < p->vertex_count; v++) {
            float *o = statics + (size_t)(in->first_vertex + v) * 6;
            memcpy(o, p->texcoords + 2 * v, 2 * sizeof(float));
            memcpy(o + 2, p->colors + 4 * v, 4 * sizeof(float));
        }
    }
    if (s->index_count)
        memcpy(sg->indices.mapped, s->indices, (size_t)s->index_count * sizeof(uint32_t));
    return VG_OK;
}

void scene_gpu_destroy(gpu *g, scene_gpu *sg)
{
    if (!sg)
        return;
    gpu_buffer_destroy(g, &sg->statics);
    gpu_buffer_destroy(g, &sg->indices);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT; i++)
        gpu_buffer_destroy(g, &sg->dynamic[i]);
    for (int i = 0; i < SCENE_MAX_TEXTURES; i++) {
        gpu_image_destroy(g, &sg->textures[i]);
        if (sg->samplers[i])
            vkDestroySampler(g->device, sg->samplers[i], g->alloc);
    }
    gpu_image_destroy(g, &sg->white);
    if (sg->default_sampler)
        vkDestroySampler(g->device, sg->default_sampler, g->alloc);
    if (sg->pool)
        vkDestroyDescriptorPool(g->device, sg->pool, g->alloc);
    if (sg->texture_layout)
        vkDestroyDescriptorSetLayout(g->device, sg->texture_layout, g->alloc);
    scene_state_free(&sg->now);
    scene_state_free(&sg->prev);
    scene_state_free(&sg->next);
    scene_state_free(&sg->before);
    *sg = (scene_gpu){0};
}

void scene_gpu_update(scene_gpu *sg, int slot, float t, float t_prev, float t_next)
{
    const scene *s = sg->scene;
    scene_evaluate(s, t, &sg->now);
    scene_evaluate(s, t_prev, &sg->prev);
    if (sg->causal_step > 0.0f) {
        scene_evaluate(s, t - sg->causal_step, &sg->before);
        sg->past = (scene_past){.now = &sg->now, .before = &sg->before};
    }
    scene_evaluate(s, t_next, &sg->next);
    float *cur = sg->dynamic[slot].mapped;
    float *prev = (float *)((uint8_t *)sg->dynamic[slot].mapped + sg->offset_prev);
    float *next = (float *)((uint8_t *)sg->dynamic[slot].mapped + sg->offset_next);
    for (uint32_t v = 0; v < s->vertex_count; v++) {
        memcpy(cur + 6 * v, sg->now.positions + 3 * v, 3 * sizeof(float));
        memcpy(cur + 6 * v + 3, sg->now.normals + 3 * v, 3 * sizeof(float));
    }
    memcpy(prev, sg->prev.positions, (size_t)s->vertex_count * 3 * sizeof(float));
    memcpy(next, sg->next.positions, (size_t)s->vertex_count * 3 * sizeof(float));
}

const scene_past *scene_gpu_known(const scene_gpu *sg) { return sg->causal_step > 0.0f ? &sg->past : NULL; }

/* ------------------------------------------------------------------------- */
/* Drawing                                                                   */
/* ------------------------------------------------------------------------- */

void scene_gpu_vertex_input(scene_input input, VkVertexInputBindingDescription *b, uint32_t *nb,
                            VkVertexInputAttributeDescription *a, uint32_t *na)
{
    *nb = *na = 0;
    b[(*nb)++] = (VkVertexInputBindingDescription){SCENE_BINDING_CURRENT, 6 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX};
    a[(*na)++] = (VkVertexInputAttributeDescription){0, SCENE_BINDING_CURRENT, VK_FORMAT_R32G32B32_SFLOAT, 0};
    if (input == SCENE_INPUT_POSITIONS)
        return;
    a[(*na)++] = (VkVertexInputAttributeDescription){1, SCENE_BINDING_CURRENT, VK_FORMAT_R32G32B32_SFLOAT, 12};
    if (input == SCENE_INPUT_MOTION) {
        b[(*nb)++] = (VkVertexInputBindingDescription){SCENE_BINDING_PREV, 3 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX};
        b[(*nb)++] = (VkVertexInputBindingDescription){SCENE_BINDING_NEXT, 3 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX};
        a[(*na)++] = (VkVertexInputAttributeDescription){2, SCENE_BINDING_PREV, VK_FORMAT_R32G32B32_SFLOAT, 0};
        a[(*na)++] = (VkVertexInputAttributeDescription){3, SCENE_BINDING_NEXT, VK_FORMAT_R32G32B32_SFLOAT, 0};
    }
    b[(*nb)++] = (VkVertexInputBindingDescription){SCENE_BINDING_STATIC, 6 * sizeof(float), VK_VERTEX_INPUT_RATE_VERTEX};
    a[(*na)++] = (VkVertexInputAttributeDescription){4, SCENE_BINDING_STATIC, VK_FORMAT_R32G32_SFLOAT, 0};
    a[(*na)++] = (VkVertexInputAttributeDescription){5, SCENE_BINDING_STATIC, VK_FORMAT_R32G32B32A32_SFLOAT, 8};
}

void scene_gpu_draw(const scene_gpu *sg, VkCommandBuffer cmd, int slot, VkPipelineLayout layout,
                    scene_input input, uint32_t flags)
{
    scene_gpu_draw_split(sg, cmd, slot, layout, input, flags, 0);
}

void scene_gpu_bind(const scene_gpu *sg, VkCommandBuffer cmd, int slot, scene_input input, VkBuffer indices)
{
    VkBuffer buffers[4] = {sg->dynamic[slot].buffer, sg->dynamic[slot].buffer, sg->dynamic[slot].buffer,
                           sg->statics.buffer};
    VkDeviceSize offsets[4] = {0, sg->offset_prev, sg->offset_next, 0};
    vkCmdBindVertexBuffers(cmd, 0, input == SCENE_INPUT_POSITIONS ? 1 : 4, buffers, offsets);
    vkCmdBindIndexBuffer(cmd, indices ? indices : sg->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
}

void scene_gpu_push_instance(const scene_gpu *sg, VkCommandBuffer cmd, VkPipelineLayout layout, int instance,
                             uint32_t flags)
{
    const scene *s = sg->scene;
    const scene_instance *in = &s->instances[instance];
    const scene_primitive *p = &s->primitives[in->primitive];
    const scene_material *m = p->material >= 0 ? &s->materials[p->material] : NULL;
    vg_draw_push push = {
        .base_color = {{1, 1, 1, 1}},
        .instance_id = in->id,
        .saliency = in->saliency,
        .texture_index = m ? m->base_color_texture : -1,
        .flags = flags,
    };
    if (m)
        memcpy(push.base_color.v, m->base_color, sizeof push.base_color.v);
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_ALL_GRAPHICS, 0, sizeof push, &push);
}

static void draw_instances(const scene_gpu *sg, VkCommandBuffer cmd, int slot, VkPipelineLayout layout,
                           scene_input input, uint32_t flags, uint32_t max_triangles, const uint8_t *mask,
                           uint8_t value)
{
    const scene *s = sg->scene;
    if (!s->index_count)
        return;
    scene_gpu_bind(sg, cmd, slot, input, VK_NULL_HANDLE);
    for (int i = 0; i < s->instance_count; i++) {
        if (mask && mask[i] != value)
            continue;
        const scene_instance *in = &s->instances[i];
        const scene_primitive *p = &s->primitives[in->primitive];
        if (input != SCENE_INPUT_POSITIONS)
            scene_gpu_push_instance(sg, cmd, layout, i, flags);
        uint32_t chunk = max_triangles ? 3 * max_triangles : p->index_count;
        for (uint32_t first = 0; first < p->index_count; first += chunk) {
            uint32_t count = p->index_count - first < chunk ? p->index_count - first : chunk;
            vkCmdDrawIndexed(cmd, count, 1, in->first_index + first, (int32_t)in->first_vertex, 0);
        }
    }
}

void scene_gpu_draw_split(const scene_gpu *sg, VkCommandBuffer cmd, int slot, VkPipelineLayout layout,
                          scene_input input, uint32_t flags, uint32_t max_triangles)
{
    draw_instances(sg, cmd, slot, layout, input, flags, max_triangles, NULL, 0);
}

void scene_gpu_draw_where(const scene_gpu *sg, VkCommandBuffer cmd, int slot, VkPipelineLayout layout,
                          scene_input input, uint32_t flags, const uint8_t *mask, uint8_t value)
{
    draw_instances(sg, cmd, slot, layout, input, flags, 0, mask, value);
}
