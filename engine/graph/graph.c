/* vergence — frame graph: building and the compile step (plain data). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/log.h"
#include "graph_internal.h"

/* ------------------------------------------------------------------------- */
/* Usage table                                                               */
/* ------------------------------------------------------------------------- */

bool rg_format_is_depth(VkFormat f)
{
    return f == VK_FORMAT_D16_UNORM || f == VK_FORMAT_D32_SFLOAT || f == VK_FORMAT_D24_UNORM_S8_UINT ||
           f == VK_FORMAT_D32_SFLOAT_S8_UINT;
}

rg_state rg_usage_state(rg_usage usage, rg_pass_type type, bool is_image, VkFormat format)
{
    /* Shader stages of the pass: graphics passes may read in any stage
     * (the warp's tessellation shaders sample the disparity map). */
    VkPipelineStageFlags2 shaders = type == RG_PASS_COMPUTE
        ? VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT
        : VK_PIPELINE_STAGE_2_PRE_RASTERIZATION_SHADERS_BIT | VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT;
    VkPipelineStageFlags2 tests =
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    VkImageLayout none = VK_IMAGE_LAYOUT_UNDEFINED;
    switch (usage) {
    case RG_COLOR_WRITE:
        return (rg_state){VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                          VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT,
                          VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, false, true};
    case RG_DEPTH_WRITE:
        return (rg_state){tests,
                          VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                              VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                          VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, false, true};
    case RG_DEPTH_READ:
        return (rg_state){tests, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
                          VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL, true, false};
    case RG_SAMPLED:
        return (rg_state){shaders, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
                          rg_format_is_depth(format) ? VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL
                                                     : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                          true, false};
    /* A buffer's reads include those through a texel view of it (the solver
     * reads its arena so: shaders/mid_arena.glsl). */
    case RG_STORAGE_READ:
        return (rg_state){shaders,
                          VK_ACCESS_2_SHADER_STORAGE_READ_BIT | (is_image ? 0 : VK_ACCESS_2_SHADER_SAMPLED_READ_BIT),
                          is_image ? VK_IMAGE_LAYOUT_GENERAL : none, true, false};
    case RG_STORAGE_WRITE:
        return (rg_state){shaders, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                          is_image ? VK_IMAGE_LAYOUT_GENERAL : none, false, true};
    case RG_STORAGE_READ_WRITE:
        return (rg_state){shaders, VK_ACCESS_2_SHADER_STORAGE_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT |
                                       (is_image ? 0 : VK_ACCESS_2_SHADER_SAMPLED_READ_BIT),
                          is_image ? VK_IMAGE_LAYOUT_GENERAL : none, true, true};
    case RG_UNIFORM:
        return (rg_state){shaders, VK_ACCESS_2_UNIFORM_READ_BIT, none, true, false};
    case RG_VERTEX:
        return (rg_state){VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT,
                          VK_ACCESS_2_VERTEX_ATTRIBUTE_READ_BIT, none, true, false};
    case RG_INDEX:
        return (rg_state){VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, VK_ACCESS_2_INDEX_READ_BIT, none, true, false};
    case RG_INDIRECT:
        return (rg_state){VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT, none, true,
                          false};
    case RG_INDIRECT_STORAGE:
        return (rg_state){VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT | shaders,
                          VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_2_SHADER_STORAGE_READ_BIT |
                              VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                          none, true, true};
    case RG_TRANSFER_SRC:
        return (rg_state){VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT,
                          is_image ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL : none, true, false};
    case RG_TRANSFER_DST:
        return (rg_state){VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT,
                          is_image ? VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL : none, false, true};
    case RG_HOST_READ:
        return (rg_state){VK_PIPELINE_STAGE_2_HOST_BIT, VK_ACCESS_2_HOST_READ_BIT,
                          is_image ? VK_IMAGE_LAYOUT_GENERAL : none, true, false};
    case RG_PRESENT:
        return (rg_state){VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, true,
                          false};
    default:
        return (rg_state){0};
    }
}

/* ------------------------------------------------------------------------- */
/* Building                                                                  */
/* ------------------------------------------------------------------------- */

rg_graph *rg_create(void)
{
    return calloc(1, sizeof(rg_graph));
}

static void copy_name(char *dst, const char *src)
{
    snprintf(dst, RG_NAME_MAX, "%s", src ? src : "unnamed");
}

static rg_res add_resource(rg_graph *g, const char *name, bool is_image)
{
    if (g->res_count >= RG_MAX_RESOURCES) {
        vg_error("frame graph: more than %d resources ('%s')", RG_MAX_RESOURCES, name);
        g->build_error = true;
        return (rg_res){0};
    }
    rg_resource *r = &g->res[g->res_count];
    *r = (rg_resource){.is_image = is_image, .physical = RG_NONE, .first = RG_NONE};
    copy_name(r->name, name);
    g->compiled = false;
    return (rg_res){++g->res_count};
}

rg_res rg_image(rg_graph *g, const rg_image_desc *desc)
{
    rg_res h = add_resource(g, desc->name, true);
    if (h.id) {
        rg_resource *r = &g->res[h.id - 1];
        r->format = desc->format;
        r->width = desc->width;
        r->height = desc->height;
        r->layers = desc->layers ? desc->layers : 1;
    }
    return h;
}

rg_res rg_buffer(rg_graph *g, const rg_buffer_desc *desc)
{
    rg_res h = add_resource(g, desc->name, false);
    if (h.id)
        g->res[h.id - 1].size = desc->size;
    return h;
}

rg_res rg_import_image(rg_graph *g, const rg_image_desc *desc, const rg_import_desc *imp)
{
    rg_res h = rg_image(g, desc);
    if (h.id) {
        g->res[h.id - 1].imported = true;
        g->res[h.id - 1].imp = *imp;
    }
    return h;
}

rg_res rg_import_buffer(rg_graph *g, const rg_buffer_desc *desc, const rg_import_desc *imp)
{
    rg_res h = rg_buffer(g, desc);
    if (h.id) {
        g->res[h.id - 1].imported = true;
        g->res[h.id - 1].imp = *imp;
    }
    return h;
}

void rg_export(rg_graph *g, rg_res res)
{
    if (res.id && res.id <= g->res_count)
        g->res[res.id - 1].exported = true;
}

rg_pass rg_pass_add(rg_graph *g, const rg_pass_desc *desc)
{
    if (g->pass_count >= RG_MAX_PASSES) {
        vg_error("frame graph: more than %d passes ('%s')", RG_MAX_PASSES, desc->name);
        g->build_error = true;
        return (rg_pass){0};
    }
    rg_pass_info *p = &g->pass[g->pass_count];
    *p = (rg_pass_info){
        .type = desc->type ? desc->type : RG_PASS_GRAPHICS,
        .execute = desc->execute,
        .user = desc->user,
        .side_effects = desc->side_effects,
        .order = RG_NONE,
    };
    copy_name(p->name, desc->name);
    g->compiled = false;
    return (rg_pass){++g->pass_count};
}

static void add_use(rg_graph *g, rg_pass pass, rg_res res, rg_usage usage, bool clear, VkClearValue value)
{
    if (!pass.id || pass.id > g->pass_count || !res.id || res.id > g->res_count) {
        vg_error("frame graph: use of an invalid pass or resource handle");
        g->build_error = true;
        return;
    }
    if (g->use_count >= RG_MAX_USES) {
        vg_error("frame graph: more than %d resource uses", RG_MAX_USES);
        g->build_error = true;
        return;
    }
    g->use[g->use_count++] = (rg_use_info){
        .pass = pass.id - 1, .res = res.id - 1, .usage = usage, .clear = clear, .clear_value = value};
    g->compiled = false;
}

void rg_use(rg_graph *g, rg_pass pass, rg_res res, rg_usage usage)
{
    add_use(g, pass, res, usage, false, (VkClearValue){0});
}

void rg_use_clear(rg_graph *g, rg_pass pass, rg_res res, rg_usage usage, VkClearValue clear)
{
    add_use(g, pass, res, usage, true, clear);
}


/* ------------------------------------------------------------------------- */
/* Names (errors, dumps)                                                     */
/* ------------------------------------------------------------------------- */

const char *rg_usage_name(rg_usage u)
{
    static const char *const names[RG_USAGE_COUNT] = {
        [RG_USAGE_NONE] = "none",           [RG_COLOR_WRITE] = "color-write",
        [RG_DEPTH_WRITE] = "depth-write",   [RG_DEPTH_READ] = "depth-read",
        [RG_SAMPLED] = "sampled",           [RG_STORAGE_READ] = "storage-read",
        [RG_STORAGE_WRITE] = "storage-write", [RG_STORAGE_READ_WRITE] = "storage-read-write",
        [RG_UNIFORM] = "uniform",           [RG_VERTEX] = "vertex",
        [RG_INDEX] = "index",               [RG_INDIRECT] = "indirect",
        [RG_INDIRECT_STORAGE] = "indirect-storage", [RG_TRANSFER_SRC] = "transfer-src",
        [RG_TRANSFER_DST] = "transfer-dst", [RG_HOST_READ] = "host-read",
        [RG_PRESENT] = "present",
    };
    return (unsigned)u < RG_USAGE_COUNT ? names[u] : "?";
}

const char *rg_layout_name(VkImageLayout l)
{
    switch (l) {
    case VK_IMAGE_LAYOUT_UNDEFINED: return "UNDEFINED";
    case VK_IMAGE_LAYOUT_GENERAL: return "GENERAL";
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL: return "COLOR_ATTACHMENT";
    case VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL: return "DEPTH_ATTACHMENT";
    case VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL: return "DEPTH_READ_ONLY";
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL: return "SHADER_READ_ONLY";
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL: return "TRANSFER_SRC";
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL: return "TRANSFER_DST";
    case VK_IMAGE_LAYOUT_PRESENT_SRC_KHR: return "PRESENT_SRC";
    default: return "OTHER";
    }
}

const char *rg_format_name(VkFormat f)
{
    switch (f) {
    case VK_FORMAT_R8_UNORM: return "R8_UNORM";
    case VK_FORMAT_R8G8B8A8_UNORM: return "RGBA8_UNORM";
    case VK_FORMAT_R8G8B8A8_SRGB: return "RGBA8_SRGB";
    case VK_FORMAT_B8G8R8A8_SRGB: return "BGRA8_SRGB";
    case VK_FORMAT_B8G8R8A8_UNORM: return "BGRA8_UNORM";
    case VK_FORMAT_R16_SFLOAT: return "R16F";
    case VK_FORMAT_R16G16_SFLOAT: return "RG16F";
    case VK_FORMAT_R16G16B16A16_SFLOAT: return "RGBA16F";
    case VK_FORMAT_R32_SFLOAT: return "R32F";
    case VK_FORMAT_R32_UINT: return "R32_UINT";
    case VK_FORMAT_R32G32_SFLOAT: return "RG32F";
    case VK_FORMAT_R32G32B32A32_SFLOAT: return "RGBA32F";
    case VK_FORMAT_D32_SFLOAT: return "D32F";
    case VK_FORMAT_D16_UNORM: return "D16";
    default: return "FORMAT";
    }
}

/* ------------------------------------------------------------------------- */
/* 1. Validate                                                               */
/* ------------------------------------------------------------------------- */

static bool is_attachment(rg_usage u)
{
    return u == RG_COLOR_WRITE || u == RG_DEPTH_WRITE || u == RG_DEPTH_READ;
}

static bool image_only(rg_usage u)
{
    return is_attachment(u) || u == RG_SAMPLED;
}

static bool buffer_only(rg_usage u)
{
    return u == RG_UNIFORM || u == RG_VERTEX || u == RG_INDEX || u == RG_INDIRECT || u == RG_INDIRECT_STORAGE;
}

static bool is_transfer(rg_usage u)
{
    return u == RG_TRANSFER_SRC || u == RG_TRANSFER_DST;
}

static vg_status invalid(const rg_graph *g, const rg_use_info *u, const char *why)
{
    vg_error("frame graph: pass '%s' uses '%s' as %s: %s", g->pass[u->pass].name, g->res[u->res].name,
             rg_usage_name(u->usage), why);
    return VG_ERR_GRAPH;
}

static vg_status validate(const rg_graph *g)
{
    for (uint32_t i = 0; i < g->use_count; i++) {
        const rg_use_info *u = &g->use[i];
        const rg_resource *r = &g->res[u->res];
        rg_pass_type type = g->pass[u->pass].type;
        if (u->usage <= RG_USAGE_NONE || u->usage >= RG_HOST_READ)
            return invalid(g, u, "not a usage a pass can declare");
        if (!r->is_image && image_only(u->usage))
            return invalid(g, u, "it is a buffer");
        if (r->is_image && buffer_only(u->usage))
            return invalid(g, u, "it is an image");
        if (is_attachment(u->usage) && type != RG_PASS_GRAPHICS)
            return invalid(g, u, "attachments belong to graphics passes");
        if (is_transfer(u->usage) && type == RG_PASS_GRAPHICS)
            return invalid(g, u, "copies cannot run inside a graphics pass's rendering");
        bool depth_format = r->is_image && rg_format_is_depth(r->format);
        if ((u->usage == RG_DEPTH_WRITE || u->usage == RG_DEPTH_READ) && !depth_format)
            return invalid(g, u, "a depth attachment needs a depth format");
        if (u->usage == RG_COLOR_WRITE && depth_format)
            return invalid(g, u, "a colour attachment cannot have a depth format");
        if (u->clear && !is_attachment(u->usage))
            return invalid(g, u, "only attachments can be cleared");
        for (uint32_t j = 0; j < i; j++)
            if (g->use[j].pass == u->pass && g->use[j].res == u->res)
                return invalid(g, u, "the pass already declared this resource");
    }
    /* Attachments of one graphics pass share one render area. */
    for (uint32_t p = 0; p < g->pass_count; p++) {
        const rg_resource *first = NULL;
        for (uint32_t i = 0; i < g->use_count; i++) {
            const rg_use_info *u = &g->use[i];
            if (u->pass != p || !is_attachment(u->usage))
                continue;
            const rg_resource *r = &g->res[u->res];
            if (!first)
                first = r;
            else if (r->width != first->width || r->height != first->height || r->layers != first->layers)
                return invalid(g, u, "its size differs from the pass's other attachments");
        }
        if (g->pass[p].type == RG_PASS_GRAPHICS && !first) {
            vg_error("frame graph: graphics pass '%s' has no attachment", g->pass[p].name);
            return VG_ERR_GRAPH;
        }
    }
    /* Nothing is read before something wrote it (imports with an initial state count as written). */
    bool written[RG_MAX_RESOURCES];
    for (uint32_t r = 0; r < g->res_count; r++)
        written[r] = g->res[r].imported && g->res[r].imp.initial != RG_USAGE_NONE;
    for (uint32_t p = 0; p < g->pass_count; p++) {
        for (uint32_t i = 0; i < g->use_count; i++) {
            const rg_use_info *u = &g->use[i];
            const rg_resource *r = &g->res[u->res];
            if (u->pass == p && rg_usage_state(u->usage, g->pass[p].type, r->is_image, r->format).reads &&
                !written[u->res])
                return invalid(g, u, "nothing wrote it before");
        }
        for (uint32_t i = 0; i < g->use_count; i++) {
            const rg_use_info *u = &g->use[i];
            const rg_resource *r = &g->res[u->res];
            if (u->pass == p && rg_usage_state(u->usage, g->pass[p].type, r->is_image, r->format).writes)
                written[u->res] = true;
        }
    }
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* 2. Cull                                                                   */
/* ------------------------------------------------------------------------- */

static rg_state use_state(const rg_graph *g, const rg_use_info *u)
{
    const rg_resource *r = &g->res[u->res];
    rg_state s = rg_usage_state(u->usage, g->pass[u->pass].type, r->is_image, r->format);
    if (u->load)
        s.reads = true;
    return s;
}

/* Attachments that are not cleared keep what an earlier pass drew (LOAD);
 * with no earlier writer their contents start undefined (DONT_CARE). */
static void resolve_loads(rg_graph *g)
{
    for (uint32_t i = 0; i < g->use_count; i++) {
        rg_use_info *u = &g->use[i];
        u->load = false;
        if (u->usage != RG_COLOR_WRITE && u->usage != RG_DEPTH_WRITE)
            continue;
        if (u->clear)
            continue;
        const rg_resource *r = &g->res[u->res];
        bool before = r->imported && r->imp.initial != RG_USAGE_NONE;
        for (uint32_t j = 0; j < g->use_count && !before; j++) {
            const rg_use_info *w = &g->use[j];
            before = w->res == u->res && w->pass < u->pass &&
                     rg_usage_state(w->usage, g->pass[w->pass].type, r->is_image, r->format).writes;
        }
        u->load = before;
    }
}

/* Walks passes backwards: a pass lives when it has side effects or writes a
 * resource that a living later pass reads, or that leaves the frame. */
static void cull(rg_graph *g)
{
    bool needed[RG_MAX_RESOURCES];
    for (uint32_t r = 0; r < g->res_count; r++)
        needed[r] = g->res[r].imported || g->res[r].exported;
    for (uint32_t p = g->pass_count; p-- > 0;) {
        bool alive = g->pass[p].side_effects;
        for (uint32_t i = 0; i < g->use_count; i++)
            if (g->use[i].pass == p && use_state(g, &g->use[i]).writes && needed[g->use[i].res])
                alive = true;
        g->pass[p].culled = !alive;
        if (!alive)
            continue;
        for (uint32_t i = 0; i < g->use_count; i++) {
            const rg_use_info *u = &g->use[i];
            if (u->pass != p)
                continue;
            rg_state s = use_state(g, u);
            const rg_resource *r = &g->res[u->res];
            if (s.writes && !s.reads && !r->imported && !r->exported)
                needed[u->res] = false; /* fully produced here: earlier versions are dead */
            if (s.reads)
                needed[u->res] = true;
        }
    }
}

/* ------------------------------------------------------------------------- */
/* 3. Order                                                                  */
/* ------------------------------------------------------------------------- */

/* Kahn's algorithm over read-after-write, write-after-read and
 * write-after-write hazards; among ready passes the earliest declared goes
 * first, so independent passes keep the order the author wrote. */
static vg_status order(rg_graph *g)
{
    static bool dep[RG_MAX_PASSES][RG_MAX_PASSES];
    memset(dep, 0, sizeof dep);
    for (uint32_t r = 0; r < g->res_count; r++) {
        uint32_t last_writer = RG_NONE;
        uint32_t readers[RG_MAX_PASSES], reader_count = 0;
        for (uint32_t p = 0; p < g->pass_count; p++) {
            if (g->pass[p].culled)
                continue;
            for (uint32_t i = 0; i < g->use_count; i++) {
                const rg_use_info *u = &g->use[i];
                if (u->pass != p || u->res != r)
                    continue;
                rg_state s = use_state(g, u);
                if (s.reads && last_writer != RG_NONE)
                    dep[last_writer][p] = true; /* RAW */
                if (s.writes) {
                    if (last_writer != RG_NONE)
                        dep[last_writer][p] = true; /* WAW */
                    for (uint32_t k = 0; k < reader_count; k++)
                        if (readers[k] != p)
                            dep[readers[k]][p] = true; /* WAR */
                    last_writer = p;
                    reader_count = 0;
                } else if (reader_count < RG_MAX_PASSES) {
                    readers[reader_count++] = p;
                }
            }
        }
    }
    uint32_t indegree[RG_MAX_PASSES] = {0};
    bool placed[RG_MAX_PASSES] = {0};
    uint32_t alive = 0;
    for (uint32_t p = 0; p < g->pass_count; p++) {
        g->pass[p].order = RG_NONE;
        if (g->pass[p].culled)
            continue;
        alive++;
        for (uint32_t q = 0; q < g->pass_count; q++)
            indegree[p] += dep[q][p];
    }
    g->order_count = 0;
    while (g->order_count < alive) {
        uint32_t next = RG_NONE;
        for (uint32_t p = 0; p < g->pass_count && next == RG_NONE; p++)
            if (!g->pass[p].culled && !placed[p] && indegree[p] == 0)
                next = p;
        if (next == RG_NONE) {
            vg_error("frame graph: the passes depend on each other in a cycle");
            return VG_ERR_GRAPH;
        }
        placed[next] = true;
        g->pass[next].order = g->order_count;
        g->order[g->order_count++] = next;
        for (uint32_t q = 0; q < g->pass_count; q++)
            if (dep[next][q])
                indegree[q]--;
    }
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* 4. Lifetimes and 5. aliasing                                              */
/* ------------------------------------------------------------------------- */

static void lifetimes(rg_graph *g)
{
    for (uint32_t r = 0; r < g->res_count; r++) {
        g->res[r].first = RG_NONE;
        g->res[r].last = 0;
        g->res[r].physical = RG_NONE;
    }
    for (uint32_t i = 0; i < g->use_count; i++) {
        const rg_use_info *u = &g->use[i];
        uint32_t o = g->pass[u->pass].order;
        if (o == RG_NONE)
            continue;
        rg_resource *r = &g->res[u->res];
        if (r->first == RG_NONE || o < r->first)
            r->first = o;
        if (o > r->last)
            r->last = o;
    }
    /* Whatever leaves the frame lives to its end. */
    for (uint32_t r = 0; r < g->res_count; r++)
        if (g->res[r].first != RG_NONE && (g->res[r].imported || g->res[r].exported))
            g->res[r].last = g->order_count;
}

static bool same_shape(const rg_physical *p, const rg_resource *r)
{
    if (p->imported || p->is_image != r->is_image)
        return false;
    if (r->is_image)
        return p->format == r->format && p->width == r->width && p->height == r->height && p->layers == r->layers;
    return p->size == r->size;
}

static void alias(rg_graph *g)
{
    memset(g->phys, 0, sizeof g->phys);
    g->phys_count = 0;
    /* Visit resources by first use so a freed physical resource is reused by
     * the next one that starts after it ends. */
    for (uint32_t o = 0; o <= g->order_count; o++)
        for (uint32_t ri = 0; ri < g->res_count; ri++) {
            rg_resource *r = &g->res[ri];
            if (r->first != o)
                continue;
            uint32_t chosen = RG_NONE;
            if (!r->imported)
                for (uint32_t k = 0; k < g->phys_count && chosen == RG_NONE; k++)
                    if (same_shape(&g->phys[k], r) && g->phys[k].last < r->first)
                        chosen = k;
            if (chosen == RG_NONE) {
                chosen = g->phys_count++;
                g->phys[chosen] = (rg_physical){
                    .is_image = r->is_image, .imported = r->imported, .format = r->format,
                    .width = r->width, .height = r->height, .layers = r->layers, .size = r->size,
                    .res = ri};
            }
            g->phys[chosen].last = r->exported ? g->order_count : r->last;
            r->physical = chosen;
        }
    for (uint32_t i = 0; i < g->use_count; i++) {
        const rg_use_info *u = &g->use[i];
        const rg_resource *r = &g->res[u->res];
        if (r->physical == RG_NONE || g->pass[u->pass].culled)
            continue;
        rg_physical *p = &g->phys[r->physical];
        switch (u->usage) {
        case RG_COLOR_WRITE: p->image_usage |= VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT; break;
        case RG_DEPTH_WRITE:
        case RG_DEPTH_READ: p->image_usage |= VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT; break;
        case RG_SAMPLED: p->image_usage |= VK_IMAGE_USAGE_SAMPLED_BIT; break;
        case RG_STORAGE_READ:
        case RG_STORAGE_WRITE:
        case RG_STORAGE_READ_WRITE:
            p->image_usage |= VK_IMAGE_USAGE_STORAGE_BIT;
            p->buffer_usage |= VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
            break;
        case RG_UNIFORM: p->buffer_usage |= VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT; break;
        case RG_VERTEX: p->buffer_usage |= VK_BUFFER_USAGE_VERTEX_BUFFER_BIT; break;
        case RG_INDEX: p->buffer_usage |= VK_BUFFER_USAGE_INDEX_BUFFER_BIT; break;
        case RG_INDIRECT: p->buffer_usage |= VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT; break;
        case RG_INDIRECT_STORAGE:
            p->buffer_usage |= VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
            break;
        case RG_TRANSFER_SRC:
            p->image_usage |= VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
            p->buffer_usage |= VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
            break;
        case RG_TRANSFER_DST:
            p->image_usage |= VK_IMAGE_USAGE_TRANSFER_DST_BIT;
            p->buffer_usage |= VK_BUFFER_USAGE_TRANSFER_DST_BIT;
            break;
        default: break;
        }
    }
}

/* ------------------------------------------------------------------------- */
/* 6. Barriers                                                               */
/* ------------------------------------------------------------------------- */

#define RG_WRITE_ACCESS                                                                            \
    (VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |     \
     VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT | VK_ACCESS_2_TRANSFER_WRITE_BIT | VK_ACCESS_2_HOST_WRITE_BIT)

/* How an imported resource enters the frame. */
static rg_track import_track(const rg_resource *r)
{
    rg_track t = {.layout = VK_IMAGE_LAYOUT_UNDEFINED, .owner = RG_NONE};
    if (r->imp.initial == RG_PRESENT) {
        /* A swapchain image: the acquire semaphore is waited on at colour output. */
        t.read_stage = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    } else if (r->imp.initial != RG_USAGE_NONE) {
        rg_state s = rg_usage_state(r->imp.initial, RG_PASS_GRAPHICS, r->is_image, r->format);
        t.layout = s.layout;
        t.read_stage = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
    }
    return t;
}

typedef struct barrier_sink {
    rg_barrier *items;
    uint32_t count, cap;
    bool failed;
} barrier_sink;

static void emit(barrier_sink *sink, const rg_barrier *b)
{
    if (!sink)
        return;
    if (sink->count == sink->cap) {
        uint32_t cap = sink->cap ? sink->cap * 2 : 64;
        rg_barrier *p = realloc(sink->items, cap * sizeof *p);
        if (!p) {
            sink->failed = true;
            return;
        }
        sink->items = p;
        sink->cap = cap;
    }
    sink->items[sink->count++] = *b;
}

/* Moves a physical resource from its tracked state to the state a use
 * needs, emitting a barrier when there is a hazard or a layout change. */
static void transition(rg_track *t, const rg_physical *ph, uint32_t res, uint32_t physical, rg_state n,
                       bool discard, barrier_sink *sink)
{
    VkImageLayout old_layout = discard ? VK_IMAGE_LAYOUT_UNDEFINED : t->layout;
    bool layout_change = ph->is_image && (discard || n.layout != t->layout);
    bool raw = t->write_stage && ((n.stage & ~t->visible_stage) || (n.access & ~t->visible_access));
    bool waw = t->write_stage && n.writes;
    bool war = n.writes && t->read_stage;
    bool prior = t->write_stage || t->read_stage;
    if (layout_change || ((raw || waw || war) && prior)) {
        rg_barrier b = {
            .res = {res + 1},
            .physical = physical,
            .src_stage = t->write_stage | t->read_stage,
            .src_access = t->write_access,
            .dst_stage = n.stage,
            .dst_access = n.access,
            .old_layout = ph->is_image ? old_layout : VK_IMAGE_LAYOUT_UNDEFINED,
            .new_layout = ph->is_image ? n.layout : VK_IMAGE_LAYOUT_UNDEFINED,
            .is_image = ph->is_image,
        };
        emit(sink, &b);
        /* The barrier made earlier writes available: later barriers chain
         * on its stages and only need to make them visible. */
        t->visible_stage = n.stage;
        t->visible_access = n.access;
        t->write_access = 0;
        t->read_stage = 0;
        /* A layout transition writes the image: a later use at another stage
         * waits for it, even when no pass of the frame wrote the image (an
         * imported one, read at compute and then at the vertex stage). */
        if (layout_change && !t->write_stage)
            t->write_stage = n.stage;
    }
    if (n.writes) {
        t->write_stage = n.stage;
        t->write_access = n.access & RG_WRITE_ACCESS;
        t->read_stage = 0;
        t->visible_stage = 0;
        t->visible_access = 0;
    } else {
        t->read_stage |= n.stage;
    }
    if (ph->is_image)
        t->layout = n.layout;
}

/* One walk over the ordered passes from the given start states. */
static void simulate(rg_graph *g, rg_track *track, barrier_sink *sink)
{
    for (uint32_t o = 0; o <= g->order_count; o++) {
        if (sink)
            g->barrier_first[o] = sink->count;
        if (o == g->order_count)
            break;
        uint32_t p = g->order[o];
        for (uint32_t i = 0; i < g->use_count; i++) {
            rg_use_info *u = &g->use[i];
            if (u->pass != p)
                continue;
            const rg_resource *r = &g->res[u->res];
            rg_track *t = &track[r->physical];
            rg_state n = use_state(g, u);
            /* A resource that takes over a physical one, or a transient one at
             * the start of the frame, starts with undefined contents. */
            bool discard = t->owner != u->res && !r->imported;
            t->owner = u->res;
            transition(t, &g->phys[r->physical], u->res, r->physical, n, discard, sink);
            u->layout = n.layout;
        }
    }
    /* End of frame: imported resources go to the state their owner asked for. */
    for (uint32_t r = 0; r < g->res_count; r++) {
        const rg_resource *res = &g->res[r];
        if (!res->imported || res->physical == RG_NONE || res->imp.final == RG_USAGE_NONE)
            continue;
        rg_state n = rg_usage_state(res->imp.final, RG_PASS_GRAPHICS, res->is_image, res->format);
        if (res->imp.final != RG_HOST_READ && res->imp.final != RG_PRESENT)
            n.stage = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
        transition(&track[res->physical], &g->phys[res->physical], r, res->physical, n, false, sink);
    }
    if (sink)
        g->barrier_first[g->order_count + 1] = sink->count;
}

static vg_status barriers(rg_graph *g)
{
    /* First walk: the state every physical resource ends the frame in, which
     * is where the next frame finds the transient ones. */
    rg_track track[RG_MAX_RESOURCES];
    for (uint32_t k = 0; k < g->phys_count; k++)
        track[k] = g->phys[k].imported ? import_track(&g->res[g->phys[k].res])
                                       : (rg_track){.layout = VK_IMAGE_LAYOUT_UNDEFINED, .owner = RG_NONE};
    simulate(g, track, NULL);
    for (uint32_t k = 0; k < g->phys_count; k++) {
        if (g->phys[k].imported)
            track[k] = import_track(&g->res[g->phys[k].res]);
        track[k].owner = RG_NONE;
        track[k].visible_stage = 0;
        track[k].visible_access = 0;
    }
    barrier_sink sink = {0};
    simulate(g, track, &sink);
    if (sink.failed) {
        free(sink.items);
        return VG_ERR_NOMEM;
    }
    free(g->barriers);
    g->barriers = sink.items;
    g->barrier_count = sink.count;
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Compile                                                                   */
/* ------------------------------------------------------------------------- */

vg_status rg_compile(rg_graph *g)
{
    g->compiled = false;
    if (g->build_error)
        return VG_ERR_GRAPH;
    vg_status st = validate(g);          /* 1. usages, sizes, read-before-write */
    if (st != VG_OK)
        return st;
    resolve_loads(g);                     /*    attachments: load or start fresh */
    cull(g);                              /* 2. drop passes nobody needs */
    if ((st = order(g)) != VG_OK)         /* 3. stable topological order */
        return st;
    lifetimes(g);                         /* 4. first and last use */
    alias(g);                             /* 5. share physical resources */
    if ((st = barriers(g)) != VG_OK)      /* 6. derive every barrier */
        return st;
    g->compiled = true;
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* Queries                                                                   */
/* ------------------------------------------------------------------------- */

uint32_t rg_order_count(const rg_graph *g) { return g->compiled ? g->order_count : 0; }

rg_pass rg_order_pass(const rg_graph *g, uint32_t i)
{
    return i < rg_order_count(g) ? (rg_pass){g->order[i] + 1} : (rg_pass){0};
}

bool rg_pass_culled(const rg_graph *g, rg_pass pass)
{
    return pass.id && pass.id <= g->pass_count && g->pass[pass.id - 1].culled;
}

const char *rg_pass_name(const rg_graph *g, rg_pass pass)
{
    return pass.id && pass.id <= g->pass_count ? g->pass[pass.id - 1].name : "?";
}

uint32_t rg_physical_count(const rg_graph *g) { return g->compiled ? g->phys_count : 0; }

uint32_t rg_res_physical(const rg_graph *g, rg_res res)
{
    return res.id && res.id <= g->res_count && g->compiled ? g->res[res.id - 1].physical : RG_NONE;
}

const char *rg_res_name(const rg_graph *g, rg_res res)
{
    return res.id && res.id <= g->res_count ? g->res[res.id - 1].name : "?";
}

const rg_barrier *rg_barriers(const rg_graph *g, uint32_t i, uint32_t *count)
{
    *count = 0;
    if (!g->compiled || i > g->order_count)
        return NULL;
    *count = g->barrier_first[i + 1] - g->barrier_first[i];
    return g->barriers + g->barrier_first[i];
}
