/* vergence — the validation counter sees what it must (issue 8): every test
 * trusts "0 validation messages", so prove the count rises on a deliberate
 * error, and that synchronization validation is really on in gpu_create's
 * path (a hazard it alone reports is counted, and is not with
 * VERGENCE_SYNC_VALIDATION=0). Run one case: test_validation_gpu NAME. */
#include <stdio.h>
#include <stdlib.h>

#include "gpu/gpu.h"
#include "test.h"

/* A zero-size buffer: core validation (VUID-VkBufferCreateInfo-size-00912). */
static int counter(void)
{
    gpu *g;
    CHECK(gpu_create(&(gpu_desc){.validate = true}, &g) == VG_OK, "gpu_create");
    CHECK(g->validation, "validation is off");
    int before = gpu_validation_messages();
    VkBuffer b = VK_NULL_HANDLE;
    VkResult r = vkCreateBuffer(g->device, &(VkBufferCreateInfo){
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO, .size = 0, .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE}, NULL, &b);
    if (r == VK_SUCCESS && b)
        vkDestroyBuffer(g->device, b, NULL);
    int raised = gpu_validation_messages() - before;
    gpu_destroy(g);
    printf("zero-size buffer: %d validation message(s) (%s)\n", raised, gpu_result_text(r));
    CHECK(raised >= 1, "a zero-size buffer went unreported");
    return 0;
}

/* Two transfer writes to one buffer with no barrier between them: a
 * write-after-write hazard only synchronization validation reports. Returns
 * the messages it raised, or -1. */
static int hazard(void)
{
    gpu *g;
    if (gpu_create(&(gpu_desc){.validate = true}, &g) != VG_OK)
        return -1;
    int before = gpu_validation_messages();
    gpu_buffer b;
    VkCommandBuffer cmd;
    vg_status st = gpu_buffer_create(g, &(gpu_buffer_desc){.name = "hazard", .size = 256,
                                                            .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT}, &b);
    if (st == VG_OK && (st = gpu_oneshot_begin(g, &cmd)) == VG_OK) {
        vkCmdFillBuffer(cmd, b.buffer, 0, VK_WHOLE_SIZE, 1);
        vkCmdFillBuffer(cmd, b.buffer, 0, VK_WHOLE_SIZE, 2); /* no barrier: WRITE-AFTER-WRITE */
        st = gpu_oneshot_submit(g, cmd);
    }
    if (st == VG_OK)
        gpu_buffer_destroy(g, &b);
    int raised = gpu_validation_messages() - before;
    printf("write-after-write, sync validation %s: %d validation message(s)\n", g->sync_validation ? "on" : "off",
           raised);
    gpu_destroy(g);
    return st == VG_OK ? raised : -1;
}

static int sync(void)
{
    unsetenv("VERGENCE_SYNC_VALIDATION"); /* the default: on with validation */
    int on = hazard();
    CHECK(on >= 1, "synchronization validation missed a write-after-write hazard (%d)", on);
    setenv("VERGENCE_SYNC_VALIDATION", "0", 1);
    int off = hazard();
    unsetenv("VERGENCE_SYNC_VALIDATION");
    CHECK(off == 0, "without synchronization validation the hazard still gave %d message(s)", off);
    return 0;
}

int main(int argc, char **argv)
{
    static const vg_test_case cases[] = {{"counter", counter}, {"sync", sync}};
    return vg_test_main(argc, argv, cases, VG_TEST_COUNT(cases));
}
