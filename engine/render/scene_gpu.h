/* vergence — a scene on the GPU: static attributes, indices, textures, and
 * per-frame world-space vertices at the frame's time and at its neighbouring
 * keyframe times (for motion vectors and the keyframes' look-ahead). */
#pragma once
#include "gpu/gpu.h"
#include "pass/frame_types.h" /* VG_FRAMES_IN_FLIGHT */
#include "scene/scene.h"

/* Vertex bindings of the scene pipelines. */
enum {
    SCENE_BINDING_CURRENT = 0, /* position + normal at t (6 floats) */
    SCENE_BINDING_PREV,        /* position at the previous keyframe (3 floats) */
    SCENE_BINDING_NEXT,        /* position at the next keyframe (3 floats) */
    SCENE_BINDING_STATIC,      /* texcoord + colour (6 floats) */
    SCENE_BINDING_COUNT,
};

typedef struct scene_gpu {
    const scene *scene;
    gpu_buffer statics;                        /* SCENE_BINDING_STATIC */
    gpu_buffer indices;
    gpu_buffer dynamic[VG_FRAMES_IN_FLIGHT];   /* current | prev | next regions */
    VkDeviceSize offset_prev, offset_next;
    gpu_image textures[SCENE_MAX_TEXTURES];
    VkSampler samplers[SCENE_MAX_TEXTURES];
    gpu_image white;
    VkSampler default_sampler;
    VkDescriptorSetLayout texture_layout;      /* set 1: sampler2D textures[] */
    VkDescriptorPool pool;
    VkDescriptorSet texture_set;
    scene_state now, prev, next;               /* evaluated states of the last update */
    /* Causal look-ahead (causal_step > 0, set by the owner): the keyframes
     * of the window after the frame's time are predicted from now and
     * `before` (causal_step seconds earlier; scene_evaluate_known). The
     * frame's own motion to its next keyframe stays exact (docs/method.md
     * "Look-ahead": what the metrics measure with). */
    float causal_step;
    scene_state before;
    scene_past past;
    /* Computed saliency (set by the owner before the G-buffer pipelines,
     * which it specialises); mean_base is the contrast's reference. */
    bool computed_saliency;
    float mean_base[3];
} scene_gpu;

vg_status scene_gpu_create(gpu *g, const scene *s, scene_gpu *out);
void scene_gpu_destroy(gpu *g, scene_gpu *sg);

/* Evaluates the scene at t, t_prev and t_next (and causal_step before t)
 * and writes slot's vertices. */
void scene_gpu_update(scene_gpu *sg, int slot, float t, float t_prev, float t_next);
/* What the keyframe window knows of the scene at the last update: NULL
 * (all of it, the scene's own future) unless causal_step > 0. */
const scene_past *scene_gpu_known(const scene_gpu *sg);

/* What a scene pipeline reads (locations: 0 position, 1 normal, 2 previous
 * position, 3 next position, 4 texcoord, 5 colour). */
typedef enum scene_input {
    SCENE_INPUT_DEFAULT = 0,  /* = SCENE_INPUT_SHADE */
    SCENE_INPUT_POSITIONS,    /* 0 */
    SCENE_INPUT_SHADE,        /* 0, 1, 4, 5 */
    SCENE_INPUT_MOTION,       /* 0 .. 5 */
} scene_input;

void scene_gpu_vertex_input(scene_input input, VkVertexInputBindingDescription *bindings,
                            uint32_t *binding_count, VkVertexInputAttributeDescription *attributes,
                            uint32_t *attribute_count);

/* Binds the slot's buffers and draws every instance; unless only positions
 * are read, each instance's vg_draw_push (all graphics stages, with `flags`)
 * precedes its draw. */
void scene_gpu_draw(const scene_gpu *sg, VkCommandBuffer cmd, int slot, VkPipelineLayout layout,
                    scene_input input, uint32_t flags);
/* Binds the slot's vertex streams and an index buffer (null: the scene's). */
void scene_gpu_bind(const scene_gpu *sg, VkCommandBuffer cmd, int slot, scene_input input, VkBuffer indices);
/* Pushes instance's vg_draw_push (material, id, saliency, flags). */
void scene_gpu_push_instance(const scene_gpu *sg, VkCommandBuffer cmd, VkPipelineLayout layout, int instance,
                             uint32_t flags);
/* The same as triangle patches, at most max_triangles per draw (0 = no
 * limit): lavapipe corrupts draws whose tessellation makes over 65,535
 * vertices (PLATFORM.md). */
void scene_gpu_draw_split(const scene_gpu *sg, VkCommandBuffer cmd, int slot, VkPipelineLayout layout,
                          scene_input input, uint32_t flags, uint32_t max_triangles);
/* As scene_gpu_draw, only the instances i with mask[i] == value. */
void scene_gpu_draw_where(const scene_gpu *sg, VkCommandBuffer cmd, int slot, VkPipelineLayout layout,
                          scene_input input, uint32_t flags, const uint8_t *mask, uint8_t value);
