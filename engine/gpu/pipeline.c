/* vergence — graphics and compute pipelines. */
#include "pipeline.h"

#include "core/log.h"

vg_status gpu_graphics_pipeline_create(gpu *g, const gpu_graphics_desc *d, VkPipeline *out)
{
    VkPipelineShaderStageCreateInfo stages[4];
    uint32_t n = 0;
    const struct { VkShaderModule m; VkShaderStageFlagBits s; } mods[] = {
        {d->vert, VK_SHADER_STAGE_VERTEX_BIT},
        {d->tesc, VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT},
        {d->tese, VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT},
        {d->frag, VK_SHADER_STAGE_FRAGMENT_BIT},
    };
    for (int i = 0; i < 4; i++)
        if (mods[i].m)
            stages[n++] = (VkPipelineShaderStageCreateInfo){
                .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                .stage = mods[i].s,
                .module = mods[i].m,
                .pName = "main",
                .pSpecializationInfo = d->spec,
            };
    bool tess = d->tesc && d->tese;
    VkPipelineVertexInputStateCreateInfo vertex = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount = d->binding_count,
        .pVertexBindingDescriptions = d->bindings,
        .vertexAttributeDescriptionCount = d->attribute_count,
        .pVertexAttributeDescriptions = d->attributes,
    };
    VkPipelineInputAssemblyStateCreateInfo assembly = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        .topology = tess       ? VK_PRIMITIVE_TOPOLOGY_PATCH_LIST
                    : d->points ? VK_PRIMITIVE_TOPOLOGY_POINT_LIST
                                : VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
    };
    VkPipelineTessellationStateCreateInfo tessellation = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_TESSELLATION_STATE_CREATE_INFO,
        .patchControlPoints = d->patch_control_points ? d->patch_control_points : 3,
    };
    VkPipelineViewportStateCreateInfo viewport = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
        .viewportCount = 1,
        .scissorCount = 1,
    };
    VkPipelineRasterizationStateCreateInfo raster = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = d->wireframe ? VK_POLYGON_MODE_LINE : VK_POLYGON_MODE_FILL,
        .cullMode = d->cull,
        .frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE, /* glTF winding; y-flip keeps it */
        .depthBiasEnable = d->depth_bias,
        .lineWidth = 1.0f,
    };
    VkPipelineMultisampleStateCreateInfo multisample = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
        .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT,
    };
    VkPipelineDepthStencilStateCreateInfo depth = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = d->depth_test,
        .depthWriteEnable = d->depth_write,
        .depthCompareOp = d->depth_compare ? d->depth_compare : VK_COMPARE_OP_LESS,
    };
    VkPipelineColorBlendAttachmentState blend[8];
    for (uint32_t i = 0; i < 8; i++)
        blend[i] = (VkPipelineColorBlendAttachmentState){
            .colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                              VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT,
        };
    if (d->blend)
        blend[0] = (VkPipelineColorBlendAttachmentState){
            .blendEnable = VK_TRUE,
            .srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA,
            .dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA,
            .colorBlendOp = VK_BLEND_OP_ADD,
            .srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE,
            .dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA,
            .alphaBlendOp = VK_BLEND_OP_ADD,
            .colorWriteMask = blend[0].colorWriteMask,
        };
    VkPipelineColorBlendStateCreateInfo color = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
        .attachmentCount = d->color_count,
        .pAttachments = blend,
    };
    VkDynamicState dyn[3] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR, VK_DYNAMIC_STATE_DEPTH_BIAS};
    VkPipelineDynamicStateCreateInfo dynamic = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO,
        .dynamicStateCount = d->depth_bias ? 3 : 2,
        .pDynamicStates = dyn,
    };
    VkPipelineRenderingCreateInfo rendering = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO,
        .viewMask = d->view_mask,
        .colorAttachmentCount = d->color_count,
        .pColorAttachmentFormats = d->color_formats,
        .depthAttachmentFormat = d->depth_format,
    };
    VkGraphicsPipelineCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
        .pNext = &rendering,
        .stageCount = n,
        .pStages = stages,
        .pVertexInputState = &vertex,
        .pInputAssemblyState = &assembly,
        .pTessellationState = tess ? &tessellation : NULL,
        .pViewportState = &viewport,
        .pRasterizationState = &raster,
        .pMultisampleState = &multisample,
        .pDepthStencilState = &depth,
        .pColorBlendState = &color,
        .pDynamicState = &dynamic,
        .layout = d->layout,
    };
    VK_TRY(vkCreateGraphicsPipelines(g->device, VK_NULL_HANDLE, 1, &info, g->alloc, out));
    GPU_NAME(g, VK_OBJECT_TYPE_PIPELINE, *out, "%s", d->name ? d->name : "graphics pipeline");
    return VG_OK;
}

vg_status gpu_compute_pipeline_create(gpu *g, VkPipelineLayout layout, VkShaderModule module,
                                      const VkSpecializationInfo *spec, const char *name, VkPipeline *out)
{
    VkComputePipelineCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage = {
            .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
            .stage = VK_SHADER_STAGE_COMPUTE_BIT,
            .module = module,
            .pName = "main",
            .pSpecializationInfo = spec,
        },
        .layout = layout,
    };
    VK_TRY(vkCreateComputePipelines(g->device, VK_NULL_HANDLE, 1, &info, g->alloc, out));
    GPU_NAME(g, VK_OBJECT_TYPE_PIPELINE, *out, "%s", name ? name : "compute pipeline");
    return VG_OK;
}

vg_status gpu_push_layout_create(gpu *g, const char *name, const VkDescriptorType *types, uint32_t count,
                                 VkShaderStageFlags stages, uint32_t push_size,
                                 VkDescriptorSetLayout *set_layout, VkPipelineLayout *layout)
{
    enum { MAX_BINDINGS = 32 }; /* VkPhysicalDevicePushDescriptorPropertiesKHR guarantees 32 */
    if (count > MAX_BINDINGS) {
        vg_error("%s: %u push-descriptor bindings, at most %d", name, count, MAX_BINDINGS);
        return VG_ERR_ARG;
    }
    VkDescriptorSetLayoutBinding bindings[MAX_BINDINGS];
    for (uint32_t i = 0; i < count; i++)
        bindings[i] = (VkDescriptorSetLayoutBinding){i, types[i], 1, stages, NULL};
    VkDescriptorSetLayoutCreateInfo set = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR,
        .bindingCount = count,
        .pBindings = bindings,
    };
    VK_TRY(vkCreateDescriptorSetLayout(g->device, &set, g->alloc, set_layout));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, *set_layout, "%s set layout", name);
    VkPushConstantRange push = {stages, 0, push_size};
    VkPipelineLayoutCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = 1,
        .pSetLayouts = set_layout,
        .pushConstantRangeCount = push_size ? 1 : 0,
        .pPushConstantRanges = &push,
    };
    VK_TRY(vkCreatePipelineLayout(g->device, &info, g->alloc, layout));
    GPU_NAME(g, VK_OBJECT_TYPE_PIPELINE_LAYOUT, *layout, "%s layout", name);
    return VG_OK;
}

vg_status gpu_compute_kit_create(gpu *g, const gpu_compute_kit_desc *d, gpu_compute_kit *out)
{
    *out = (gpu_compute_kit){.push_size = d->push_size};
    vg_status st = gpu_push_layout_create(g, d->name, d->types, d->count, VK_SHADER_STAGE_COMPUTE_BIT, d->push_size,
                                          &out->set_layout, &out->layout);
    for (int i = 0; i < GPU_KIT_MAX_KERNELS && st == VG_OK && d->kernels[i].code; i++) {
        VkShaderModule m = VK_NULL_HANDLE;
        st = gpu_shader_create(g, d->kernels[i].code, d->kernels[i].size, d->kernels[i].name, &m);
        VkSpecializationMapEntry entries[GPU_KIT_MAX_SPEC];
        uint32_t n = d->kernels[i].spec_count < GPU_KIT_MAX_SPEC ? d->kernels[i].spec_count : GPU_KIT_MAX_SPEC;
        for (uint32_t c = 0; c < n; c++)
            entries[c] = (VkSpecializationMapEntry){c, c * (uint32_t)sizeof(uint32_t), sizeof(uint32_t)};
        VkSpecializationInfo spec = {n, entries, n * sizeof(uint32_t), d->kernels[i].spec};
        if (st == VG_OK)
            st = gpu_compute_pipeline_create(g, out->layout, m, n ? &spec : NULL, d->kernels[i].name, &out->pipeline[i]);
        if (m)
            vkDestroyShaderModule(g->device, m, g->alloc);
    }
    if (st != VG_OK)
        gpu_compute_kit_destroy(g, out);
    return st;
}

void gpu_compute_kit_destroy(gpu *g, gpu_compute_kit *k)
{
    if (!k)
        return;
    for (int i = 0; i < GPU_KIT_MAX_KERNELS; i++)
        if (k->pipeline[i])
            vkDestroyPipeline(g->device, k->pipeline[i], g->alloc);
    if (k->layout)
        vkDestroyPipelineLayout(g->device, k->layout, g->alloc);
    if (k->set_layout)
        vkDestroyDescriptorSetLayout(g->device, k->set_layout, g->alloc);
    *k = (gpu_compute_kit){0};
}

void gpu_compute_kit_bind(const gpu *g, VkCommandBuffer cmd, const gpu_compute_kit *k, uint32_t kernel,
                          const VkWriteDescriptorSet *writes, uint32_t count, const void *push)
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, k->pipeline[kernel]);
    g->cmd_push_descriptor_set(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, k->layout, 0, count, writes);
    if (k->push_size && push)
        vkCmdPushConstants(cmd, k->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, k->push_size, push);
}

void gpu_compute_kit_bind_list(const gpu *g, VkCommandBuffer cmd, const gpu_compute_kit *k, uint32_t kernel,
                               const gpu_binding *b, uint32_t count, const void *push)
{
    VkWriteDescriptorSet w[GPU_MAX_BINDINGS];
    VkDescriptorBufferInfo bufs[GPU_MAX_BINDINGS];
    count = count < GPU_MAX_BINDINGS ? count : GPU_MAX_BINDINGS;
    for (uint32_t i = 0; i < count; i++) {
        bufs[i] = (VkDescriptorBufferInfo){b[i].buffer, 0, VK_WHOLE_SIZE};
        w[i] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = i,
                                      .descriptorCount = 1, .descriptorType = b[i].type};
        if (b[i].image)
            w[i].pImageInfo = b[i].image;
        else if (b[i].view)
            w[i].pTexelBufferView = b[i].view;
        else
            w[i].pBufferInfo = &bufs[i];
    }
    gpu_compute_kit_bind(g, cmd, k, kernel, w, count, push);
}

void gpu_pipelines_destroy(gpu *g, VkPipeline *p, uint32_t count)
{
    for (uint32_t i = 0; i < count; i++)
        if (p[i]) {
            vkDestroyPipeline(g->device, p[i], g->alloc);
            p[i] = VK_NULL_HANDLE;
        }
}

void gpu_shaders_destroy(gpu *g, VkShaderModule *m, uint32_t count)
{
    for (uint32_t i = 0; i < count; i++)
        if (m[i]) {
            vkDestroyShaderModule(g->device, m[i], g->alloc);
            m[i] = VK_NULL_HANDLE;
        }
}
