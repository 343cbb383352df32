/* vergence — a one-frame graph for testing GPU passes on given inputs:
 * images uploaded from host memory, the passes under test, images read back.
 * Everything goes through the frame graph (it derives every barrier), so
 * synchronization validation sees what the frame would do. */
#pragma once
#include <stdbool.h>
#include <stdint.h>

#include "gpu/gpu.h"
#include "graph/graph.h"

#define HARNESS_MAX_IMAGES 16

typedef struct harness_image {
    rg_res res;
    uint32_t width, height, texel;
    VkDeviceSize offset;   /* in the host buffer */
    bool upload, download;
} harness_image;

typedef struct harness {
    gpu *gpu;
    rg_graph *graph;
    gpu_buffer host;
    rg_res r_host;
    harness_image images[HARNESS_MAX_IMAGES];
    int count;
    VkDeviceSize size;
} harness;

/* GPU (validation from VERGENCE_VALIDATE) and an empty graph. */
int harness_open(harness *h);
/* An image of the graph; upload: filled from the host before the passes;
 * download: copied to the host after them. */
rg_res harness_image_add(harness *h, const char *name, VkFormat format, uint32_t w, uint32_t hgt, bool upload,
                         bool download);
/* After every image was added, before the passes under test: the host
 * buffer and the upload pass. */
int harness_upload(harness *h);
/* After the passes under test were added: the download pass, compile, realize. */
int harness_build(harness *h);
/* Host memory of an image (valid after harness_build). */
void *harness_data(harness *h, rg_res image);
/* Records the graph once and waits. */
int harness_run(harness *h);
/* Destroys everything; returns the process's validation message count. */
int harness_close(harness *h);
