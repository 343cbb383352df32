/* vergence — pipeline creation from desc structs (zero = default). */
#pragma once
#include "gpu.h"

typedef struct gpu_graphics_desc {
    const char *name;
    VkPipelineLayout layout;
    VkShaderModule vert, tesc, tese, frag;   /* frag may be null (depth only) */
    const VkVertexInputBindingDescription *bindings;
    uint32_t binding_count;
    const VkVertexInputAttributeDescription *attributes;
    uint32_t attribute_count;
    uint32_t patch_control_points;           /* with tessellation: 3 */
    bool points;                             /* point list instead of triangle list */
    VkCullModeFlags cull;                    /* 0 = none */
    bool depth_test, depth_write;
    VkCompareOp depth_compare;               /* 0 (NEVER) means LESS */
    bool depth_bias;                         /* dynamic depth bias */
    bool wireframe;
    bool blend;                              /* alpha blending (premultiplied: no) on colour 0 */
    const VkFormat *color_formats;
    uint32_t color_count;
    VkFormat depth_format;
    uint32_t view_mask;                      /* multiview */
} gpu_graphics_desc;

vg_status gpu_graphics_pipeline_create(gpu *g, const gpu_graphics_desc *desc, VkPipeline *out);
vg_status gpu_compute_pipeline_create(gpu *g, VkPipelineLayout layout, VkShaderModule module,
                                      const char *name, VkPipeline *out);

/* Shader module from an embedded SPIR-V array: GPU_SHADER(g, spv_gbuffer_vert, &m). */
#define GPU_SHADER(g, spv, out) gpu_shader_create((g), (spv), sizeof(spv), #spv, (out))

/* A push-descriptor set layout of `count` bindings 0..count-1 (types[i] at
 * binding i) for `stages`, and a pipeline layout of it with push_size bytes
 * of push constants (0 = none). */
vg_status gpu_push_layout_create(gpu *g, const char *name, const VkDescriptorType *types, uint32_t count,
                                 VkShaderStageFlags stages, uint32_t push_size,
                                 VkDescriptorSetLayout *set_layout, VkPipelineLayout *layout);
