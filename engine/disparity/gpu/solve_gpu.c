/* vergence — the keyframe window and its solve on the GPU. */
#include "solve_gpu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "gpu/pipeline.h"
#include "disparity/mid_shared.h"

#include "mid_control_comp.h"
#include "mid_precond_comp.h"
#include "mid_publish_comp.h"
#include "mid_scan_comp.h"
#include "mid_sum_comp.h"
#include "mid_terms_comp.h"
#include "mid_vec_comp.h"
#include "mid_window_comp.h"

/* ------------------------------------------------------------------------- */
/* Steps and their graphs                                                    */
/* ------------------------------------------------------------------------- */

enum { K_WINDOW, K_SCAN, K_TERMS, K_VEC, K_PRECOND, K_CONTROL, K_PUBLISH, K_SUM, K_COUNT };

/* Dispatch size of a step: the element grid, chunks of sums or of the CSR
 * scan, one workgroup, or the chain heads (gated steps only). */
enum { SIZE_N = 0, SIZE_SUM, SIZE_SCAN, SIZE_ONE, SIZE_HEADS };
_Static_assert(MID_B_COUNT <= 32, "the arena's bindings are one push-descriptor set: at most 32 everywhere");
/* Gates: which MID_ARGS_* sizes an indirect dispatch takes (0 = direct). */
enum { GATE_NONE = 0, GATE_ACTIVE, GATE_CG, GATE_LINE, GATE_COMMIT };
/* Steps of the line preconditioner or of Jacobi CG only. */
enum { ONLY_ALL = 0, ONLY_LINES, ONLY_JACOBI };

typedef struct step_def {
    const char *name;
    uint8_t kernel, op, gate, size, only;
} step_def;

#define STEP(name, k, op, gate, size, only) {name, k, op, gate, size, only}
#define CONTROL(name, op) STEP(name, K_CONTROL, op, GATE_NONE, SIZE_ONE, ONLY_ALL)
#define SUM_COST(gate) STEP("sum.cost", K_SUM, MID_OP_SUM_COST, gate, SIZE_SUM, ONLY_ALL)
#define SUM_VEC(gate, only) STEP("sum.vec", K_SUM, MID_OP_SUM_VEC, gate, SIZE_SUM, only)

/* The window (mid_window_build). */
static const step_def k_build[] = {
    CONTROL("control.reset", MID_OP_C_RESET),
    STEP("window.gather", K_WINDOW, MID_OP_GATHER, GATE_NONE, SIZE_N, ONLY_ALL),
    CONTROL("control.range", MID_OP_C_RANGE),
    STEP("window.links", K_WINDOW, MID_OP_LINKS, GATE_NONE, SIZE_N, ONLY_ALL),
    STEP("scan.chunks", K_SCAN, MID_OP_SCAN_BLOCKS, GATE_NONE, SIZE_SCAN, ONLY_ALL),
    STEP("scan.top", K_SCAN, MID_OP_SCAN_TOP, GATE_NONE, SIZE_ONE, ONLY_ALL),
    STEP("scan.add", K_SCAN, MID_OP_SCAN_ADD, GATE_NONE, SIZE_SCAN, ONLY_ALL),
    STEP("window.fill", K_WINDOW, MID_OP_FILL, GATE_NONE, SIZE_N, ONLY_ALL),
    STEP("window.sort", K_WINDOW, MID_OP_SORT, GATE_NONE, SIZE_N, ONLY_ALL),
    STEP("window.targets", K_WINDOW, MID_OP_TARGETS, GATE_NONE, SIZE_N, ONLY_ALL),
    STEP("window.chains", K_WINDOW, MID_OP_CHAINS, GATE_NONE, SIZE_N, ONLY_ALL),
    STEP("window.heads", K_WINDOW, MID_OP_HEADS, GATE_NONE, SIZE_N, ONLY_LINES),
};
/* f0, projected, and its linearisation (mid_solver_run's start). */
static const step_def k_init[] = {
    STEP("vec.init", K_VEC, MID_OP_INIT, GATE_NONE, SIZE_N, ONLY_ALL),
    STEP("terms.linearize", K_TERMS, MID_OP_LIN_F, GATE_NONE, SIZE_N, ONLY_ALL),
    SUM_COST(GATE_NONE),
    CONTROL("control.cost", MID_OP_C_INIT_COST),
};
/* A Gauss-Newton iteration up to its first CG step (gauss_newton_step). */
static const step_def k_prologue[] = {
    CONTROL("control.iteration", MID_OP_C_ITER_BEGIN),
    STEP("terms.gradient", K_TERMS, MID_OP_GATHER_GRAD, GATE_ACTIVE, SIZE_N, ONLY_ALL),
    STEP("terms.diagonal", K_TERMS, MID_OP_DIAGONAL, GATE_ACTIVE, SIZE_N, ONLY_ALL),
    STEP("vec.cg_start", K_VEC, MID_OP_CG_START, GATE_ACTIVE, SIZE_N, ONLY_ALL),
    SUM_VEC(GATE_ACTIVE, ONLY_ALL),
    CONTROL("control.pg2", MID_OP_C_PG2),
    STEP("precond.assemble", K_PRECOND, MID_OP_ASSEMBLE, GATE_ACTIVE, SIZE_N, ONLY_LINES),
    STEP("precond.factor", K_PRECOND, MID_OP_FACTOR, GATE_ACTIVE, SIZE_HEADS, ONLY_LINES),
    STEP("precond.apply", K_PRECOND, MID_OP_APPLY, GATE_ACTIVE, SIZE_HEADS, ONLY_LINES),
    STEP("vec.zp_init", K_VEC, MID_OP_ZP_INIT, GATE_ACTIVE, SIZE_N, ONLY_ALL),
    SUM_VEC(GATE_ACTIVE, ONLY_ALL),
    CONTROL("control.rz0", MID_OP_C_RZ0),
};
/* One preconditioned CG step. With the line preconditioner, its walk along
 * the chains also makes the step's updates and r.z terms (APPLY_CG: three
 * element-wise dispatches in one, the same bits). */
static const step_def k_cg[] = {
    STEP("terms.direction", K_TERMS, MID_OP_DIRECTION, GATE_CG, SIZE_N, ONLY_ALL),
    STEP("terms.product", K_TERMS, MID_OP_GATHER_HESS, GATE_CG, SIZE_N, ONLY_ALL),
    SUM_VEC(GATE_CG, ONLY_ALL),
    CONTROL("control.php", MID_OP_C_PHP),
    STEP("vec.cg_update", K_VEC, MID_OP_CG_UPDATE, GATE_CG, SIZE_N, ONLY_JACOBI),
    STEP("precond.apply_cg", K_PRECOND, MID_OP_APPLY_CG, GATE_CG, SIZE_HEADS, ONLY_LINES),
    SUM_VEC(GATE_CG, ONLY_ALL),
    CONTROL("control.rz", MID_OP_C_RZNEW),
    STEP("vec.p_update", K_VEC, MID_OP_P_UPDATE, GATE_CG, SIZE_N, ONLY_ALL),
};
/* One trial of the backtracking line search. */
static const step_def k_trial[] = {
    STEP("vec.trial", K_VEC, MID_OP_TRIAL, GATE_LINE, SIZE_N, ONLY_ALL),
    SUM_VEC(GATE_LINE, ONLY_ALL),
    STEP("terms.linearize", K_TERMS, MID_OP_LIN_FTRY, GATE_LINE, SIZE_N, ONLY_ALL),
    SUM_COST(GATE_LINE),
    CONTROL("control.armijo", MID_OP_C_TRIAL),
};
static const step_def k_end[] = {
    STEP("vec.commit", K_VEC, MID_OP_COMMIT, GATE_COMMIT, SIZE_N, ONLY_ALL),
    CONTROL("control.end", MID_OP_C_ITER_END),
};
/* The paper's step (Sec. 4.5) with the Jacobi scaling of DESIGN.md. */
static const step_def k_descent[] = {
    STEP("terms.gradient", K_TERMS, MID_OP_GATHER_GRAD, GATE_ACTIVE, SIZE_N, ONLY_ALL),
    STEP("terms.diagonal", K_TERMS, MID_OP_DIAGONAL, GATE_ACTIVE, SIZE_N, ONLY_ALL),
    STEP("vec.descent", K_VEC, MID_OP_DESCENT, GATE_ACTIVE, SIZE_N, ONLY_ALL),
    STEP("terms.linearize", K_TERMS, MID_OP_LIN_FTRY, GATE_ACTIVE, SIZE_N, ONLY_ALL),
    SUM_COST(GATE_ACTIVE),
    CONTROL("control.descent", MID_OP_C_DESCENT),
    STEP("vec.commit", K_VEC, MID_OP_COMMIT, GATE_COMMIT, SIZE_N, ONLY_ALL),
};
static const step_def k_publish[] = {
    STEP("publish.gate", K_PUBLISH, MID_OP_GATE, GATE_NONE, SIZE_ONE, ONLY_ALL),
    STEP("publish", K_PUBLISH, MID_OP_PUBLISH, GATE_NONE, SIZE_N, ONLY_ALL),
};

enum { G_BUILD, G_INIT, G_PROLOGUE, G_CG, G_TRIAL, G_END, G_DESCENT, G_PUBLISH, G_COUNT };

static const struct {
    const char *name;
    const step_def *steps;
    int count;
    double cost; /* element traversals, for spreading a program over frames */
} k_graphs[G_COUNT] = {
#define G(name, arr, cost) {name, arr, (int)(sizeof arr / sizeof arr[0]), cost}
    G("mid.window.build", k_build, 14.0),
    G("mid.solve.init", k_init, 3.0),
    G("mid.solve.prologue", k_prologue, 9.0),
    G("mid.solve.cg", k_cg, 8.0),
    G("mid.solve.trial", k_trial, 3.0),
    G("mid.solve.end", k_end, 1.0),
    G("mid.solve.descent", k_descent, 7.0),
    G("mid.solve.publish", k_publish, 1.0),
#undef G
};

/* ------------------------------------------------------------------------- */
/* Module                                                                    */
/* ------------------------------------------------------------------------- */

typedef struct step_ref {
    struct solve_gpu *m;
    const step_def *def;
} step_ref;

typedef struct item {
    uint8_t graph, trial;
} item;

/* A solve's program: its constants and items. */
typedef struct program {
    mid_push push;
    bool gather, jacobi;
    float lambda;
    item *items;
    int count, cap;
} program;

#define MAX_STEPS 64

struct solve_gpu {
    gpu *gpu;
    solve_gpu_desc d;
    uint32_t cap, adj_cap, ns;
    gpu_buffer arena, args, own_store, own_published;
    VkBuffer store, published;
    VkDeviceSize offset[MID_B_COUNT], bytes[MID_B_COUNT];
    VkDescriptorBufferInfo infos[MID_B_COUNT];
    VkWriteDescriptorSet writes[MID_B_COUNT];
    VkDescriptorSetLayout set_layout, view_layout;
    VkDescriptorPool view_pool;
    VkDescriptorSet view_set;
    VkBufferView views[2];              /* the arena as R32_UINT and as R32G32B32A32_UINT texels */
    VkPipelineLayout layout;
    VkPipeline pipe[K_COUNT][MID_OP_COUNT]; /* one per kernel and operation (specialisation) */
    rg_graph *graph[G_COUNT];
    step_ref refs[G_COUNT][MAX_STEPS];

    /* The current program (the last solve_gpu_begin) and the one before it,
     * whose unrecorded items a frame may still have to record. */
    program prog[2];
    int cur;
    const program *rec;  /* the one being recorded */
    float trial_t;
};

static void step_execute(const rg_context *ctx, void *user)
{
    const step_ref *r = user;
    solve_gpu *m = r->m;
    const program *pr = m->rec;
    const step_def *s = r->def;
    if ((s->only == ONLY_LINES && pr->jacobi) || (s->only == ONLY_JACOBI && !pr->jacobi))
        return;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    mid_push p = pr->push;
    p.op = s->op == MID_OP_GATHER && !pr->gather ? MID_OP_PREPARE : s->op;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m->pipe[s->kernel][s->kernel == K_CONTROL ? 0 : p.op]);
    m->gpu->cmd_push_descriptor_set(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m->layout, 0, MID_B_COUNT, m->writes);
    if (s->op == MID_OP_TRIAL)
        p.scalar = m->trial_t;
    else if (s->op == MID_OP_DESCENT)
        p.scalar = pr->lambda;
    vkCmdPushConstants(cmd, m->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof p, &p);
    if (s->gate != GATE_NONE) {
        uint32_t slot = MID_ARGS_SIZES * (uint32_t)(s->gate - 1) + (s->size == SIZE_SUM ? 1 : s->size == SIZE_HEADS ? 2 : 0);
        vkCmdDispatchIndirect(cmd, m->args.buffer, (VkDeviceSize)slot * 3 * sizeof(uint32_t));
    } else if (s->size == SIZE_ONE) {
        vkCmdDispatch(cmd, 1, 1, 1);
    } else if (s->size == SIZE_SCAN) {
        vkCmdDispatch(cmd, ((p.n + 1 + MID_SCAN_BLOCK - 1) / MID_SCAN_BLOCK + 63) / 64, 2, 1);
    } else if (s->size == SIZE_SUM) {
        vkCmdDispatch(cmd, (p.blocks + 63) / 64, 1, 1);
    } else {
        vkCmdDispatch(cmd, (p.nx + MID_TILE - 1) / MID_TILE, (p.ny + MID_TILE - 1) / MID_TILE, p.nt);
    }
}

/* One pass per step: the graph derives the barrier between each pair. */
static vg_status graph_build(solve_gpu *m, int gi)
{
    rg_graph *g = m->graph[gi] = rg_create();
    if (!g)
        return VG_ERR_NOMEM;
    rg_import_desc rw = {.initial = RG_STORAGE_READ_WRITE, .final = RG_STORAGE_READ_WRITE};
    rg_import_desc ind = {.initial = RG_INDIRECT, .final = RG_INDIRECT};
    rg_res arena = rg_import_buffer(g, &(rg_buffer_desc){"mid.arena", m->arena.size}, &rw);
    rg_res args = rg_import_buffer(g, &(rg_buffer_desc){"mid.args", m->args.size}, &ind);
    rg_res store = {0}, published = {0};
    for (int i = 0; i < k_graphs[gi].count; i++) {
        const step_def *s = &k_graphs[gi].steps[i];
        m->refs[gi][i] = (step_ref){m, s};
        rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = s->name, .type = RG_PASS_COMPUTE,
                                                   .execute = step_execute, .user = &m->refs[gi][i]});
        rg_use(g, p, arena, RG_STORAGE_READ_WRITE);
        if (s->kernel == K_CONTROL)
            rg_use(g, p, args, RG_STORAGE_READ_WRITE);
        else if (s->gate != GATE_NONE)
            rg_use(g, p, args, RG_INDIRECT);
        /* Every pass whose kernel reads the store (mid_window) or writes the
         * published ratios declares it: synchronization validation looks at
         * what a pipeline could touch, not at what this dispatch does. */
        if (s->kernel == K_WINDOW) {
            if (!store.id)
                store = rg_import_buffer(g, &(rg_buffer_desc){"mid.store", m->d.store_size}, &rw);
            rg_use(g, p, store, RG_STORAGE_READ);
        }
        if (s->kernel == K_PUBLISH) {
            if (!published.id)
                published = rg_import_buffer(g, &(rg_buffer_desc){"mid.published", m->d.published_size}, &rw);
            rg_use(g, p, published, RG_STORAGE_READ_WRITE);
        }
    }
    vg_status st = rg_compile(g);
    if (st == VG_OK)
        st = rg_realize(g, m->gpu);
    if (st != VG_OK)
        return st;
    rg_bind_buffer(g, arena, m->arena.buffer);
    rg_bind_buffer(g, args, m->args.buffer);
    if (store.id)
        rg_bind_buffer(g, store, m->store);
    if (published.id)
        rg_bind_buffer(g, published, m->published);
    return VG_OK;
}

/* Byte sizes of the arena's arrays (mid_shared.h MID_B_*). */
static void arena_layout(solve_gpu *m)
{
    VkDeviceSize n = m->cap, f = sizeof(float), blocks = (n + MID_SUM_CHUNK - 1) / MID_SUM_CHUNK;
    VkDeviceSize sz[MID_B_COUNT] = {
        [MID_B_STATE] = sizeof(mid_solve_state),
        [MID_B_PARTIAL] = blocks * MID_PARTIAL_FLOATS * f,
        [MID_B_FIELD] = 4 * n * f, /* g, h, depth, instance id */
        [MID_B_FLOW] = 4 * n * f,
        [MID_B_LINK] = 2 * n * sizeof(mid_link),
        [MID_B_ADJ_OFF] = 2 * (n + 1) * f,
        [MID_B_ADJ] = 2 * (VkDeviceSize)m->adj_cap * sizeof(mid_adj_entry),
        [MID_B_CURSOR] = 2 * n * f,
        [MID_B_EDGE] = 2 * n * f,
        [MID_B_TARGET] = 2 * n * f,
        [MID_B_INVDT] = 2 * MID_MAX_KEYFRAMES * f,
        [MID_B_CHAIN] = 2 * n * f,
        [MID_B_HEAVY] = 2 * n * f,
        [MID_B_SCAN] = 2 * ((n + 1) / MID_SCAN_BLOCK + 1) * f,
        [MID_B_L] = 3 * n * f,
        [MID_B_LIN] = MID_LIN_FIELDS * n * f,
        [MID_B_DOT] = MID_DOT_COLUMNS * n * f,
        [MID_B_HEADS] = n * sizeof(uint32_t),
    };
    int singles[] = {MID_B_F, MID_B_FTRY, MID_B_GRAD, MID_B_DIAG, MID_B_S, MID_B_R, MID_B_Z,
                     MID_B_P, MID_B_HP, MID_B_FREE, MID_B_FPREV};
    for (size_t i = 0; i < sizeof singles / sizeof singles[0]; i++)
        sz[singles[i]] = n * f;
    VkDeviceSize at = 0;
    for (int b = 0; b < MID_B_COUNT; b++) {
        if (b == MID_B_ARGS || b == MID_B_STORE || b == MID_B_PUBLISHED)
            continue;
        m->offset[b] = at;
        m->bytes[b] = sz[b];
        at += (sz[b] + 255) & ~(VkDeviceSize)255;
    }
    m->arena.size = at;
}

static void descriptors_init(solve_gpu *m)
{
    for (int b = 0; b < MID_B_COUNT; b++) {
        VkDescriptorBufferInfo info = {m->arena.buffer, m->offset[b], m->bytes[b]};
        if (b == MID_B_ARGS)
            info = (VkDescriptorBufferInfo){m->args.buffer, 0, VK_WHOLE_SIZE};
        else if (b == MID_B_STORE)
            info = (VkDescriptorBufferInfo){m->store, 0, VK_WHOLE_SIZE};
        else if (b == MID_B_PUBLISHED)
            info = (VkDescriptorBufferInfo){m->published, 0, VK_WHOLE_SIZE};
        m->infos[b] = info;
        m->writes[b] = (VkWriteDescriptorSet){
            .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstBinding = (uint32_t)b, .descriptorCount = 1,
            .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &m->infos[b]};
    }
}

/* The arena's texel views (set 1, shaders/mid_arena.glsl): the kernels read
 * through them what earlier dispatches wrote; llvmpipe fetches a texel as
 * one gather, a storage buffer value in a loop over the lanes. */
static vg_status views_create(solve_gpu *m)
{
    gpu *g = m->gpu;
    uint32_t limit = g->props.limits.maxTexelBufferElements;
    if (m->arena.size / 4 > limit) {
        vg_error("GPU MID window: %dx%d x %d keyframes need a %.0f MB arena; this device reads at most %.0f MB "
                 "through a texel view (fewer keyframes: a shorter window, or a coarser grid)",
                 m->d.nx, m->d.ny, m->d.max_keyframes, (double)m->arena.size / 1048576.0, 4.0 * limit / 1048576.0);
        return VG_ERR_DEVICE;
    }
    VkDescriptorSetLayoutBinding bindings[2] = {
        {0, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {1, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, NULL}};
    VK_TRY(vkCreateDescriptorSetLayout(g->device, &(VkDescriptorSetLayoutCreateInfo){
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO, .bindingCount = 2, .pBindings = bindings},
        g->alloc, &m->view_layout));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, m->view_layout, "mid arena views layout");
    static const VkFormat formats[2] = {VK_FORMAT_R32_UINT, VK_FORMAT_R32G32B32A32_UINT};
    for (int v = 0; v < 2; v++) {
        vg_status st = gpu_buffer_view_create(g, m->arena.buffer, formats[v], m->arena.size,
                                              v ? "mid arena (uvec4)" : "mid arena (uint)", &m->views[v]);
        if (st != VG_OK)
            return st;
    }
    VK_TRY(vkCreateDescriptorPool(g->device, &(VkDescriptorPoolCreateInfo){
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO, .maxSets = 1, .poolSizeCount = 1,
        .pPoolSizes = &(VkDescriptorPoolSize){VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 2}}, g->alloc, &m->view_pool));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_POOL, m->view_pool, "mid arena views pool");
    VK_TRY(vkAllocateDescriptorSets(g->device, &(VkDescriptorSetAllocateInfo){
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO, .descriptorPool = m->view_pool,
        .descriptorSetCount = 1, .pSetLayouts = &m->view_layout}, &m->view_set));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_SET, m->view_set, "mid arena views");
    VkWriteDescriptorSet writes[2];
    for (uint32_t v = 0; v < 2; v++)
        writes[v] = (VkWriteDescriptorSet){.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = m->view_set,
                                           .dstBinding = v, .descriptorCount = 1,
                                           .descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
                                           .pTexelBufferView = &m->views[v]};
    vkUpdateDescriptorSets(g->device, 2, writes, 0, NULL);
    return VG_OK;
}

static vg_status pipelines_create(solve_gpu *m)
{
    /* Every binding a storage buffer (more than gpu_push_layout_create takes). */
    gpu *g = m->gpu;
    VkDescriptorSetLayoutBinding bindings[MID_B_COUNT];
    for (uint32_t b = 0; b < MID_B_COUNT; b++)
        bindings[b] = (VkDescriptorSetLayoutBinding){b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
                                                     VK_SHADER_STAGE_COMPUTE_BIT, NULL};
    VK_TRY(vkCreateDescriptorSetLayout(g->device, &(VkDescriptorSetLayoutCreateInfo){
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR,
        .bindingCount = MID_B_COUNT, .pBindings = bindings}, g->alloc, &m->set_layout));
    GPU_NAME(g, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, m->set_layout, "mid set layout");
    vg_status st = views_create(m);
    if (st != VG_OK)
        return st;
    VkDescriptorSetLayout sets[2] = {m->set_layout, m->view_layout};
    VK_TRY(vkCreatePipelineLayout(g->device, &(VkPipelineLayoutCreateInfo){
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO, .setLayoutCount = 2, .pSetLayouts = sets,
        .pushConstantRangeCount = 1,
        .pPushConstantRanges = &(VkPushConstantRange){VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(mid_push)}},
        g->alloc, &m->layout));
    GPU_NAME(g, VK_OBJECT_TYPE_PIPELINE_LAYOUT, m->layout, "mid layout");
    static const struct {
        const uint32_t *code;
        size_t size;
        const char *name;
    } src[K_COUNT] = {
        [K_WINDOW] = {spv_mid_window_comp, sizeof spv_mid_window_comp, "mid.window"},
        [K_SCAN] = {spv_mid_scan_comp, sizeof spv_mid_scan_comp, "mid.scan"},
        [K_TERMS] = {spv_mid_terms_comp, sizeof spv_mid_terms_comp, "mid.terms"},
        [K_VEC] = {spv_mid_vec_comp, sizeof spv_mid_vec_comp, "mid.vec"},
        [K_PRECOND] = {spv_mid_precond_comp, sizeof spv_mid_precond_comp, "mid.precond"},
        [K_CONTROL] = {spv_mid_control_comp, sizeof spv_mid_control_comp, "mid.control"},
        [K_PUBLISH] = {spv_mid_publish_comp, sizeof spv_mid_publish_comp, "mid.publish"},
        [K_SUM] = {spv_mid_sum_comp, sizeof spv_mid_sum_comp, "mid.sum"},
    };
    VkShaderModule mod[K_COUNT] = {0};
    for (int k = 0; k < K_COUNT && st == VG_OK; k++)
        st = gpu_shader_create(g, src[k].code, src[k].size, src[k].name, &mod[k]);
    /* Every (kernel, operation) the steps use; the control kernel branches
     * at run time (one workgroup: cheap), the element kernels get their
     * operation as a specialisation constant (a CPU rasteriser would run
     * every branch of a switch under masks), and every array's first word
     * in the arena (constant 1 + MID_B_*: the texel views' W_*). */
    for (int gi = 0; gi < G_COUNT && st == VG_OK; gi++)
        for (int i = 0; i < k_graphs[gi].count && st == VG_OK; i++) {
            const step_def *sd = &k_graphs[gi].steps[i];
            uint32_t ops[2] = {sd->kernel == K_CONTROL ? 0u : sd->op, MID_OP_PREPARE};
            int variants = sd->op == MID_OP_GATHER ? 2 : 1;
            for (int v = 0; v < variants && st == VG_OK; v++) {
                VkPipeline *out = &m->pipe[sd->kernel][ops[v]];
                if (*out)
                    continue;
                VkSpecializationMapEntry entry[1 + MID_B_COUNT];
                uint32_t data[1 + MID_B_COUNT];
                data[0] = ops[v];
                for (uint32_t b = 0; b <= MID_B_COUNT; b++) {
                    entry[b] = (VkSpecializationMapEntry){b, b * 4, sizeof(uint32_t)};
                    if (b)
                        data[b] = (uint32_t)(m->offset[b - 1] / 4);
                }
                char name[48];
                snprintf(name, sizeof name, "%s op %u", src[sd->kernel].name, ops[v]);
                VkSpecializationInfo spec = {1 + MID_B_COUNT, entry, sizeof data, data};
                st = gpu_compute_pipeline_create(g, m->layout, mod[sd->kernel], &spec, name, out);
            }
        }
    for (int k = 0; k < K_COUNT; k++)
        if (mod[k])
            vkDestroyShaderModule(g->device, mod[k], g->alloc);
    return st;
}

vg_status solve_gpu_create(gpu *g, const solve_gpu_desc *desc, solve_gpu **out)
{
    *out = NULL;
    if (desc->nx < 2 || desc->ny < 2 || desc->max_keyframes < 1 || desc->max_keyframes > (int)MID_MAX_KEYFRAMES) {
        vg_error("GPU MID window: %dx%d x %d keyframes is out of range (at least 2x2, 1..%u keyframes)",
                 desc->nx, desc->ny, desc->max_keyframes, MID_MAX_KEYFRAMES);
        return VG_ERR_ARG;
    }
    solve_gpu *m = calloc(1, sizeof *m);
    if (!m)
        return VG_ERR_NOMEM;
    m->gpu = g;
    m->d = *desc;
    m->ns = (uint32_t)(desc->nx * desc->ny);
    m->cap = m->ns * (uint32_t)desc->max_keyframes;
    m->adj_cap = 4 * m->cap; /* every source has at most four taps */
    arena_layout(m);
    VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    vg_status st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "mid arena", .size = m->arena.size,
                                                           .usage = usage | VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT,
                                                           .host_visible = desc->host_visible},
                                     &m->arena);
    if (st == VG_OK)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "mid dispatch sizes",
                                                     .size = MID_ARGS_COUNT * 3 * sizeof(uint32_t),
                                                     .usage = usage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT},
                               &m->args);
    /* Without a frame (tests), small buffers of its own stand in. */
    if (st == VG_OK && !desc->store)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "mid store (none)", .size = 256, .usage = usage},
                               &m->own_store);
    if (st == VG_OK && !desc->published)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "mid published (none)", .size = 256, .usage = usage},
                               &m->own_published);
    m->store = desc->store ? desc->store : m->own_store.buffer;
    m->published = desc->published ? desc->published : m->own_published.buffer;
    if (!desc->store)
        m->d.store_size = 256;
    if (!desc->published)
        m->d.published_size = 256;
    if (st == VG_OK) {
        descriptors_init(m);
        st = pipelines_create(m);
    }
    for (int gi = 0; gi < G_COUNT && st == VG_OK; gi++)
        st = graph_build(m, gi);
    if (st != VG_OK) {
        solve_gpu_destroy(m);
        return st;
    }
    *out = m;
    return VG_OK;
}

void solve_gpu_destroy(solve_gpu *m)
{
    if (!m)
        return;
    VkDevice dev = m->gpu->device;
    for (int gi = 0; gi < G_COUNT; gi++)
        rg_destroy(m->graph[gi]);
    for (int k = 0; k < K_COUNT; k++)
        for (int op = 0; op < (int)MID_OP_COUNT; op++)
            if (m->pipe[k][op])
                vkDestroyPipeline(dev, m->pipe[k][op], m->gpu->alloc);
    if (m->layout)
        vkDestroyPipelineLayout(dev, m->layout, m->gpu->alloc);
    if (m->set_layout)
        vkDestroyDescriptorSetLayout(dev, m->set_layout, m->gpu->alloc);
    if (m->view_layout)
        vkDestroyDescriptorSetLayout(dev, m->view_layout, m->gpu->alloc);
    if (m->view_pool)
        vkDestroyDescriptorPool(dev, m->view_pool, m->gpu->alloc);
    for (int v = 0; v < 2; v++)
        if (m->views[v])
            vkDestroyBufferView(dev, m->views[v], m->gpu->alloc);
    gpu_buffer_destroy(m->gpu, &m->arena);
    gpu_buffer_destroy(m->gpu, &m->args);
    gpu_buffer_destroy(m->gpu, &m->own_store);
    gpu_buffer_destroy(m->gpu, &m->own_published);
    free(m->prog[0].items);
    free(m->prog[1].items);
    free(m);
}

/* ------------------------------------------------------------------------- */
/* Programs                                                                  */
/* ------------------------------------------------------------------------- */

static void add_item(program *pr, int graph, int trial)
{
    if (pr->count == pr->cap) {
        int cap = pr->cap ? 2 * pr->cap : 256;
        item *p = realloc(pr->items, (size_t)cap * sizeof *p);
        if (!p)
            return; /* the program ends early (without its publish step) */
        pr->items = p;
        pr->cap = cap;
    }
    pr->items[pr->count++] = (item){(uint8_t)graph, (uint8_t)trial};
}

void solve_gpu_begin(solve_gpu *m, const solve_gpu_params *s)
{
    uint32_t nt = (uint32_t)s->keyframes, n = m->ns * nt;
    if (n > m->cap) {
        vg_error("GPU MID window: %u keyframes exceed the capacity (%d)", nt, m->d.max_keyframes);
        nt = (uint32_t)m->d.max_keyframes;
        n = m->cap;
    }
    mid_weights w = mid_weights_resolve(s->weights);
    mid_solver_kind kind = s->solver == MID_SOLVER_DEFAULT ? MID_SOLVER_GAUSS_NEWTON : s->solver;
    float occ = s->occlusion_tolerance > 0 ? s->occlusion_tolerance : MID_OCCLUSION_TOLERANCE;
    m->cur ^= 1; /* the current program becomes the previous one */
    program *pr = &m->prog[m->cur];
    pr->push = (mid_push){
        .nx = (uint32_t)m->d.nx, .ny = (uint32_t)m->d.ny, .nt = nt, .ns = m->ns,
        .n = n, .cap = m->cap, .blocks = (n + MID_SUM_CHUNK - 1) / MID_SUM_CHUNK,
        .w_data = w.data, .w_spatial = w.spatial, .w_temporal = w.temporal, .w_accel = w.accel,
        .grad_scale = 2.0f / (float)n, .log_tol = logf(1.0f + occ),
        .flow_tol = s->flow_tolerance > 0 ? s->flow_tolerance : MID_FLOW_TOLERANCE,
        .range_lo = s->range_lo, .range_hi = s->range_hi,
        .dt = s->keyframe_seconds > 0 ? s->keyframe_seconds : (float)MID_KEYFRAME_SECONDS,
        .nt_prev = (uint32_t)(s->prev_keyframes > 0 ? s->prev_keyframes : 0),
        .range_hull = s->range_hull, .jacobi = s->precond == MID_PRECOND_JACOBI,
        .store_first = s->store_first, .store_cap = s->store_cap ? s->store_cap : 1,
        .publish_from = (uint32_t)(s->publish_from > 0 ? s->publish_from : 0), .adj_cap = m->adj_cap,
        .shift = (uint32_t)s->shift, .warm = s->warm && s->prev_keyframes > 0,
        .gate = s->gate, .gate_k = s->gate && s->gate_keyframe >= 1 && s->gate_keyframe + 1 < (int)nt
                                       ? (uint32_t)s->gate_keyframe : MID_GATE_NONE,
    };
    pr->gather = s->gather;
    pr->jacobi = s->precond == MID_PRECOND_JACOBI;
    pr->lambda = s->step > 0 ? s->step : MID_DESCENT_STEP;
    int iterations = s->iterations > 0 ? s->iterations
                     : kind == MID_SOLVER_DESCENT ? MID_DESCENT_ITERATIONS : MID_GN_ITERATIONS;
    int cg = s->cg_steps > 0 ? s->cg_steps : MID_GN_CG_STEPS;
    pr->count = 0;
    add_item(pr, G_BUILD, 0);
    add_item(pr, G_INIT, 0);
    for (int it = 0; it < iterations; it++) {
        if (kind == MID_SOLVER_DESCENT) {
            add_item(pr, G_DESCENT, 0);
            continue;
        }
        add_item(pr, G_PROLOGUE, 0);
        for (int j = 0; j < cg; j++)
            add_item(pr, G_CG, 0);
        for (int t = 0; t < MID_LINE_TRIALS; t++)
            add_item(pr, G_TRIAL, t);
        add_item(pr, G_END, 0);
    }
    if (s->publish)
        add_item(pr, G_PUBLISH, 0);
}

int solve_gpu_previous_settled(const solve_gpu *m, int from, int iterations)
{
    const program *pr = &m->prog[m->cur ^ 1];
    int ends = 0;
    for (int i = 1; i < pr->count; i++) {
        int g = pr->items[i - 1].graph;
        ends += g == G_END || g == G_DESCENT;
        if (i >= from && ends >= iterations && (g == G_INIT || g == G_END || g == G_DESCENT || g == G_PUBLISH))
            return i;
    }
    return pr->count;
}

int solve_gpu_item_count(const solve_gpu *m) { return m->prog[m->cur].count; }
int solve_gpu_previous_item_count(const solve_gpu *m) { return m->prog[m->cur ^ 1].count; }

double solve_gpu_item_cost(const solve_gpu *m, int i)
{
    const program *pr = &m->prog[m->cur];
    if (i < 0 || i >= pr->count)
        return 0.0;
    const item *it = &pr->items[i];
    /* Trials after the first are usually skipped (their dispatch size is 0). */
    if (it->graph == G_TRIAL && it->trial > 0)
        return 0.2;
    return k_graphs[it->graph].cost;
}

static void record(solve_gpu *m, const program *pr, VkCommandBuffer cmd, uint32_t slot, int first, int last)
{
    m->rec = pr;
    /* The arena's views (set 1) stay bound across the steps' pipelines: they share one layout. */
    if (first < last && first < pr->count)
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, m->layout, 1, 1, &m->view_set, 0, NULL);
    for (int i = first < 0 ? 0 : first; i < last && i < pr->count; i++) {
        const item *it = &pr->items[i];
        m->trial_t = ldexpf(1.0f, -(int)it->trial); /* t = 1, 1/2, 1/4, ... as the CPU's t *= 0.5f */
        rg_execute(m->graph[it->graph], cmd, slot);
    }
}

void solve_gpu_record(solve_gpu *m, VkCommandBuffer cmd, uint32_t slot, int first, int last)
{
    record(m, &m->prog[m->cur], cmd, slot, first, last);
}

void solve_gpu_record_previous(solve_gpu *m, VkCommandBuffer cmd, uint32_t slot, int first, int last)
{
    record(m, &m->prog[m->cur ^ 1], cmd, slot, first, last);
}

VkBuffer solve_gpu_arena(const solve_gpu *m) { return m->arena.buffer; }
VkDeviceSize solve_gpu_arena_size(const solve_gpu *m) { return m->arena.size; }
VkBuffer solve_gpu_args(const solve_gpu *m) { return m->args.buffer; }
uint32_t solve_gpu_capacity(const solve_gpu *m) { return m->cap; }
uint32_t solve_gpu_adj_capacity(const solve_gpu *m) { return m->adj_cap; }

void *solve_gpu_host(const solve_gpu *m, int binding, VkDeviceSize *bytes)
{
    if (!m->arena.mapped || binding < 0 || binding >= MID_B_COUNT || binding == MID_B_ARGS ||
        binding == MID_B_STORE || binding == MID_B_PUBLISHED)
        return NULL;
    if (bytes)
        *bytes = m->bytes[binding];
    return (uint8_t *)m->arena.mapped + m->offset[binding];
}

void solve_gpu_dump(const solve_gpu *m, FILE *out)
{
    for (int gi = 0; gi < G_COUNT; gi++) {
        fprintf(out, "%s:\n", k_graphs[gi].name);
        rg_dump_text(m->graph[gi], out);
    }
}
