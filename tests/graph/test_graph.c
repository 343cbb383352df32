/* Frame-graph compile tests: pure data, no GPU (Filament's approach: run
 * graphs without a device and check what the compile step decided). */
#include <stdlib.h>
#include <unistd.h>

#include "graph/graph.h"
#include "test.h"

#define IMG(g, n, f, w, h) rg_image((g), &(rg_image_desc){.name = (n), .format = (f), .width = (w), .height = (h)})
#define BUF(g, n, s) rg_buffer((g), &(rg_buffer_desc){.name = (n), .size = (s)})
#define PASS(g, n, t) rg_pass_add((g), &(rg_pass_desc){.name = (n), .type = (t)})

static const rg_barrier *find_barrier(const rg_graph *g, uint32_t slot, rg_res res)
{
    uint32_t n;
    const rg_barrier *b = rg_barriers(g, slot, &n);
    for (uint32_t i = 0; i < n; i++)
        if (b[i].res.id == res.id)
            return &b[i];
    return NULL;
}

static uint32_t order_of(const rg_graph *g, rg_pass p)
{
    for (uint32_t i = 0; i < rg_order_count(g); i++)
        if (rg_order_pass(g, i).id == p.id)
            return i;
    return UINT32_MAX;
}

/* A pass whose output nobody reads disappears, and so does the chain that
 * only fed it; side effects and exported results keep passes alive. */
static int test_cull(void)
{
    rg_graph *g = rg_create();
    rg_res a = IMG(g, "a", VK_FORMAT_R32_SFLOAT, 64, 64);
    rg_res b = IMG(g, "b", VK_FORMAT_R32_SFLOAT, 64, 64);
    rg_res dbg = IMG(g, "debug", VK_FORMAT_R32_SFLOAT, 64, 64);
    rg_res dbg2 = IMG(g, "debug2", VK_FORMAT_R32_SFLOAT, 64, 64);
    rg_pass pa = PASS(g, "make-a", RG_PASS_COMPUTE);
    rg_use(g, pa, a, RG_STORAGE_WRITE);
    rg_pass pb = PASS(g, "a-to-b", RG_PASS_COMPUTE);
    rg_use(g, pb, a, RG_SAMPLED);
    rg_use(g, pb, b, RG_STORAGE_WRITE);
    rg_pass pd = PASS(g, "debug", RG_PASS_COMPUTE);
    rg_use(g, pd, a, RG_SAMPLED);
    rg_use(g, pd, dbg, RG_STORAGE_WRITE);
    rg_pass pd2 = PASS(g, "debug-of-debug", RG_PASS_COMPUTE);
    rg_use(g, pd2, dbg, RG_SAMPLED);
    rg_use(g, pd2, dbg2, RG_STORAGE_WRITE);
    rg_pass ps = rg_pass_add(g, &(rg_pass_desc){.name = "hud", .type = RG_PASS_COMPUTE, .side_effects = true});
    rg_export(g, b);
    CHECK(rg_compile(g) == VG_OK, "compile failed");
    CHECK(!rg_pass_culled(g, pa) && !rg_pass_culled(g, pb), "the exported chain was culled");
    CHECK(rg_pass_culled(g, pd) && rg_pass_culled(g, pd2), "debug passes nobody reads survived");
    CHECK(!rg_pass_culled(g, ps), "a pass with side effects was culled");
    CHECK(rg_order_count(g) == 3, "%u passes survive, expected 3", rg_order_count(g));
    CHECK(rg_res_physical(g, dbg) == UINT32_MAX, "a culled resource got memory");
    rg_destroy(g);
    return 0;
}

/* Order follows the hazards and keeps declaration order among independent passes. */
static int test_order(void)
{
    rg_graph *g = rg_create();
    rg_res x = BUF(g, "x", 256), y = BUF(g, "y", 256), z = BUF(g, "z", 256);
    rg_pass p0 = PASS(g, "x", RG_PASS_COMPUTE);
    rg_use(g, p0, x, RG_STORAGE_WRITE);
    rg_pass p1 = PASS(g, "y", RG_PASS_COMPUTE);
    rg_use(g, p1, y, RG_STORAGE_WRITE);
    rg_pass p2 = PASS(g, "z=x+y", RG_PASS_COMPUTE);
    rg_use(g, p2, x, RG_STORAGE_READ);
    rg_use(g, p2, y, RG_STORAGE_READ);
    rg_use(g, p2, z, RG_STORAGE_WRITE);
    rg_pass p3 = PASS(g, "x again", RG_PASS_COMPUTE); /* WAR on x after p2 */
    rg_use(g, p3, x, RG_STORAGE_READ_WRITE);
    rg_use(g, p3, z, RG_STORAGE_READ);
    rg_export(g, x);
    CHECK(rg_compile(g) == VG_OK, "compile failed");
    CHECK(order_of(g, p0) == 0 && order_of(g, p1) == 1 && order_of(g, p2) == 2 && order_of(g, p3) == 3,
          "order %u %u %u %u", order_of(g, p0), order_of(g, p1), order_of(g, p2), order_of(g, p3));
    /* p3 writes x that p2 read: a write-after-read barrier with no access to flush. */
    const rg_barrier *war = find_barrier(g, 3, x);
    CHECK(war && war->src_stage == VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT && war->src_access == 0,
          "WAR barrier on x missing or wrong");
    rg_destroy(g);
    return 0;
}

/* Layout transitions and access masks come from the declared usages. */
static int test_barriers(void)
{
    rg_graph *g = rg_create();
    rg_res color = IMG(g, "color", VK_FORMAT_R8G8B8A8_UNORM, 320, 180);
    rg_res depth = IMG(g, "depth", VK_FORMAT_D32_SFLOAT, 320, 180);
    rg_res out = BUF(g, "out", 320 * 180 * 4);
    rg_res readback = rg_import_buffer(g, &(rg_buffer_desc){.name = "readback", .size = 320 * 180 * 4},
                                       &(rg_import_desc){.final = RG_HOST_READ});
    rg_pass draw = PASS(g, "draw", RG_PASS_GRAPHICS);
    rg_use_clear(g, draw, color, RG_COLOR_WRITE, (VkClearValue){0});
    rg_use_clear(g, draw, depth, RG_DEPTH_WRITE, (VkClearValue){.depthStencil = {1, 0}});
    rg_pass post = PASS(g, "post", RG_PASS_COMPUTE);
    rg_use(g, post, color, RG_SAMPLED);
    rg_use(g, post, depth, RG_SAMPLED);
    rg_use(g, post, out, RG_STORAGE_WRITE);
    rg_pass post2 = PASS(g, "post2", RG_PASS_COMPUTE); /* read after read: no barrier */
    rg_use(g, post2, color, RG_SAMPLED);
    rg_use(g, post2, out, RG_STORAGE_READ_WRITE);
    rg_pass copy = PASS(g, "copy", RG_PASS_TRANSFER);
    rg_use(g, copy, out, RG_TRANSFER_SRC);
    rg_use(g, copy, readback, RG_TRANSFER_DST);
    CHECK(rg_compile(g) == VG_OK, "compile failed");

    const rg_barrier *b = find_barrier(g, 0, color);
    CHECK(b && b->old_layout == VK_IMAGE_LAYOUT_UNDEFINED &&
              b->new_layout == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
          "colour attachment does not start from UNDEFINED");
    b = find_barrier(g, 1, color);
    CHECK(b && b->old_layout == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL &&
              b->new_layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL &&
              b->src_stage == VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT &&
              (b->src_access & VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT) &&
              b->dst_stage == VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT &&
              b->dst_access == VK_ACCESS_2_SHADER_SAMPLED_READ_BIT,
          "colour -> sampled barrier wrong");
    b = find_barrier(g, 1, depth);
    CHECK(b && b->new_layout == VK_IMAGE_LAYOUT_DEPTH_READ_ONLY_OPTIMAL &&
              (b->src_stage & VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT),
          "depth -> sampled barrier wrong");
    CHECK(!find_barrier(g, 2, color), "read after read in the same layout needs no barrier");
    b = find_barrier(g, 2, out);
    CHECK(b && !b->is_image && b->src_access == VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT &&
              (b->dst_access & VK_ACCESS_2_SHADER_STORAGE_READ_BIT),
          "storage RAW barrier wrong");
    b = find_barrier(g, 3, out);
    CHECK(b && b->dst_stage == VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT && b->dst_access == VK_ACCESS_2_TRANSFER_READ_BIT,
          "storage -> transfer barrier wrong");
    b = find_barrier(g, rg_order_count(g), readback);
    CHECK(b && b->src_access == VK_ACCESS_2_TRANSFER_WRITE_BIT && b->dst_stage == VK_PIPELINE_STAGE_2_HOST_BIT &&
              b->dst_access == VK_ACCESS_2_HOST_READ_BIT,
          "readback has no end-of-frame barrier to the host");
    /* Next frame: the transient colour image starts over, after last frame's reads. */
    b = find_barrier(g, 0, color);
    CHECK(b->src_stage & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
          "first use does not wait for the previous frame's last use (src %llx)",
          (unsigned long long)b->src_stage);
    rg_destroy(g);
    return 0;
}

static int expect_invalid(rg_graph *g, const char *what);

/* A work list: one step appends to it, the next dispatches from it
 * indirectly and consumes it (indirect-storage), a third reads what that
 * one wrote. Each gets a barrier that covers the indirect read too. */
static int test_work_list(void)
{
    rg_graph *g = rg_create();
    rg_res list = rg_import_buffer(g, &(rg_buffer_desc){.name = "work list", .size = 4096},
                                   &(rg_import_desc){.initial = RG_STORAGE_READ_WRITE,
                                                     .final = RG_STORAGE_READ_WRITE});
    rg_pass append = PASS(g, "append", RG_PASS_COMPUTE);
    rg_use(g, append, list, RG_STORAGE_READ_WRITE);
    rg_pass consume = PASS(g, "consume", RG_PASS_COMPUTE);
    rg_use(g, consume, list, RG_INDIRECT_STORAGE);
    rg_pass after = rg_pass_add(g, &(rg_pass_desc){.name = "after", .type = RG_PASS_COMPUTE, .side_effects = true});
    rg_use(g, after, list, RG_STORAGE_READ);
    CHECK(rg_compile(g) == VG_OK, "compile failed");
    CHECK(rg_order_count(g) == 3, "%u passes kept", rg_order_count(g));
    const rg_barrier *b = find_barrier(g, 1, list);
    CHECK(b && !b->is_image && (b->src_stage & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT) &&
              (b->src_access & VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT) &&
              (b->dst_stage & VK_PIPELINE_STAGE_2_DRAW_INDIRECT_BIT) &&
              (b->dst_stage & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT) &&
              (b->dst_access & VK_ACCESS_2_INDIRECT_COMMAND_READ_BIT) &&
              (b->dst_access & VK_ACCESS_2_SHADER_STORAGE_READ_BIT),
          "append -> indirect dispatch: no barrier to the indirect read (dst stage %llx access %llx)",
          b ? (unsigned long long)b->dst_stage : 0ull, b ? (unsigned long long)b->dst_access : 0ull);
    b = find_barrier(g, 2, list);
    CHECK(b && (b->src_access & VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT) &&
              (b->dst_access & VK_ACCESS_2_SHADER_STORAGE_READ_BIT),
          "the consumer writes the list too: the reader after it waits");
    rg_destroy(g);
    /* Declared on an image, it is refused. */
    g = rg_create();
    rg_res img = IMG(g, "img", VK_FORMAT_R32_UINT, 8, 8);
    rg_pass w = PASS(g, "w", RG_PASS_COMPUTE);
    rg_use(g, w, img, RG_STORAGE_WRITE);
    rg_pass r = PASS(g, "r", RG_PASS_COMPUTE);
    rg_use(g, r, img, RG_INDIRECT_STORAGE);
    rg_export(g, img);
    return expect_invalid(g, "indirect-storage on an image"); /* it destroys g */
}

/* Transient resources of the same shape with disjoint lifetimes share memory. */
static int test_transient_reuse(void)
{
    rg_graph *g = rg_create();
    rg_res a = IMG(g, "a", VK_FORMAT_R32_SFLOAT, 128, 128);
    rg_res b = IMG(g, "b", VK_FORMAT_R32_SFLOAT, 128, 128);
    rg_res c = IMG(g, "c", VK_FORMAT_R32_SFLOAT, 128, 128);
    rg_res d = IMG(g, "d", VK_FORMAT_R16_SFLOAT, 128, 128); /* other format: never shares */
    rg_res e = IMG(g, "e", VK_FORMAT_R32_SFLOAT, 128, 128);
    rg_pass p0 = PASS(g, "p0", RG_PASS_COMPUTE);
    rg_use(g, p0, a, RG_STORAGE_WRITE);
    rg_pass p1 = PASS(g, "p1", RG_PASS_COMPUTE);
    rg_use(g, p1, a, RG_SAMPLED);
    rg_use(g, p1, b, RG_STORAGE_WRITE);
    rg_pass p2 = PASS(g, "p2", RG_PASS_COMPUTE);
    rg_use(g, p2, b, RG_SAMPLED);
    rg_use(g, p2, c, RG_STORAGE_WRITE); /* a is dead here: c can take its place */
    rg_use(g, p2, d, RG_STORAGE_WRITE);
    rg_pass p3 = PASS(g, "p3", RG_PASS_COMPUTE);
    rg_use(g, p3, c, RG_SAMPLED);
    rg_use(g, p3, d, RG_SAMPLED);
    rg_use(g, p3, e, RG_STORAGE_WRITE);
    rg_export(g, e);
    CHECK(rg_compile(g) == VG_OK, "compile failed");
    uint32_t pa = rg_res_physical(g, a), pb = rg_res_physical(g, b), pc = rg_res_physical(g, c);
    uint32_t pd = rg_res_physical(g, d), pe = rg_res_physical(g, e);
    CHECK(pa == pc, "c does not reuse a (%u vs %u)", pc, pa);
    CHECK(pa != pb, "a and b overlap but share %u", pa);
    CHECK(pd != pa && pd != pb && pd != pc, "a different format was aliased");
    CHECK(pe == pb, "e (exported) should take b, dead after p2 (%u vs %u)", pe, pb);
    CHECK(rg_physical_count(g) == 3, "%u physical resources, expected 3", rg_physical_count(g));
    /* Taking over memory discards it: UNDEFINED after the previous owner's reads. */
    const rg_barrier *bar = find_barrier(g, 2, c);
    CHECK(bar && bar->old_layout == VK_IMAGE_LAYOUT_UNDEFINED &&
              (bar->src_stage & VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT),
          "aliased first use has no discard barrier after the previous owner");
    rg_destroy(g);
    return 0;
}

static int expect_invalid(rg_graph *g, const char *what)
{
    vg_status st = rg_compile(g);
    rg_destroy(g);
    CHECK(st == VG_ERR_GRAPH, "%s was accepted (status %d)", what, st);
    return 0;
}

/* Invalid graphs fail to compile with one message, they never half-run. */
static int test_validate(void)
{
    rg_graph *g = rg_create();
    rg_res a = IMG(g, "a", VK_FORMAT_R32_SFLOAT, 64, 64);
    rg_pass p = PASS(g, "reader", RG_PASS_COMPUTE);
    rg_use(g, p, a, RG_SAMPLED);
    if (expect_invalid(g, "a read before any write"))
        return 1;

    g = rg_create();
    rg_res c = IMG(g, "c", VK_FORMAT_R8G8B8A8_UNORM, 64, 64);
    rg_res d = IMG(g, "d", VK_FORMAT_D32_SFLOAT, 32, 32);
    p = PASS(g, "draw", RG_PASS_GRAPHICS);
    rg_use(g, p, c, RG_COLOR_WRITE);
    rg_use(g, p, d, RG_DEPTH_WRITE);
    if (expect_invalid(g, "attachments of different sizes"))
        return 1;

    g = rg_create();
    c = IMG(g, "c", VK_FORMAT_R8G8B8A8_UNORM, 64, 64);
    p = PASS(g, "draw", RG_PASS_GRAPHICS);
    rg_use(g, p, c, RG_DEPTH_WRITE);
    if (expect_invalid(g, "a colour format as depth"))
        return 1;

    g = rg_create();
    c = IMG(g, "c", VK_FORMAT_R8G8B8A8_UNORM, 64, 64);
    p = PASS(g, "compute", RG_PASS_COMPUTE);
    rg_use(g, p, c, RG_COLOR_WRITE);
    if (expect_invalid(g, "an attachment in a compute pass"))
        return 1;

    g = rg_create();
    rg_res b = BUF(g, "b", 16);
    p = PASS(g, "twice", RG_PASS_COMPUTE);
    rg_use(g, p, b, RG_STORAGE_WRITE);
    rg_use(g, p, b, RG_STORAGE_READ);
    if (expect_invalid(g, "one resource declared twice by a pass"))
        return 1;

    g = rg_create();
    b = BUF(g, "b", 16);
    p = PASS(g, "sample a buffer", RG_PASS_COMPUTE);
    rg_use(g, p, b, RG_SAMPLED);
    return expect_invalid(g, "a buffer used as a sampled image");
}

/* Attachments without a clear load what an earlier pass drew. */
static int test_attachment_load(void)
{
    rg_graph *g = rg_create();
    rg_res c = IMG(g, "c", VK_FORMAT_R8G8B8A8_UNORM, 64, 64);
    rg_pass sky = PASS(g, "sky", RG_PASS_GRAPHICS);
    rg_use(g, sky, c, RG_COLOR_WRITE);
    rg_pass geo = PASS(g, "geometry", RG_PASS_GRAPHICS);
    rg_use(g, geo, c, RG_COLOR_WRITE);
    rg_export(g, c);
    CHECK(rg_compile(g) == VG_OK, "compile failed");
    CHECK(!rg_pass_culled(g, sky), "the pass under a loading attachment was culled");
    const rg_barrier *b = find_barrier(g, 1, c);
    CHECK(b && b->old_layout == VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL &&
              (b->src_access & VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT) &&
              (b->dst_access & VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT),
          "write-after-write on an attachment needs a barrier");
    rg_destroy(g);
    return 0;
}

/* The dumps name every pass, resource and barrier. */
static int test_dump(void)
{
    rg_graph *g = rg_create();
    rg_res c = IMG(g, "gbuffer.color", VK_FORMAT_R8G8B8A8_SRGB, 64, 64);
    rg_pass p = PASS(g, "gbuffer", RG_PASS_GRAPHICS);
    rg_use_clear(g, p, c, RG_COLOR_WRITE, (VkClearValue){0});
    rg_export(g, c);
    CHECK(rg_compile(g) == VG_OK, "compile failed");
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    rg_dump_text(g, f);
    fclose(f);
    CHECK(strstr(text, "gbuffer") && strstr(text, "gbuffer.color") && strstr(text, "COLOR_ATTACHMENT"),
          "text dump lacks names:\n%s", text);
    free(text);
    char dot[] = "/tmp/vergence_graph_XXXXXX";
    int fd = mkstemp(dot);
    CHECK(fd >= 0, "no temporary file");
    close(fd);
    CHECK(rg_dump_dot(g, dot) == VG_OK, "dot dump failed");
    FILE *d = fopen(dot, "r");
    char buf[4096] = {0};
    size_t n = fread(buf, 1, sizeof buf - 1, d);
    fclose(d);
    remove(dot);
    CHECK(n > 0 && strstr(buf, "digraph") && strstr(buf, "gbuffer.color"), "dot dump wrong:\n%s", buf);
    rg_destroy(g);
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {
        {"cull", test_cull},
        {"order", test_order},
        {"barriers", test_barriers},
        {"work_list", test_work_list},
        {"transient_reuse", test_transient_reuse},
        {"validate", test_validate},
        {"attachment_load", test_attachment_load},
        {"dump", test_dump},
    };
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
