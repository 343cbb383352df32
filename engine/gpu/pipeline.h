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
    const VkSpecializationInfo *spec;        /* specialisation constants of every stage, or NULL */
} gpu_graphics_desc;

vg_status gpu_graphics_pipeline_create(gpu *g, const gpu_graphics_desc *desc, VkPipeline *out);
/* spec: specialisation constants, or NULL. */
vg_status gpu_compute_pipeline_create(gpu *g, VkPipelineLayout layout, VkShaderModule module,
                                      const VkSpecializationInfo *spec, const char *name, VkPipeline *out);

/* Destroys the non-null pipelines (shader modules) of an array and zeroes them. */
void gpu_pipelines_destroy(gpu *g, VkPipeline *p, uint32_t count);
void gpu_shaders_destroy(gpu *g, VkShaderModule *m, uint32_t count);

/* Shader module from an embedded SPIR-V array: GPU_SHADER(g, spv_gbuffer_vert, &m). */
#define GPU_SHADER(g, spv, out) gpu_shader_create((g), (spv), sizeof(spv), #spv, (out))

/* A push-descriptor set layout of `count` bindings 0..count-1 (types[i] at
 * binding i) for `stages`, and a pipeline layout of it with push_size bytes
 * of push constants (0 = none). */
vg_status gpu_push_layout_create(gpu *g, const char *name, const VkDescriptorType *types, uint32_t count,
                                 VkShaderStageFlags stages, uint32_t push_size,
                                 VkDescriptorSetLayout *set_layout, VkPipelineLayout *layout);

/* The compute kit: kernels that share one push-descriptor set layout and
 * pipeline layout (bindings 0..count-1, compute stage, push_size bytes of
 * push constants), each a pipeline built from its SPIR-V. One create, one
 * bind, one NULL-safe destroy for every compute pass module. */
#define GPU_KIT_MAX_KERNELS 8
#define GPU_KIT_MAX_SPEC 4

typedef struct gpu_kernel_code {
    const uint32_t *code;
    size_t size;                             /* bytes */
    const char *name;                        /* the pipeline's debug name */
    const uint32_t *spec;                    /* specialisation constants 0 .. spec_count - 1 (uints), or NULL */
    uint32_t spec_count;
} gpu_kernel_code;
/* A kernel from an embedded SPIR-V array: GPU_KERNEL(spv_compose_comp, "compose"). */
#define GPU_KERNEL(spv, name) ((gpu_kernel_code){(spv), sizeof(spv), (name), NULL, 0})
/* The same with specialisation constants (a uint array): one pipeline per
 * value, so a CPU rasteriser does not run every branch of a switch. */
#define GPU_KERNEL_SPEC(spv, name, consts) \
    ((gpu_kernel_code){(spv), sizeof(spv), (name), (consts), sizeof(consts) / sizeof(uint32_t)})

typedef struct gpu_compute_kit_desc {
    const char *name;                        /* names the layouts */
    const VkDescriptorType *types;           /* binding i has types[i] */
    uint32_t count;
    uint32_t push_size;
    gpu_kernel_code kernels[GPU_KIT_MAX_KERNELS]; /* up to the first without code */
} gpu_compute_kit_desc;

typedef struct gpu_compute_kit {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline[GPU_KIT_MAX_KERNELS];
    uint32_t push_size;
} gpu_compute_kit;

vg_status gpu_compute_kit_create(gpu *g, const gpu_compute_kit_desc *desc, gpu_compute_kit *out);
void gpu_compute_kit_destroy(gpu *g, gpu_compute_kit *k);
/* Binds kernel `kernel`, pushes `count` descriptor writes and, when the kit
 * has them, its push constants from `push`. */
void gpu_compute_kit_bind(const gpu *g, VkCommandBuffer cmd, const gpu_compute_kit *k, uint32_t kernel,
                          const VkWriteDescriptorSet *writes, uint32_t count, const void *push);

/* The descriptor of one binding: an image, a whole buffer or a texel view. */
typedef struct gpu_binding {
    VkDescriptorType type;
    const VkDescriptorImageInfo *image;
    VkBuffer buffer;
    const VkBufferView *view;
} gpu_binding;
#define GPU_STORAGE_IMAGE(info) ((gpu_binding){VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, (info), VK_NULL_HANDLE, NULL})
#define GPU_STORAGE_BUFFER(buf) ((gpu_binding){VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, NULL, (buf), NULL})
#define GPU_UNIFORM_BUFFER(buf) ((gpu_binding){VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, NULL, (buf), NULL})
#define GPU_UNIFORM_TEXEL(view) ((gpu_binding){VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, NULL, VK_NULL_HANDLE, (view)})
#define GPU_MAX_BINDINGS 8
/* The same with bindings 0..count-1 given as b[0..count-1] (count <= GPU_MAX_BINDINGS). */
void gpu_compute_kit_bind_list(const gpu *g, VkCommandBuffer cmd, const gpu_compute_kit *k, uint32_t kernel,
                               const gpu_binding *b, uint32_t count, const void *push);
