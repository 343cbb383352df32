/* vergence — what the frame shares with its pass modules.
 *
 * A pass module (gbuffer, disparity, warp, compose) owns its pipelines and
 * persistent resources, made by X_gpu_create() from the frame_ctx and, where
 * it has settings, its own desc (X_gpu_desc, the frame fills it in), and
 * adds its passes to the frame graph in X_gpu_add(), reading and writing
 * named resources of frame_resources. Its execute callbacks read per-frame
 * state (slot, times, cameras) from the frame_ctx, which lives as long as
 * the frame. */
#pragma once
#include "core/camera.h"
#include "frame_types.h"
#include "gpu/gpu.h"
#include "graph/graph.h"
#include "stereo/stereo_display.h"

/* The scene and its GPU copy belong to the modules that draw it (render/,
 * the frame): the kit names them only, so a module of the kit that draws no
 * scene (the disparity and screen-space passes, the SDK) links none. */
struct scene;
struct scene_gpu;

typedef struct frame_ctx {
    gpu *gpu;
    const struct scene *scene;
    uint32_t width, height;      /* the centre image and each eye, pixels */
    int camera;                  /* the scene camera it renders (node order) */
    struct scene_gpu *sg;        /* the frame's (render/scene_gpu.h) */
    gpu_buffer ubo[VG_FRAMES_IN_FLIGHT];    /* vg_frame_ubo per slot */
    VkDescriptorSetLayout push_layout;      /* set 0: frame UBO (0), shadow map (1), pass images (2..) */
    VkPipelineLayout scene_layout;          /* set 0 push + set 1 textures + vg_draw_push */
    VkSampler shadow_sampler, linear_clamp, nearest_clamp;
    stereo_display display;
    stereo_camera rig;

    /* Per frame. */
    int slot;
    frame_times times;
    vg_camera cam, cam_prev, cam_next;
    int shadow_cascades;     /* cascades the shadow pass draws (1 or VG_SHADOW_CASCADES: shadow_gpu_setup) */
} frame_ctx;

/* Resources of the frame graph, by name, for pass modules to connect. */
typedef struct frame_resources {
    rg_res ubo, vertices, statics, indices;                /* imported scene streams */
    rg_res shadow;                                         /* sun shadow map: the cascades' atlas */
    rg_res color, depth, ids, motion, zbuffer;             /* G-buffer (centre eye) */
    rg_res g, h, f;                                        /* vergence maps, arcmin (R32F) */
    rg_res curve;                                          /* global depth -> vergence curve */
    rg_res left, right, left_aux, right_aux;               /* eyes: colour, (centre x, y, error px, stage) */
    rg_res ref_left, ref_right;                            /* two-camera reference eyes */
    rg_res stereo;                                         /* composed output */
} frame_resources;

/* The original rig and the display as the shaders read them (vg_frame_ubo's
 * rig and display; stereo.glsl, include/vergence/display.glsl), for images
 * `width` pixels wide: the frame's constants and the SDK's alike. */
struct vg_frame_ubo;
void frame_ctx_ubo_stereo(struct vg_frame_ubo *u, const stereo_camera *rig, const stereo_display *display,
                          uint32_t width);

/* Pushes the frame UBO (binding 0) and, when shadow is non-null, the shadow
 * map (binding 1) for a scene pipeline. */
void frame_ctx_push_scene(const frame_ctx *fc, const rg_context *ctx, rg_res shadow);
