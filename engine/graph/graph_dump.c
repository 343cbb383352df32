/* vergence — frame graph: names and dumps (text and Graphviz DOT). */
#include <stdio.h>
#include <string.h>

#include "core/log.h"
#include "graph_internal.h"

static void stage_names(VkPipelineStageFlags2 s, char *out, size_t cap)
{
    static const struct { VkPipelineStageFlags2 bit; const char *name; } table[] = {
        {VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, "ALL"},
        {VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT, "INDIRECT"},
        {VK_PIPELINE_STAGE_2_VERTEX_ATTRIBUTE_INPUT_BIT, "VERTEX_INPUT"},
        {VK_PIPELINE_STAGE_2_INDEX_INPUT_BIT, "INDEX_INPUT"},
        {VK_PIPELINE_STAGE_2_PRE_RASTERIZATION_SHADERS_BIT, "PRE_RASTER"},
        {VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, "FRAGMENT"},
        {VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT, "EARLY_TESTS"},
        {VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT, "LATE_TESTS"},
        {VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, "COLOR_OUT"},
        {VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, "COMPUTE"},
        {VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT, "TRANSFER"},
        {VK_PIPELINE_STAGE_2_HOST_BIT, "HOST"},
    };
    out[0] = 0;
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++)
        if (s & table[i].bit) {
            if (out[0])
                strncat(out, "|", cap - strlen(out) - 1);
            strncat(out, table[i].name, cap - strlen(out) - 1);
        }
    if (!out[0])
        snprintf(out, cap, "NONE");
}

static const char *type_name(rg_pass_type t)
{
    return t == RG_PASS_COMPUTE ? "compute" : t == RG_PASS_TRANSFER ? "transfer" : "graphics";
}

static void dump_barrier(const rg_graph *g, const rg_barrier *b, FILE *out)
{
    char src[128], dst[128];
    stage_names(b->src_stage, src, sizeof src);
    stage_names(b->dst_stage, dst, sizeof dst);
    if (b->is_image)
        fprintf(out, "    barrier %-18s %s -> %s  [%s -> %s]\n", g->res[b->res.id - 1].name,
                rg_layout_name(b->old_layout), rg_layout_name(b->new_layout), src, dst);
    else
        fprintf(out, "    barrier %-18s buffer  [%s -> %s]\n", g->res[b->res.id - 1].name, src, dst);
}

void rg_dump_text(const rg_graph *g, FILE *out)
{
    if (!g->compiled) {
        fprintf(out, "frame graph: not compiled\n");
        return;
    }
    uint32_t culled = g->pass_count - g->order_count, used = 0;
    for (uint32_t r = 0; r < g->res_count; r++)
        used += g->res[r].physical != RG_NONE;
    fprintf(out, "frame graph: %u passes (%u culled), %u resources on %u physical, %u barriers\n",
            g->order_count, culled, used, g->phys_count, g->barrier_count);
    for (uint32_t o = 0; o < g->order_count; o++) {
        uint32_t p = g->order[o];
        fprintf(out, "%2u %-20s (%s)\n", o, g->pass[p].name, type_name(g->pass[p].type));
        uint32_t n;
        const rg_barrier *b = rg_barriers(g, o, &n);
        for (uint32_t k = 0; k < n; k++)
            dump_barrier(g, &b[k], out);
        for (uint32_t i = 0; i < g->use_count; i++) {
            const rg_use_info *u = &g->use[i];
            if (u->pass != p)
                continue;
            fprintf(out, "    %-6s %-18s %s%s  (physical %u)\n",
                    rg_usage_state(u->usage, g->pass[p].type, true, VK_FORMAT_UNDEFINED).writes || u->load ? "write" : "read",
                    g->res[u->res].name, rg_usage_name(u->usage),
                    u->clear ? ", clear" : u->load ? ", load" : "", g->res[u->res].physical);
        }
    }
    uint32_t n;
    const rg_barrier *b = rg_barriers(g, g->order_count, &n);
    if (n) {
        fprintf(out, "   end of frame\n");
        for (uint32_t k = 0; k < n; k++)
            dump_barrier(g, &b[k], out);
    }
    for (uint32_t p = 0; p < g->pass_count; p++)
        if (g->pass[p].culled)
            fprintf(out, "   culled: %s\n", g->pass[p].name);
    fprintf(out, "resources:\n");
    for (uint32_t r = 0; r < g->res_count; r++) {
        const rg_resource *res = &g->res[r];
        if (res->physical == RG_NONE) {
            fprintf(out, "  %-20s unused\n", res->name);
            continue;
        }
        char shape[64];
        if (res->is_image)
            snprintf(shape, sizeof shape, "%s %ux%u%s", rg_format_name(res->format), res->width, res->height,
                     res->layers > 1 ? "xN" : "");
        else
            snprintf(shape, sizeof shape, "buffer %llu B", (unsigned long long)res->size);
        fprintf(out, "  %-20s %-26s physical %-2u passes %u..%u%s%s\n", res->name, shape, res->physical,
                res->first, res->last, res->imported ? " imported" : "", res->exported ? " exported" : "");
    }
}

vg_status rg_dump_dot(const rg_graph *g, const char *path)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        vg_error("%s: cannot write the graph dump", path);
        return VG_ERR_IO;
    }
    fprintf(f, "digraph frame {\n  rankdir=LR;\n  node [fontname=\"Helvetica\", fontsize=10];\n");
    for (uint32_t p = 0; p < g->pass_count; p++)
        fprintf(f, "  p%u [shape=box, style=\"rounded,filled\", fillcolor=\"%s\", label=\"%s\\n(%s)\"];\n", p,
                g->pass[p].culled ? "#dddddd" : g->pass[p].type == RG_PASS_COMPUTE ? "#cfe8ff" : "#ffe3c4",
                g->pass[p].name, g->pass[p].culled ? "culled" : type_name(g->pass[p].type));
    for (uint32_t r = 0; r < g->res_count; r++) {
        const rg_resource *res = &g->res[r];
        fprintf(f, "  r%u [shape=ellipse, style=filled, fillcolor=\"%s\", label=\"%s\\n%s%s\"];\n", r,
                res->imported ? "#e6d8ff" : "#f2f2f2", res->name,
                res->is_image ? rg_format_name(res->format) : "buffer",
                res->physical != RG_NONE ? "" : " (unused)");
    }
    for (uint32_t i = 0; i < g->use_count; i++) {
        const rg_use_info *u = &g->use[i];
        rg_state s = rg_usage_state(u->usage, g->pass[u->pass].type, g->res[u->res].is_image, g->res[u->res].format);
        if (s.reads || u->load)
            fprintf(f, "  r%u -> p%u [label=\"%s\"];\n", u->res, u->pass, rg_usage_name(u->usage));
        if (s.writes)
            fprintf(f, "  p%u -> r%u [label=\"%s\"];\n", u->pass, u->res, rg_usage_name(u->usage));
    }
    fprintf(f, "}\n");
    if (fclose(f) != 0) {
        vg_error("%s: cannot finish the graph dump", path);
        return VG_ERR_IO;
    }
    return VG_OK;
}
