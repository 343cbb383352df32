/* vergence — the frame graph.
 *
 * Passes (graphics, compute or transfer) declare every resource they touch
 * with a usage. rg_compile() is plain data, testable without a GPU:
 *
 *   1. validate  — usages fit the resource, attachments agree in size, nothing
 *                  is read before something wrote it;
 *   2. cull      — drop passes whose results nobody reads;
 *   3. order     — a stable topological order of the hazards between passes;
 *   4. lifetimes — first and last pass of every transient resource;
 *   5. alias     — transient resources with equal descriptions and disjoint
 *                  lifetimes share one physical image or buffer;
 *   6. barriers  — for every pass, the barriers and layout transitions its
 *                  uses need, derived from the previous use of the same
 *                  physical resource (pass code never writes a barrier).
 *
 * Semantics follow declaration order: a pass reads what the passes declared
 * before it wrote. Writes to imported resources and passes marked with
 * side_effects keep a pass alive. A transient resource that must outlive the
 * frame (read back, shown) is exported with rg_export().
 *
 * rg_realize()/rg_execute() (graph_vk.c) create the physical resources and
 * record the compiled graph into a command buffer, with a GPU timestamp pair
 * around every pass. The graph is compiled once per configuration and
 * executed every frame; physical resources keep their state across frames. */
#pragma once
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include <vulkan/vulkan.h>

#include "core/status.h"

#define RG_MAX_PASSES 64
#define RG_MAX_RESOURCES 128
#define RG_MAX_USES 1024

typedef struct rg_graph rg_graph;
typedef struct rg_res { uint32_t id; } rg_res;   /* 0 = none */
typedef struct rg_pass { uint32_t id; } rg_pass; /* 0 = none */

typedef enum rg_pass_type {
    RG_PASS_DEFAULT = 0, /* = graphics */
    RG_PASS_GRAPHICS,
    RG_PASS_COMPUTE,
    RG_PASS_TRANSFER,
} rg_pass_type;

typedef enum rg_usage {
    RG_USAGE_NONE = 0,
    RG_COLOR_WRITE,        /* colour attachment */
    RG_DEPTH_WRITE,        /* depth attachment, test and write */
    RG_DEPTH_READ,         /* depth attachment, test only */
    RG_SAMPLED,            /* sampled image (texture) */
    RG_STORAGE_READ,       /* storage image or buffer, read */
    RG_STORAGE_WRITE,      /* storage image or buffer, full overwrite */
    RG_STORAGE_READ_WRITE, /* storage image or buffer, read-modify-write */
    RG_UNIFORM,            /* uniform buffer */
    RG_VERTEX,             /* vertex buffer */
    RG_INDEX,              /* index buffer */
    RG_INDIRECT,           /* indirect draw or dispatch arguments */
    RG_INDIRECT_STORAGE,   /* a work list: indirect arguments in a storage buffer
                              the pass also reads and writes */
    RG_TRANSFER_SRC,
    RG_TRANSFER_DST,
    RG_HOST_READ,          /* final state only: the CPU reads it after the frame */
    RG_PRESENT,            /* final state only: presented to a swapchain */
    RG_USAGE_COUNT,
} rg_usage;

typedef struct rg_image_desc {
    const char *name;
    VkFormat format;
    uint32_t width, height;
    uint32_t layers;             /* 0 = 1 */
} rg_image_desc;

typedef struct rg_buffer_desc {
    const char *name;
    uint64_t size;
} rg_buffer_desc;

/* Imported resources live outside the graph (history, swapchain, readback).
 * initial: how the frame finds it (RG_USAGE_NONE: contents undefined);
 * final: the state the graph leaves it in (RG_USAGE_NONE: as the last pass left it). */
typedef struct rg_import_desc {
    rg_usage initial, final;
} rg_import_desc;

typedef struct rg_context rg_context;
typedef void (*rg_execute_fn)(const rg_context *ctx, void *user);

typedef struct rg_pass_desc {
    const char *name;
    rg_pass_type type;
    rg_execute_fn execute;
    void *user;
    bool side_effects;           /* never culled */
} rg_pass_desc;

/* A barrier derived by the compile step (Vulkan synchronization2 terms). */
typedef struct rg_barrier {
    rg_res res;
    uint32_t physical;
    VkPipelineStageFlags2 src_stage, dst_stage;
    VkAccessFlags2 src_access, dst_access;
    VkImageLayout old_layout, new_layout;
    bool is_image;
} rg_barrier;

/* ------------------------------------------------------------------------- */
/* Building                                                                  */
/* ------------------------------------------------------------------------- */

rg_graph *rg_create(void);
void rg_destroy(rg_graph *g);

rg_res rg_image(rg_graph *g, const rg_image_desc *desc);
rg_res rg_buffer(rg_graph *g, const rg_buffer_desc *desc);
rg_res rg_import_image(rg_graph *g, const rg_image_desc *desc, const rg_import_desc *imp);
rg_res rg_import_buffer(rg_graph *g, const rg_buffer_desc *desc, const rg_import_desc *imp);
/* Keeps a transient resource alive to the end of the frame and its writers unculled. */
void rg_export(rg_graph *g, rg_res res);

rg_pass rg_pass_add(rg_graph *g, const rg_pass_desc *desc);
void rg_use(rg_graph *g, rg_pass pass, rg_res res, rg_usage usage);
/* Colour/depth attachment use that starts with a clear. */
void rg_use_clear(rg_graph *g, rg_pass pass, rg_res res, rg_usage usage, VkClearValue clear);

/* ------------------------------------------------------------------------- */
/* Compiling (pure data)                                                     */
/* ------------------------------------------------------------------------- */

/* Logs one line naming the pass and resource at fault when the graph is invalid. */
vg_status rg_compile(rg_graph *g);

uint32_t rg_order_count(const rg_graph *g);           /* passes that survived culling */
rg_pass rg_order_pass(const rg_graph *g, uint32_t i);  /* i-th pass in execution order */
bool rg_pass_culled(const rg_graph *g, rg_pass pass);
const char *rg_pass_name(const rg_graph *g, rg_pass pass);
uint32_t rg_physical_count(const rg_graph *g);
uint32_t rg_res_physical(const rg_graph *g, rg_res res);  /* UINT32_MAX when unused */
const char *rg_res_name(const rg_graph *g, rg_res res);
/* Barriers recorded before the i-th ordered pass; i == rg_order_count() gives
 * the end-of-frame transitions of imported and exported resources. */
const rg_barrier *rg_barriers(const rg_graph *g, uint32_t i, uint32_t *count);

void rg_dump_text(const rg_graph *g, FILE *out);
vg_status rg_dump_dot(const rg_graph *g, const char *path);

/* ------------------------------------------------------------------------- */
/* Running (graph_vk.c)                                                      */
/* ------------------------------------------------------------------------- */

struct gpu;

/* Creates the physical transient resources and the timestamp queries. */
vg_status rg_realize(rg_graph *g, struct gpu *gpu);
/* Binds the external object of an imported resource (each frame if it changes). */
void rg_bind_image(rg_graph *g, rg_res res, VkImage image, VkImageView view);
void rg_bind_buffer(rg_graph *g, rg_res res, VkBuffer buffer);
/* Frames in flight that can each hold their own timestamps. */
#define RG_MAX_SLOTS 4

/* Records every ordered pass with its barriers into cmd; `slot` (below
 * RG_MAX_SLOTS) picks the timestamp queries of this frame in flight. */
void rg_execute(rg_graph *g, VkCommandBuffer cmd, uint32_t slot);
/* Records only the o-th ordered pass with the barriers before it (and the
 * final barriers after the last): a profiler submits each pass on its own
 * and times it by the wall clock (no timestamps). */
void rg_execute_pass(rg_graph *g, VkCommandBuffer cmd, uint32_t o);
/* Records the ordered passes [first, end) into a command buffer a host
 * records too (the SDK): from the first pass on, a full memory dependency on
 * what the host recorded before (the graph cannot know which of its
 * imported images the host wrote, nor at which stage), then each pass as
 * rg_execute_pass does. */
void rg_execute_range(rg_graph *g, VkCommandBuffer cmd, uint32_t first, uint32_t end);
/* After that slot's command buffer completed: GPU ms of each ordered pass
 * (NaN when the device has no timestamps). Returns the number of passes. */
uint32_t rg_timings(rg_graph *g, uint32_t slot, double *ms, uint32_t cap);

/* What a pass's execute callback sees. */
VkCommandBuffer rg_ctx_cmd(const rg_context *ctx);
VkImage rg_ctx_image(const rg_context *ctx, rg_res res);
VkImageView rg_ctx_view(const rg_context *ctx, rg_res res);
VkBuffer rg_ctx_buffer(const rg_context *ctx, rg_res res);
VkImageLayout rg_ctx_layout(const rg_context *ctx, rg_res res); /* layout during this pass */
/* A descriptor of the image during this pass: its view and layout (a
 * storage image), and with a sampler (a combined image sampler). */
VkDescriptorImageInfo rg_ctx_image_info(const rg_context *ctx, rg_res res);
VkDescriptorImageInfo rg_ctx_sampled_info(const rg_context *ctx, rg_res res, VkSampler sampler);
VkExtent2D rg_ctx_extent(const rg_context *ctx);              /* render area of a graphics pass */
struct gpu *rg_ctx_gpu(const rg_context *ctx);
