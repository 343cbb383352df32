/* vergence — a camera resolved for one time: what the scene's cameras
 * resolve to (scene/camera.c) and what every pass reads, the scene's or
 * not (pass/frame_ctx.h), so a pass that draws no scene needs no scene. */
#pragma once
#include <stdbool.h>

/* A resolved view at one time: Vulkan clip space (y down, depth 0..1). */
typedef struct vg_camera {
    float view[16];          /* world -> view (right-handed, looking down -Z) */
    float proj[16];          /* view -> clip */
    float view_proj[16];
    float position[3];       /* eye in world space */
    float forward[3], right[3], up[3]; /* unit axes in world space */
    float yfov, aspect, znear, zfar; /* zfar is always finite here */
    int source_node;         /* camera node, -1 for the automatic framing */
    bool orthographic;       /* added by the scene module: proj is orthographic (yfov 0) */
    float ymag;              /* orthographic half height in world units (0 for perspective) */
} vg_camera;
