/* vergence — overlays drawn into each eye. */
#include "overlay_gpu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_easy_font.h>

#include "gpu/pipeline.h"

#include "hud_frag.h"
#include "hud_vert.h"

#define OVERLAY_MAX_QUADS 8192

/* stb_easy_font's vertex: x, y, z floats and an RGBA8 colour. */
typedef struct hud_vertex {
    float x, y, z;
    uint8_t rgba[4];
} hud_vertex;

typedef struct hud_push {
    float inv_half_extent[2];
    float scale;
    float shift;                 /* eye pixels to the right */
} hud_push;

typedef struct eye_pass {
    overlay_gpu *o;
    int eye;                     /* 0 left, 1 right */
} eye_pass;

struct overlay_gpu {
    frame_ctx *fc;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    gpu_buffer vertices[VG_FRAMES_IN_FLIGHT];
    gpu_buffer indices;
    uint32_t quads[VG_FRAMES_IN_FLIGHT];
    float scale[VG_FRAMES_IN_FLIGHT], parallax[VG_FRAMES_IN_FLIGHT];
    eye_pass pass[2];
};

/* ------------------------------------------------------------------------- */
/* Geometry, in font units (the vertex shader scales by the HUD's scale)     */
/* ------------------------------------------------------------------------- */

static uint32_t add_quad(hud_vertex *v, uint32_t n, float x0, float y0, float x1, float y1, const uint8_t c[4])
{
    if (n >= OVERLAY_MAX_QUADS)
        return n;
    hud_vertex *q = v + 4 * n;
    const float xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1};
    for (int i = 0; i < 4; i++)
        q[i] = (hud_vertex){xs[i], ys[i], 0, {c[0], c[1], c[2], c[3]}};
    return n + 1;
}

/* A line from (x0, y0) to (x1, y1), `width` across. */
static uint32_t add_segment(hud_vertex *v, uint32_t n, float x0, float y0, float x1, float y1, float width,
                            const uint8_t c[4])
{
    float dx = x1 - x0, dy = y1 - y0, len = sqrtf(dx * dx + dy * dy);
    if (n >= OVERLAY_MAX_QUADS || !(len > 0))
        return n;
    float nx = -dy / len * 0.5f * width, ny = dx / len * 0.5f * width;
    hud_vertex *q = v + 4 * n;
    const float xs[4] = {x0 + nx, x1 + nx, x1 - nx, x0 - nx}, ys[4] = {y0 + ny, y1 + ny, y1 - ny, y0 - ny};
    for (int i = 0; i < 4; i++)
        q[i] = (hud_vertex){xs[i], ys[i], 0, {c[0], c[1], c[2], c[3]}};
    return n + 1;
}

static float text_width(const char *text)
{
    char buf[FRAME_HUD_LINE];
    snprintf(buf, sizeof buf, "%s", text);
    return (float)stb_easy_font_width(buf);
}

static uint32_t add_text(hud_vertex *v, uint32_t n, float x, float y, const char *text, const uint8_t c[4])
{
    if (n >= OVERLAY_MAX_QUADS)
        return n;
    char buf[FRAME_HUD_LINE];
    snprintf(buf, sizeof buf, "%s", text);
    unsigned char color[4] = {c[0], c[1], c[2], c[3]};
    return n + (uint32_t)stb_easy_font_print(x, y, buf, color, v + 4 * n,
                                             (int)((OVERLAY_MAX_QUADS - n) * 4 * sizeof(hud_vertex)));
}

/* The chart at the top right of an eye ew font units wide, from y = top + 4
 * (none in an eye narrower than twice the chart): a dark panel, the title,
 * the plot with its zero line and y range, the series as lines through
 * dots, their legend, the caption. */
static uint32_t add_chart(hud_vertex *v, uint32_t n, const frame_hud_chart *c, float ew, float top)
{
    static const uint8_t panel[4] = {12, 16, 24, 215}, ink[4] = {236, 240, 245, 255}, dim[4] = {150, 158, 170, 255},
                         axis[4] = {90, 98, 112, 255};
    const float w = 176.0f, h = 92.0f, x = ew - 4.0f - w, y = top + 4.0f;
    if (ew < 2.0f * w)
        return n; /* it would hide most of a narrow eye */
    const float px0 = x + 20, px1 = x + w - 6, py0 = y + 20, py1 = y + h - 28; /* the plot */
    if (!(c->x1 > c->x0) || !(c->y1 > c->y0))
        return n;
    n = add_quad(v, n, x, y, x + w, y + h, panel);
    n = add_text(v, n, x + 4, y + 3, c->title, ink);
    float sx = (px1 - px0) / (c->x1 - c->x0), sy = (py1 - py0) / (c->y1 - c->y0);
#define CHART_X(u) (px0 + ((u) - c->x0) * sx)
#define CHART_Y(u) (py1 - ((u) - c->y0) * sy)
    char tick[16];
    snprintf(tick, sizeof tick, "%.0f", c->y1);
    n = add_text(v, n, x + 3, py0 - 3, tick, dim);
    snprintf(tick, sizeof tick, "%.0f", c->y0);
    n = add_text(v, n, x + 3, py1 - 5, tick, dim);
    n = add_segment(v, n, px0, py0, px0, py1, 1.0f, axis);
    if (c->y0 < 0 && c->y1 > 0) {
        n = add_segment(v, n, px0, CHART_Y(0.0f), px1, CHART_Y(0.0f), 1.0f, axis);
        n = add_text(v, n, x + 14, CHART_Y(0.0f) - 5, "0", dim);
    }
    float legend = px1;
    for (int s = c->series_count - 1; s >= 0; s--) { /* the legend, right to left */
        const frame_hud_series *se = &c->series[s];
        const uint8_t col[4] = {se->rgb[0], se->rgb[1], se->rgb[2], 255};
        legend -= text_width(se->label);
        n = add_text(v, n, legend, py1 + 4, se->label, col);
        legend -= 8;
    }
    for (int s = 0; s < c->series_count && s < FRAME_HUD_CHART_SERIES; s++) {
        const frame_hud_series *se = &c->series[s];
        const uint8_t col[4] = {se->rgb[0], se->rgb[1], se->rgb[2], 255};
        float lx = 0, ly = 0; /* the last point */
        for (int i = 0; i < se->count && i < FRAME_HUD_CHART_POINTS; i++) {
            float ux = CHART_X(fminf(fmaxf(se->x[i], c->x0), c->x1));
            float uy = CHART_Y(fminf(fmaxf(se->y[i], c->y0), c->y1));
            if (i)
                n = add_segment(v, n, lx, ly, ux, uy, 1.5f, col);
            n = add_quad(v, n, ux - 1.5f, uy - 1.5f, ux + 1.5f, uy + 1.5f, col);
            lx = ux, ly = uy;
        }
    }
#undef CHART_X
#undef CHART_Y
    n = add_text(v, n, x + 4, y + h - 13, c->caption, ink);
    return n;
}

void overlay_gpu_update(overlay_gpu *o, const frame_hud *hud)
{
    int slot = o->fc->slot;
    hud_vertex *v = o->vertices[slot].mapped;
    uint32_t n = 0;
    const frame_ctx *d = o->fc;
    /* Font pixels are 6 x 12 a character line: one eye pixel each up to 480
     * eye pixels across, so a 64-character line fits any eye. */
    float scale = hud && hud->scale > 0 ? hud->scale : fmaxf(1.0f, floorf((float)d->width / 480.0f));
    o->scale[slot] = scale;
    o->parallax[slot] = hud ? hud->parallax : 0.0f;
    float ew = (float)d->width / scale, eh = (float)d->height / scale; /* the eye in font units */
    static const uint8_t panel[4] = {12, 16, 24, 180}, title[4] = {255, 214, 110, 255}, text[4] = {236, 240, 245, 255};
    float panel_right = 0, panel_bottom = 0, badge_bottom = 0;
    if (hud && hud->visible && hud->line_count > 0) {
        float width = 0;
        for (int i = 0; i < hud->line_count; i++)
            width = fmaxf(width, text_width(hud->lines[i]));
        panel_right = 12 + width, panel_bottom = 8 + 12.0f * (float)hud->line_count;
        n = add_quad(v, n, 4, 4, panel_right, panel_bottom, panel);
        for (int i = 0; i < hud->line_count; i++)
            n = add_text(v, n, 8, 7 + 12.0f * (float)i, hud->lines[i], i == 0 ? title : text);
    }
    if (hud && hud->badge[0]) {
        /* A coloured tag with dark text, at the top right (under the panel
         * where a narrow eye has no room beside it). */
        float w = text_width(hud->badge), y = ew - w - 16 < panel_right + 4 ? panel_bottom + 4 : 4;
        badge_bottom = y + 16;
        const uint8_t back[4] = {hud->badge_rgb[0], hud->badge_rgb[1], hud->badge_rgb[2], 235};
        static const uint8_t ink[4] = {16, 18, 24, 255};
        n = add_quad(v, n, ew - w - 16, y, ew - 4, y + 16, back);
        n = add_text(v, n, ew - w - 10, y + 4, hud->badge, ink);
    }
    if (hud && hud->chart.visible)
        n = add_chart(v, n, &hud->chart, ew, badge_bottom);
    /* Markers: a dark outline under a coloured cross or box, the label below. */
    static const uint8_t shade[4] = {8, 10, 14, 220};
    for (int i = 0; hud && i < hud->marker_count && i < FRAME_HUD_MAX_MARKERS; i++) {
        const frame_hud_marker *m = &hud->markers[i];
        const uint8_t c[4] = {m->rgb[0], m->rgb[1], m->rgb[2], 255};
        float x = m->u * ew, y = m->v * eh;
        if (m->shape == FRAME_HUD_CROSS) {
            n = add_quad(v, n, x - 7, y - 1.5f, x + 7, y + 1.5f, shade);
            n = add_quad(v, n, x - 1.5f, y - 7, x + 1.5f, y + 7, shade);
            n = add_quad(v, n, x - 6, y - 0.5f, x + 6, y + 0.5f, c);
            n = add_quad(v, n, x - 0.5f, y - 6, x + 0.5f, y + 6, c);
        } else {
            for (int k = 0; k < 2; k++) { /* outline, then the box on it */
                float r = 8.0f - 0.5f * (float)k, t = k ? 1.0f : 2.0f;
                const uint8_t *col = k ? c : shade;
                r += k ? 0.0f : 0.5f;
                n = add_quad(v, n, x - r, y - r, x + r, y - r + t, col);
                n = add_quad(v, n, x - r, y + r - t, x + r, y + r, col);
                n = add_quad(v, n, x - r, y - r, x - r + t, y + r, col);
                n = add_quad(v, n, x + r - t, y - r, x + r, y + r, col);
            }
        }
        if (m->label[0]) {
            float w = text_width(m->label);
            n = add_quad(v, n, x - w * 0.5f - 2, y + 10, x + w * 0.5f + 2, y + 21, shade);
            n = add_text(v, n, x - w * 0.5f, y + 11, m->label, c);
        }
    }
    if (hud && hud->banner[0]) {
        float w = text_width(hud->banner), cx = ew * 0.5f, cy = eh * 0.5f;
        n = add_quad(v, n, cx - w * 0.5f - 8, cy - 10, cx + w * 0.5f + 8, cy + 12, panel);
        n = add_text(v, n, cx - w * 0.5f, cy - 4, hud->banner, title);
    }
    o->quads[slot] = n;
}

/* ------------------------------------------------------------------------- */
/* Passes                                                                    */
/* ------------------------------------------------------------------------- */

static void overlay_execute(const rg_context *ctx, void *user)
{
    const eye_pass *e = user;
    overlay_gpu *o = e->o;
    int slot = o->fc->slot;
    if (!o->quads[slot])
        return;
    const frame_ctx *d = o->fc;
    VkCommandBuffer cmd = rg_ctx_cmd(ctx);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, o->pipeline);
    VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &o->vertices[slot].buffer, &offset);
    vkCmdBindIndexBuffer(cmd, o->indices.buffer, 0, VK_INDEX_TYPE_UINT32);
    /* Parallax p: the left eye's copy p/2 to the left, the right eye's p/2 to the right. */
    float half = 0.5f * o->parallax[slot];
    hud_push push = {{2.0f / (float)d->width, 2.0f / (float)d->height}, o->scale[slot], e->eye ? half : -half};
    vkCmdPushConstants(cmd, o->layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof push, &push);
    vkCmdDrawIndexed(cmd, 6 * o->quads[slot], 1, 0, 0, 0);
}

void overlay_gpu_add(overlay_gpu *o, rg_graph *g, frame_resources *res)
{
    static const char *const names[2] = {"overlay.left", "overlay.right"};
    for (int e = 0; e < 2; e++) {
        o->pass[e] = (eye_pass){o, e};
        rg_pass p = rg_pass_add(g, &(rg_pass_desc){.name = names[e], .type = RG_PASS_GRAPHICS,
                                                   .execute = overlay_execute, .user = &o->pass[e]});
        rg_use(g, p, e ? res->right : res->left, RG_COLOR_WRITE);
    }
}

/* ------------------------------------------------------------------------- */
/* Lifetime                                                                  */
/* ------------------------------------------------------------------------- */

vg_status overlay_gpu_create(frame_ctx *fc, overlay_gpu **out)
{
    *out = NULL;
    overlay_gpu *o = calloc(1, sizeof *o);
    if (!o)
        return VG_ERR_NOMEM;
    o->fc = fc;
    gpu *g = fc->gpu;
    VkPushConstantRange push = {VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(hud_push)};
    VkPipelineLayoutCreateInfo li = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .pushConstantRangeCount = 1,
        .pPushConstantRanges = &push,
    };
    vg_status st = VG_OK;
    if (vkCreatePipelineLayout(g->device, &li, g->alloc, &o->layout) != VK_SUCCESS)
        st = VG_ERR_VULKAN;
    else
        GPU_NAME(g, VK_OBJECT_TYPE_PIPELINE_LAYOUT, o->layout, "overlay layout");
    VkShaderModule vs = 0, fs = 0;
    if (st == VG_OK) st = GPU_SHADER(g, spv_hud_vert, &vs);
    if (st == VG_OK) st = GPU_SHADER(g, spv_hud_frag, &fs);
    VkVertexInputBindingDescription vb = {0, sizeof(hud_vertex), VK_VERTEX_INPUT_RATE_VERTEX};
    VkVertexInputAttributeDescription va[2] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0},
        {1, 0, VK_FORMAT_R8G8B8A8_UNORM, 12},
    };
    static const VkFormat eye_format = VK_FORMAT_R8G8B8A8_UNORM; /* the warp's eyes */
    if (st == VG_OK)
        st = gpu_graphics_pipeline_create(g, &(gpu_graphics_desc){
            .name = "overlay", .layout = o->layout, .vert = vs, .frag = fs, .bindings = &vb, .binding_count = 1,
            .attributes = va, .attribute_count = 2, .blend = true, .color_formats = &eye_format,
            .color_count = 1}, &o->pipeline);
    if (vs)
        vkDestroyShaderModule(g->device, vs, g->alloc);
    if (fs)
        vkDestroyShaderModule(g->device, fs, g->alloc);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT && st == VG_OK; i++)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "overlay vertices",
                                                     .size = OVERLAY_MAX_QUADS * 4 * sizeof(hud_vertex),
                                                     .usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                                                     .host_visible = true}, &o->vertices[i]);
    if (st == VG_OK)
        st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "overlay quad indices",
                                                     .size = OVERLAY_MAX_QUADS * 6 * sizeof(uint32_t),
                                                     .usage = VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                                                     .host_visible = true}, &o->indices);
    if (st == VG_OK) {
        uint32_t *idx = o->indices.mapped;
        for (uint32_t q = 0; q < OVERLAY_MAX_QUADS; q++) {
            const uint32_t quad[6] = {0, 1, 2, 0, 2, 3};
            for (int k = 0; k < 6; k++)
                idx[6 * q + (uint32_t)k] = 4 * q + quad[k];
        }
    }
    if (st != VG_OK) {
        overlay_gpu_destroy(o);
        return st;
    }
    *out = o;
    return VG_OK;
}

void overlay_gpu_destroy(overlay_gpu *o)
{
    if (!o)
        return;
    gpu *g = o->fc->gpu;
    if (o->pipeline)
        vkDestroyPipeline(g->device, o->pipeline, g->alloc);
    if (o->layout)
        vkDestroyPipelineLayout(g->device, o->layout, g->alloc);
    for (int i = 0; i < VG_FRAMES_IN_FLIGHT; i++)
        gpu_buffer_destroy(g, &o->vertices[i]);
    gpu_buffer_destroy(g, &o->indices);
    free(o);
}
