/* vergence — frame graph internals shared by the compile step (graph.c:
 * pure data), the dump (graph_dump.c) and the Vulkan executor (graph_vk.c),
 * both of which use the compile step's data and never the other way round. */
#pragma once
#include "gpu/gpu.h"
#include "graph.h"

#define RG_NAME_MAX 48
#define RG_NONE UINT32_MAX

/* What one usage means to Vulkan. */
typedef struct rg_state {
    VkPipelineStageFlags2 stage;
    VkAccessFlags2 access;
    VkImageLayout layout;
    bool reads, writes;
} rg_state;

typedef struct rg_resource {
    char name[RG_NAME_MAX];
    bool is_image, imported, exported;
    VkFormat format;
    uint32_t width, height, layers;
    uint64_t size;
    rg_import_desc imp;
    /* compile results */
    uint32_t physical;           /* RG_NONE when culled away */
    uint32_t first, last;        /* order indices of first and last use */
} rg_resource;

typedef struct rg_use_info {
    uint32_t pass, res;
    rg_usage usage;
    bool clear;
    VkClearValue clear_value;
    /* compile results */
    bool load;                   /* attachment keeps earlier contents */
    VkImageLayout layout;
} rg_use_info;

typedef struct rg_pass_info {
    char name[RG_NAME_MAX];
    rg_pass_type type;
    rg_execute_fn execute;
    void *user;
    bool side_effects;
    bool culled;
    uint32_t order;              /* RG_NONE when culled */
} rg_pass_info;

/* Per-physical-resource synchronisation state while barriers are derived. */
typedef struct rg_track {
    VkImageLayout layout;
    VkPipelineStageFlags2 write_stage, read_stage, visible_stage;
    VkAccessFlags2 write_access, visible_access;
    uint32_t owner;              /* logical resource currently held, RG_NONE at start */
} rg_track;

typedef struct rg_physical {
    bool is_image, imported;
    VkFormat format;
    uint32_t width, height, layers;
    uint64_t size;
    VkImageUsageFlags image_usage;
    VkBufferUsageFlags buffer_usage;
    uint32_t last;               /* last order index using it (aliasing) */
    uint32_t res;                /* a logical resource it holds (for names) */
    /* runtime */
    gpu_image image;
    gpu_buffer buffer;
    VkImage ext_image;
    VkImageView ext_view;
    VkBuffer ext_buffer;
} rg_physical;

struct rg_graph {
    rg_resource res[RG_MAX_RESOURCES];
    rg_pass_info pass[RG_MAX_PASSES];
    rg_use_info use[RG_MAX_USES];
    uint32_t res_count, pass_count, use_count;
    bool build_error;            /* a build call failed (already logged) */

    bool compiled;
    uint32_t order[RG_MAX_PASSES];
    uint32_t order_count;
    rg_physical phys[RG_MAX_RESOURCES];
    uint32_t phys_count;
    rg_barrier *barriers;        /* all barriers, grouped by order slot */
    uint32_t barrier_count;
    uint32_t barrier_first[RG_MAX_PASSES + 2]; /* slot i: [first[i], first[i+1]) */

    /* runtime (graph_vk.c) */
    struct gpu *gpu;
    VkQueryPool queries[RG_MAX_SLOTS];
};

struct rg_context {
    rg_graph *graph;
    uint32_t pass;
    VkCommandBuffer cmd;
    VkExtent2D extent;
};

rg_state rg_usage_state(rg_usage usage, rg_pass_type type, bool is_image, VkFormat format);
bool rg_format_is_depth(VkFormat f);
const char *rg_usage_name(rg_usage u);
const char *rg_layout_name(VkImageLayout l);
const char *rg_format_name(VkFormat f);
/* Frees the physical resources and queries (graph_vk.c; rg_destroy there). */
void rg_unrealize(rg_graph *g);
