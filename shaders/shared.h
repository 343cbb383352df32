/* vergence — constants and struct layouts shared by C and GLSL.
 *
 * Both sides use scalar block layout (VK_EXT_scalar_block_layout, core in
 * Vulkan 1.2), so a struct here has the same bytes in C and in a shader.
 * Keep every member 4-byte scalar or built from them; order members from
 * large to small to keep C's natural alignment equal to scalar layout. */
#ifndef VG_SHARED_H
#define VG_SHARED_H

#ifdef GL_core_profile
#define VG_STRUCT(name) struct name
#define VG_VEC2 vec2
#define VG_VEC4 vec4
#define VG_MAT4 mat4
#define VG_UINT uint
#else
#include <stdint.h>
typedef struct vg_gvec2 { float v[2]; } vg_gvec2;
typedef struct vg_gvec4 { float v[4]; } vg_gvec4;
typedef struct vg_gmat4 { float m[16]; } vg_gmat4; /* column-major, as GLSL */
#define VG_STRUCT(name) typedef struct name name; struct name
#define VG_VEC2 vg_gvec2
#define VG_VEC4 vg_gvec4
#define VG_MAT4 vg_gmat4
#define VG_UINT uint32_t
#endif

/* Base-colour textures bound at once (must equal SCENE_MAX_TEXTURES). */
#define VG_MAX_TEXTURES 16

/* G-buffer colour attachments, in this order. */
#define VG_GBUFFER_COLOR 0   /* RGBA8 sRGB: lit colour, alpha = saliency */
#define VG_GBUFFER_DEPTH 1   /* R32F: linear depth along the view axis, metres */
#define VG_GBUFFER_ID 2      /* R32UI: instance id, 0 = background */
#define VG_GBUFFER_MOTION 3  /* RGBA32F: pixels to previous keyframe (xy), to next keyframe (zw) */

/* Per-frame constants of the scene passes. */
VG_STRUCT(vg_frame_ubo) {
    VG_MAT4 view_proj;        /* world -> clip at the frame's time */
    VG_MAT4 view_proj_prev;   /* at the previous keyframe's time */
    VG_MAT4 view_proj_next;   /* at the next keyframe's time */
    VG_MAT4 view;             /* world -> view (linear depth = -z) */
    VG_MAT4 inv_view_proj;    /* clip -> world, for the sky */
    VG_MAT4 light_view_proj;  /* world -> shadow map clip */
    VG_VEC4 camera_pos;       /* xyz eye; w = far plane (background depth) */
    VG_VEC4 sun_dir;          /* xyz unit vector toward the sun; w = shadow texel size (world) */
    VG_VEC4 sun_color;        /* rgb radiance; w = ambient strength */
    VG_VEC4 sky_zenith;       /* rgb; w = fog density (1/m) */
    VG_VEC4 sky_horizon;      /* rgb; w = exposure */
    VG_VEC4 ground_color;     /* rgb bounce light from below; w unused */
    VG_VEC4 viewport;         /* width, height, 1/width, 1/height */
};

/* Per-draw push constants. */
VG_STRUCT(vg_draw_push) {
    VG_VEC4 base_color;       /* linear RGBA factor */
    VG_UINT instance_id;      /* 1-based */
    float saliency;           /* 0..1 */
    int texture_index;        /* index into the texture array, -1 for none */
    VG_UINT flags;            /* unused, 0 */
};

#endif
