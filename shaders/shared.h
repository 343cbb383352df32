/* vergence — constants and struct layouts shared by the engine's C and GLSL,
 * in vergence/lang.h's subset of both (the warp's public share, stage ids
 * and the curve, is vergence/warp_shared.h).
 *
 * Both sides use scalar block layout (VK_EXT_scalar_block_layout, core in
 * Vulkan 1.2), so a struct here has the same bytes in C and in a shader.
 * Keep every member 4-byte scalar or built from them; order members from
 * large to small to keep C's natural alignment equal to scalar layout. */
#ifndef VG_SHARED_H
#define VG_SHARED_H

#include "vergence/warp_shared.h"

/* A work list one kernel appends to and indirect dispatches of
 * VG_WORKLIST_GROUP-invocation workgroups then cover (warp.edges' buckets,
 * warp.fill's candidates). Its header is a uvec4: the count, then the
 * dispatch size over it, which starts at VG_WORKLIST_EMPTY; the dispatch
 * size is at byte VG_WORKLIST_ARGS(slot) of an array of headers. */
#define VG_WORKLIST_GROUP 64u
#define VG_WORKLIST_ARGS(slot) ((slot) * 4u * 4u + 4u)
#ifdef GL_core_profile
#define VG_WORKLIST_EMPTY uvec4(0u, 0u, 1u, 1u)
/* index = the new item's place; the last workgroup grows when it starts one. */
#define VG_WORKLIST_APPEND(header, index)                    \
    {                                                        \
        index = atomicAdd((header).x, 1u);                   \
        if (index % VG_WORKLIST_GROUP == 0u)                 \
            atomicAdd((header).y, 1u);                       \
    }
#endif

/* Base-colour textures bound at once (must equal SCENE_MAX_TEXTURES). */
#define VG_MAX_TEXTURES 16

/* G-buffer colour attachments, in this order. */
#define VG_GBUFFER_COLOR 0   /* RGBA8 UNORM holding sRGB-encoded colour, alpha = saliency */
#define VG_GBUFFER_DEPTH 1   /* R32F: linear depth along the view axis, metres */
#define VG_GBUFFER_ID 2      /* R32UI: instance id, 0 = background */
#define VG_GBUFFER_MOTION 3  /* RGBA32F: pixels to previous keyframe (xy), to next keyframe (zw) */

/* Per-frame constants of the scene passes. */
VGX_STRUCT(vg_frame_ubo) {
    VGX_MAT4 view_proj;        /* world -> clip at the frame's time */
    VGX_MAT4 view_proj_prev;   /* at the previous keyframe's time */
    VGX_MAT4 view_proj_next;   /* at the next keyframe's time */
    VGX_MAT4 view;             /* world -> view (linear depth = -z) */
    VGX_MAT4 inv_view_proj;    /* clip -> world, for the sky */
    VGX_MAT4 light_view_proj[2]; /* world -> shadow clip of each cascade: [0] the whole scene, [1] the near one */
    VGX_VEC4 camera_pos;       /* xyz eye; w = far plane (background depth) */
    VGX_VEC4 sun_dir;          /* xyz unit vector toward the sun; w unused */
    VGX_VEC4 shadow;           /* x: view depth (m) below which the near cascade shades (0: one cascade);
                                 y, z: texel of cascade 0 / 1 in world metres; w unused */
    VGX_VEC4 sun_color;        /* rgb radiance; w = ambient strength */
    VGX_VEC4 sky_zenith;       /* rgb; w = fog density (1/m) */
    VGX_VEC4 sky_horizon;      /* rgb; w = exposure */
    VGX_VEC4 ground_color;     /* rgb bounce light from below; w unused */
    VGX_VEC4 viewport;         /* width, height, 1/width, 1/height */
    VGX_MAT4 eye_view_proj[2]; /* off-axis cameras of the original rig: left, right */
    VGX_VEC4 rig;              /* gain K (image px), convergence c (m), interaxial b (m), unused */
    VGX_VEC4 display;          /* ipd e (m), distance D (m), metres per image pixel, screen vergence (arcmin) */
    VGX_VEC4 warp;             /* tess px (0 = off), tess error px (0 = off), depth epsilon (relative), Halton radius px */
    VGX_VEC4 warp2;            /* max tessellation level, specular (1) or diffuse only (0), measure (1), unused */
    VGX_VEC4 saliency;         /* computed saliency (gbuffer.glsl): rgb the scene's mean base colour
                                 (linear), w its depth scale (m: the camera's distance to its centre) */
};

/* Push-descriptor bindings of set 0 shared by the scene pipelines. */
#define VG_BINDING_FRAME 0    /* vg_frame_ubo */
#define VG_BINDING_SHADOW 1   /* sampler2DShadow */
#define VG_BINDING_DEPTH 2    /* sampler2D: centre linear depth (nearest) */
#define VG_BINDING_TARGET 3   /* sampler2D: target vergence, arcmin (nearest) */
#define VG_BINDING_CURVE 4    /* storage buffer: vgx_curve_data */
/* VG_BINDING_TESS_LEVELS (16): storage buffer, the warp's edge levels */

/* vg_draw_push.flags */
#define VG_DRAW_RIGHT_EYE 1u  /* warp/cameras: render the right eye */
#define VG_DRAW_CASCADE 1u    /* shadow: which cascade (light_view_proj[flags & 1]) */
/* The shadow map is an atlas of VG_SHADOW_CASCADES square maps side by side,
 * cascade c in [c / N, (c + 1) / N) of its width. */
#define VG_SHADOW_CASCADES 2

/* Per-draw push constants. */
VGX_STRUCT(vg_draw_push) {
    VGX_VEC4 base_color;       /* linear RGBA factor */
    uint instance_id;      /* 1-based */
    float saliency;           /* 0..1 */
    int texture_index;        /* index into the texture array, -1 for none */
    uint flags;            /* VG_DRAW_* bits */
};

/* warp.classify: one entry per scene instance. Its flat and tessellated
 * index lists sit in the instance's own range [first_index, +index_count) of
 * two output index buffers; indirect draw args: the flat draw of instance i
 * at i, its tessellated chunks at instance_count + tess_args + c, and after
 * all commands one uint per instance: how many of its chunks hold triangles. */
VGX_STRUCT(vg_warp_instance) {
    uint first_index, index_count, first_vertex, tess_args;
    uint tess_chunks, pad0, pad1, pad2;
};
/* warp.classify works on chunks of up to 256 triangles of one instance. */
VGX_STRUCT(vg_warp_chunk) {
    uint instance, first_triangle, triangle_count, first_chunk; /* first_chunk: the instance's chunk 0 */
};
VGX_STRUCT(vg_classify_push) {
    uint instance_count;
    uint chunk_triangles;   /* patches per tessellated draw (lavapipe's vertex limit) */
    uint chunk_count;
    uint tess_slots;        /* draw commands of all tessellated chunks; per-instance counts follow them */
    uint edge_count;        /* the scene's distinct triangle edges (warp.edges) */
    uint vertex_count;      /* the scene's vertices (warp.vertices) */
    uint stamp;             /* this frame's mark in vertex_seen: never 0, one more each frame */
    uint bucket;            /* warp_edge_levels: the bucket of edges it levels (VG_EDGE_BUCKETS) */
};
/* warp.edges: an edge of the scene's triangles, once however many triangles
 * share it. Vertices global (instance first_vertex + index); the (at most
 * two) triangles that use it as global triangle numbers, VG_EDGE_NONE for a
 * border edge's second, VG_EDGE_ALWAYS when more than two share it (its
 * level is always computed). */
VGX_STRUCT(vg_warp_edge) {
    uint v0, v1, t0, t1;
};
#define VG_EDGE_NONE 0xffffffffu
#define VG_EDGE_ALWAYS 0xfffffffeu
#define VG_BINDING_VERTICES 7     /* warp.classify: scene positions (6 floats per vertex) */
#define VG_BINDING_INDICES 8
#define VG_BINDING_INSTANCES 9
#define VG_BINDING_FLAT 10
#define VG_BINDING_TESS 11
#define VG_BINDING_ARGS 12
#define VG_BINDING_CHUNKS 13      /* vg_warp_chunk */
#define VG_BINDING_KINDS 14       /* per triangle: bits 0-7 kind (0 culled, 1 flat, 2 tessellated),
                                     bits 8-15, 16-23, 24-31 the levels of edges 1-2, 2-0, 0-1 */
#define VG_BINDING_COUNTS 15      /* per chunk: flat and tessellated triangles */
/* warp.compact writes, the tessellation control shader reads: the packed
 * kinds word of every tessellated triangle in draw order. Each tessellated
 * draw's firstInstance is the draw-order index of its first patch, so a
 * patch finds its levels at gl_InstanceIndex + gl_PrimitiveID. Binding 16 of
 * the scene pipelines' set 0 too. */
#define VG_BINDING_TESS_LEVELS 16
#define VG_BINDING_TRI_EDGES 17   /* warp.classify: per triangle, its edges 1-2, 2-0, 0-1 (vg_warp_edge ids) */
#define VG_BINDING_EDGES 18       /* vg_warp_edge */
#define VG_BINDING_EDGE_LEVELS 19 /* per edge: its tessellation level this frame (1 when no visible
                                     triangle uses it) */
/* warp.vertices writes, the flat triangles' vertex shader reads: per scene
 * vertex, vgx_warp_disparity of this frame (vec2: disparity x clip w in
 * pixels, cascade stage), for the vertices of the triangles warp.cull let
 * through; each is warped once for both eyes. Binding 20 of the scene
 * pipelines' set 0 too. */
#define VG_BINDING_VERTEX_WARP 20
#define VG_BINDING_VERTEX_SEEN 21 /* warp.classify: per scene vertex, the stamp of the last frame a visible
                                     triangle used it (so nothing is cleared between frames) */
/* warp.classify's work lists: the edges to sample, by their number of
 * samples (6, 12, VGX_EDGE_SAMPLES: lists 0, 1, 2), then the vertices whose
 * warp needs the cascade's Halton search (list VG_HALTON_LIST). A work-list
 * header per list, then edge_count ids per edge list, then vertex_count
 * vertex ids. */
#define VG_BINDING_CLASSIFY_WORK 22
#define VG_EDGE_BUCKETS 3u
#define VG_HALTON_LIST VG_EDGE_BUCKETS
#define VG_CLASSIFY_LISTS (VG_EDGE_BUCKETS + 1u)

/* compose modes (frame_compose minus one) and push constants. The packed
 * layouts (side by side, top-bottom, their halves, frame packing,
 * cross-eyed) are one case: each eye into its rectangle of the output
 * (frame_compose_layout), averaged down where it is squeezed. */
#define VG_COMPOSE_SBS 0
#define VG_COMPOSE_SBS_HALF 1
#define VG_COMPOSE_TB 2
#define VG_COMPOSE_ROWS 3
#define VG_COMPOSE_COLUMNS 4
#define VG_COMPOSE_CHECKER 5
#define VG_COMPOSE_ANAGLYPH 6
#define VG_COMPOSE_ANAGLYPH_PLAIN 7
#define VG_COMPOSE_LEFT 8
#define VG_COMPOSE_RIGHT 9
#define VG_COMPOSE_TB_HALF 10
#define VG_COMPOSE_ANAGLYPH_GREEN_MAGENTA 11
#define VG_COMPOSE_ANAGLYPH_AMBER_BLUE 12
#define VG_COMPOSE_FRAME_PACKING 13
#define VG_COMPOSE_CROSS_EYED 14
/* The mode (VG_COMPOSE_*) and whether the layout is packed are the
 * shader's specialisation constants 0 and 1. */
VGX_STRUCT(vg_compose_push) {
    uint swap;             /* 1: exchange the eyes (overlaid modes; packed ones swap rectangles) */
    uint width, height;    /* of one eye */
    uint rect[8];          /* packed: x, y, w, h of the left eye's, then the right eye's */
};

/* probe: the pixels of a few instances (the game's ball) and the mean of
 * (shown map - g) over them, one partial sum per 16 x 16 workgroup
 * (engine/frame/probe_gpu.c adds them on the host). */
#define VG_PROBE_GROUP 16u
#define VG_PROBE_MAX_IDS 8
VGX_STRUCT(vg_probe_push) {
    uint ids[VG_PROBE_MAX_IDS]; /* instance ids, 0 = unused */
    uint width, height;
    uint groups_x;
};
VGX_STRUCT(vg_probe_partial) {
    float sum;                /* of (shown - g), arcmin */
    uint pixels;
};

#endif
