/* vergence — comfortable stereo that keeps motion in depth, for any Vulkan
 * engine (docs/sdk.md is the integration guide).
 *
 * A context is made from the host's own Vulkan objects; each frame the host
 * records one dispatch into its own command buffer, naming its own images
 * (VkImage + VkImageView + the layout they are in), and gets the vergence
 * maps back as images it can sample. Nothing is ever submitted or waited
 * on behind the host's back. Every Vulkan object of the context is made in
 * vgx_context_create, but for the first dispatch of another configuration
 * (other input layouts, warp_map or depth_kind), which makes its passes'
 * scratch images and buffers; what the configuration before used is freed
 * once the frames in flight that used it have completed.
 *
 *   g  the vergence (arcmin) a viewer of the display gets from the host's
 *      original stereo camera, per pixel of the host's linear depth
 *   h  g compressed into the display's comfortable range by the operator
 *      (Lang et al. 2010 by default), weighted by the host's saliency
 *   f  h with the original acceleration in depth restored where the viewer
 *      would see it (VGX_CONTEXT_OPTIMIZE): a window of keyframes seconds
 *      long, solved for minimal MID distortion in JND (Kellnhofer et al.,
 *      "Optimizing disparity for motion in depth", 2013), upsampled to the
 *      frame in space and time
 *
 * A frame with f: vgx_begin_frame(frame index) says which keyframes the
 * host renders this frame (its scene at their times, seconds ahead: the
 * look-ahead) into tiles of a coarse atlas, with the matrix that places
 * each; the host draws them with its own G-buffer shaders, then records
 * vgx_dispatch with its frame's depth, saliency, motion and ids and the atlas.
 * The stereo pair: the host's tessellation shaders include
 * vergence/warp.glsl (VGX_CONTEXT_WARP, vgx_get_warp).
 *
 * Conventions (docs/method.md of the vergence repository): vergence in
 * arcmin, larger = nearer; depth in metres along the view axis.
 *
 * Errors: every call that can fail returns a vgx_result; the context's
 * message callback gets one line naming the cause (without one, lines go to
 * stderr). No global state: contexts are independent. Thread safety: a
 * context is used by one thread at a time (external synchronisation, as
 * Vulkan's); different contexts may be used from different threads. The
 * command buffer given to vgx_dispatch is externally synchronised by the
 * host, as for any vkCmd call.
 *
 * C99 and C++ compatible. */
#ifndef VERGENCE_VERGENCE_H
#define VERGENCE_VERGENCE_H

#include <stdint.h>

#include <vulkan/vulkan.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------- */
/* Version                                                                   */
/* ------------------------------------------------------------------------- */

#define VGX_MAKE_VERSION(major, minor, patch) (((uint32_t)(major) << 22) | ((uint32_t)(minor) << 12) | (uint32_t)(patch))
#define VGX_VERSION_MAJOR(v) ((uint32_t)(v) >> 22)
#define VGX_VERSION_MINOR(v) (((uint32_t)(v) >> 12) & 0x3ffu)
#define VGX_VERSION_PATCH(v) ((uint32_t)(v) & 0xfffu)
/* The version of this header; vgx_version() is the library's. A context
 * is created when both have the same major version and the library's minor
 * version is at least the header's (0.1 hosts run on a 0.2 library).
 *
 * How the ABI grows: a release never moves or removes a member of a public
 * struct; a desc gains members at its end only, and the library reads a
 * host's descs (vgx_context_desc.header_version for the context's, the
 * context's for every desc given to it later) with the members of the
 * header the host was built with, the newer ones taking their zero
 * default. Structs the library fills are never grown. sdk/abi/ in the
 * repository keeps each release's header and ABI, and the test command
 * checks this library against them (abidiff; a 0.1 host's test run). */
#define VGX_HEADER_VERSION VGX_MAKE_VERSION(VGX_HEADER_VERSION_MAJOR, VGX_HEADER_VERSION_MINOR, 0)
/* The same, for #if (0.2 on; a 0.1 header leaves them undefined). */
#define VGX_HEADER_VERSION_MAJOR 0
#define VGX_HEADER_VERSION_MINOR 2

#if defined(_WIN32)
#define VGX_API
#else
#define VGX_API __attribute__((visibility("default")))
#endif

VGX_API uint32_t vgx_version(void);

/* ------------------------------------------------------------------------- */
/* Results and messages                                                      */
/* ------------------------------------------------------------------------- */

typedef enum vgx_result {
    VGX_SUCCESS = 0,
    VGX_ERROR_INVALID_ARGUMENT = -1, /* a null or out-of-range field, named in the message */
    VGX_ERROR_OUT_OF_MEMORY = -2,
    VGX_ERROR_VULKAN = -3,           /* a Vulkan call failed; the message names it and its VkResult */
    VGX_ERROR_DEVICE = -4,           /* the host's device lacks a feature or extension (vgx_device_requirements) */
    VGX_ERROR_VERSION = -5,          /* header and library versions do not match */
} vgx_result;

/* "VGX_SUCCESS", "VGX_ERROR_INVALID_ARGUMENT", ... ("unknown" for others). */
VGX_API const char *vgx_result_name(vgx_result result);

typedef enum vgx_severity {
    VGX_SEVERITY_ERROR = 1,
    VGX_SEVERITY_WARNING = 2,
    VGX_SEVERITY_INFO = 3,
} vgx_severity;

/* One line, no newline. Called on the thread of the vgx_ call that says it. */
typedef void (*vgx_message_fn)(vgx_severity severity, const char *message, void *user);

/* ------------------------------------------------------------------------- */
/* Device requirements                                                       */
/* ------------------------------------------------------------------------- */

/* What the host enables on its VkDevice for vergence (Vulkan 1.3):
 * the device extensions below, and the features dynamicRendering,
 * synchronization2, maintenance4 (1.3), hostQueryReset, scalarBlockLayout
 * (1.2), shaderStorageImageWriteWithoutFormat and drawIndirectFirstInstance
 * (1.0). Returns the extension names (count in *count; static storage). */
VGX_API const char *const *vgx_device_extensions(uint32_t *count);
/* VGX_SUCCESS when the physical device supports everything above; else
 * VGX_ERROR_DEVICE with the first missing name in *missing (may be NULL). */
VGX_API vgx_result vgx_check_physical_device(VkPhysicalDevice physical_device, const char **missing);
/* Every requirement the physical device lacks, at once, for a context made
 * with `context_flags` (VGX_CONTEXT_*: VGX_CONTEXT_WARP adds the
 * tessellationShader feature that the stages of vergence/warp.glsl need):
 * Vulkan 1.3, each feature and extension above, a queue family with graphics
 * and compute. Writes at most `capacity` names (static storage) to `missing`
 * (NULL with capacity 0: only count) and how many lack to *missing_count.
 * VGX_SUCCESS when nothing lacks, else VGX_ERROR_DEVICE; VGX_ERROR_INVALID_ARGUMENT
 * without a physical device or missing_count. */
VGX_API vgx_result vgx_get_missing_requirements(VkPhysicalDevice physical_device, uint32_t context_flags,
                                                const char **missing, uint32_t capacity, uint32_t *missing_count);

/* ------------------------------------------------------------------------- */
/* Context                                                                   */
/* ------------------------------------------------------------------------- */

/* The display the stereo pair is watched on (zero = the paper's: a 24"
 * 16:9 1920x1080 panel at 0.80 m, a 65 mm interocular distance). */
typedef struct vgx_display {
    double diagonal_in;
    int aspect_w, aspect_h;
    int res_x, res_y;
    double distance_m;
    double ipd_m;
} vgx_display;

typedef enum vgx_operator {
    VGX_OPERATOR_DEFAULT = 0, /* = lang */
    VGX_OPERATOR_NONE,        /* h = g */
    VGX_OPERATOR_LINEAR,      /* scale about the screen until g's range fits */
    VGX_OPERATOR_LANG,        /* saliency-weighted histogram mapping (Lang et al. 2010) */
    VGX_OPERATOR_LANG_SMOOTHED, /* lang with its mapping smoothed in time (0.5 s) */
} vgx_operator;

typedef enum vgx_preset {
    VGX_PRESET_DEFAULT = 0,   /* comfort: the screen +- 60 arcmin */
    VGX_PRESET_STUDY,         /* +- 30 arcmin: the paper's studies */
} vgx_preset;

/* vgx_context_desc.flags */
#define VGX_CONTEXT_SALIENCY 0x1u /* the host gives saliency each frame and in its keyframes (else every pixel weighs 1) */
#define VGX_CONTEXT_OPTIMIZE 0x2u /* f: the host gives motion, ids and the keyframes vgx_begin_frame asks for */
#define VGX_CONTEXT_WARP 0x4u     /* the dispatch also makes what warp.glsl reads (vgx_get_warp): the host draws
                                     its stereo pair by moving its own vertices */
#define VGX_CONTEXT_KEYFRAMES 0x8u /* keyframes without f (implied by VGX_CONTEXT_OPTIMIZE): lang-smoothed's h then
                                     depends on its keyframe and the frame only, not on which frames were rendered */
#define VGX_CONTEXT_DEBUG_UTILS 0x10u /* the host enabled VK_EXT_debug_utils on its instance: every Vulkan object
                                     the context makes carries a name ("vgx g", "mid.solve", ...) and each pass
                                     of vgx_dispatch a command-buffer label (RenderDoc, Nsight) */
#define VGX_CONTEXT_EYES 0x20u    /* 0.2: the dispatch also makes the stereo pair itself, for a host whose materials
                                     cannot take the warp's tessellation: its shaded centre view
                                     (vgx_dispatch_desc.color) moved per pixel by the warp map's disparity, the
                                     disocclusions filled from the background side (vgx_get_eye) */

/* The warp's settings (include/vergence/warp.glsl; zero = the engine's). */
typedef struct vgx_warp_settings {
    double tess_px;                   /* tessellate edges down to this many pixels (paper: 1); 0 = error-driven */
    double tess_error_px;             /* error-driven: the disparity error an edge may leave, pixels; 0 = 0.025 */
    uint32_t max_tess_level;          /* 0 = 32 (64 with tess_px) */
    double depth_epsilon;             /* the cascade: relative depth difference of one surface; 0 = 0.01 */
    double halton_radius_px;          /* the cascade's Halton search radius; 0 = 24 */
} vgx_warp_settings;

/* Where the window's future keyframes come from (paper 4.5: "a prediction
 * of future frames"). */
typedef enum vgx_look_ahead {
    VGX_LOOK_AHEAD_PREDICTED = 0, /* each keyframe is rendered once, when it enters the window, at its future
                                     time: the host knows (animations, scripted motion) or predicts its scene */
    VGX_LOOK_AHEAD_CAUSAL,        /* the host can only extrapolate from the past: at every window move it renders
                                     the keyframe just observed and all future ones again, each a fresh
                                     prediction. Measured in docs/method.md section 15: it keeps motion in depth
                                     only where motion stays constant over the window's future */
} vgx_look_ahead;

/* Device memory from the host's own allocator (0.2; vgx_context_desc.memory).
 * The context asks once per image or buffer it makes, in
 * vgx_context_create and in the first dispatch of a configuration (see
 * vgx_dispatch), and gives each block back when it no longer uses it: in
 * vgx_context_destroy, or in a later dispatch for a replaced
 * configuration's. Called on the thread of that vgx_ call. */
typedef struct vgx_memory_request {
    const char *name;                 /* what it is for ("vgx g", "rg warp.curve.tiles", ...) */
    VkMemoryRequirements requirements;/* of the image or buffer it is bound to */
    VkMemoryPropertyFlags properties; /* DEVICE_LOCAL (preferred; any type of memoryTypeBits will do), or
                                         HOST_VISIBLE | HOST_COHERENT (required, and mapped) */
} vgx_memory_request;

typedef struct vgx_memory_block {
    VkDeviceMemory memory;
    VkDeviceSize offset;              /* a multiple of requirements.alignment; size bytes from it are the context's */
    void *mapped;                     /* host-visible requests: the host address of `offset`, mapped until freed */
    void *user;                       /* the host's own handle of the block (a VmaAllocation, say) */
} vgx_memory_block;

typedef struct vgx_memory_hooks {
    /* VK_SUCCESS and the block, or an error (the call that asked fails with its message). */
    VkResult (*allocate)(void *user, const vgx_memory_request *request, vgx_memory_block *block);
    void (*free)(void *user, const vgx_memory_block *block);
    void *user;
} vgx_memory_hooks;

typedef struct vgx_context_desc {
    uint32_t header_version;          /* VGX_HEADER_VERSION */
    VkInstance instance;
    VkPhysicalDevice physical_device;
    VkDevice device;                  /* with vgx_device_extensions() and the features above enabled */
    uint32_t queue_family;            /* of the command buffers the host records dispatches into */
    const VkAllocationCallbacks *allocator; /* used for every Vulkan object the context creates; NULL = driver's */
    uint32_t width, height;           /* the frame's size: depth, saliency and the maps */
    vgx_display display;
    vgx_operator op;
    vgx_preset preset;
    double target_range_arcmin;       /* half-width of the comfortable range around the screen; 0 = the preset's */
    double fps;                       /* frame n shows the host's scene at n / fps seconds; 0 = 60 */
    int keyframe_stride;              /* frames between keyframes (paper 4.4); 0 = 10 */
    double window_seconds;            /* the keyframe window (paper 4.2); 0 = 3 s, half of it ahead */
    vgx_look_ahead look_ahead;
    vgx_warp_settings warp;           /* with VGX_CONTEXT_WARP */
    uint32_t flags;                   /* VGX_CONTEXT_* */
    vgx_message_fn message;           /* NULL = stderr */
    void *message_user;
    /* 0.2: */
    uint32_t frames_in_flight;        /* frames the host keeps in flight, 1 to VGX_MAX_FRAMES_IN_FLIGHT; 0 = 2.
                                         Before recording the dispatch of frame n, the host has waited for frame
                                         n - frames_in_flight to complete (its fence); a dispatch that would make
                                         one more in flight is refused (VGX_ERROR_INVALID_ARGUMENT, its message) */
    vgx_memory_hooks memory;          /* both set: every block of device memory from the host; zero: a dedicated
                                         vkAllocateMemory per image or buffer */
} vgx_context_desc;

#define VGX_MAX_FRAMES_IN_FLIGHT 4

typedef struct vgx_context vgx_context;

VGX_API vgx_result vgx_context_create(const vgx_context_desc *desc, vgx_context **out);
/* The host makes sure the GPU no longer uses what the context recorded
 * (vkDeviceWaitIdle, or its frame fences). NULL is ignored. */
VGX_API void vgx_context_destroy(vgx_context *context);

/* The device memory a context of `desc` holds (0.2), measured by making it
 * on desc's device and destroying it (about the time of
 * vgx_context_create; the memory hooks, if any, are called). */
typedef struct vgx_memory_footprint {
    VkDeviceSize bytes;               /* all of it, after vgx_context_create */
    VkDeviceSize host_visible_bytes;  /* of which host-visible */
    uint32_t blocks;                  /* images and buffers: one allocation (or hook call) each */
    VkDeviceSize configuration_bytes; /* of `bytes`: the scratch of the dispatch's graph. A configuration change
                                         (vgx_dispatch) makes as much again, and the replaced one is freed once the
                                         frames in flight that used it have completed */
} vgx_memory_footprint;
VGX_API vgx_result vgx_get_memory_footprint(const vgx_context_desc *desc, vgx_memory_footprint *footprint);

/* What a context was made into (fixed for its life). */
typedef struct vgx_context_info {
    double range_lo_arcmin, range_hi_arcmin; /* the comfortable range h and f are mapped into */
    uint32_t grid_width, grid_height, grid_stride; /* the solver's coarse grid: a sample every stride pixels */
    int window_past, window_future;   /* keyframes of the window behind and ahead of a frame */
    uint32_t atlas_width, atlas_height; /* the keyframe atlas (VGX_CONTEXT_OPTIMIZE; else 0) */
    uint32_t atlas_tiles;             /* keyframes it holds: at most this many per frame */
} vgx_context_info;
VGX_API void vgx_get_info(const vgx_context *context, vgx_context_info *info);

/* ------------------------------------------------------------------------- */
/* Per frame                                                                 */
/* ------------------------------------------------------------------------- */

/* What frame `frame_index` needs from the host (vgx_begin_frame). */
typedef struct vgx_frame_plan {
    int64_t frame_index;
    double time_s;                    /* frame_index / fps: render the frame's scene at this time */
    double prev_key_time_s, next_key_time_s; /* the motion image's targets: the keyframes strictly before and after */
    uint32_t keyframe_count;          /* keyframes to render into the atlas this frame (vgx_get_keyframe 0..count-1) */
} vgx_frame_plan;

/* One keyframe to render into the atlas: the host's scene and camera at
 * time_s, with a viewport of the whole atlas (vgx_context_info's size,
 * depth 0..1), the scissor below, and its clip coordinates multiplied by
 * atlas_from_clip (column-major, as GLSL: clip' = atlas_from_clip * clip).
 * Motion goes to the scene and camera at prev_time_s and next_time_s,
 * through the same matrix, in atlas pixels. */
typedef struct vgx_keyframe {
    int64_t index;                    /* the keyframe: frame index * keyframe_stride */
    double time_s, prev_time_s, next_time_s;
    float atlas_from_clip[16];
    VkRect2D scissor;
} vgx_keyframe;

/* Starts frame_index (contexts with VGX_CONTEXT_OPTIMIZE; without, optional:
 * each dispatch is then the next frame). Any order of indices works: a
 * repeated index records nothing new, a skip is caught up, a jump back or
 * far ahead starts the window afresh. */
VGX_API vgx_result vgx_begin_frame(vgx_context *context, int64_t frame_index, vgx_frame_plan *plan);
VGX_API vgx_result vgx_get_keyframe(const vgx_context *context, uint32_t i, vgx_keyframe *keyframe);
/* The host's scene changed unpredictably (a cut, a new throw): the
 * predicted keyframes are stale; the next frame starts the window afresh. */
VGX_API void vgx_restart(vgx_context *context);

/* A host image: its handle, a 2D view of it, and the layout it is in when
 * the dispatch's commands run. The dispatch leaves it in that layout,
 * having made its own accesses available; the host's earlier writes must be
 * available to compute shaders (for a layout other than the one it was
 * written in, the host's own barrier did it). COLOR_ATTACHMENT_OPTIMAL
 * tells the dispatch the image was just rendered: it waits for the colour
 * attachment writes itself. */
typedef struct vgx_image {
    VkImage image;
    VkImageView view;
    VkImageLayout layout;
} vgx_image;

/* The original stereo camera: a parallel rig with shifted sensors whose
 * centre is the host's camera. Zero interaxial / convergence = the
 * display's interocular distance / viewing distance (ortho-stereo). */
typedef struct vgx_rig {
    double hfov_deg;                  /* the host camera's horizontal field of view (required) */
    double interaxial_m;
    double convergence_m;             /* the distance that lands on the screen */
} vgx_rig;

/* The G-buffer images vergence reads (usage STORAGE each), for the frame
 * (width x height) or the keyframe atlas (atlas_width x atlas_height). */
typedef struct vgx_gbuffer {
    vgx_image depth;                  /* R32_SFLOAT: linear depth along the view axis, metres; background = far plane */
    vgx_image saliency;               /* R8G8B8A8_UNORM, saliency 0..1 in alpha (VGX_CONTEXT_SALIENCY) */
    vgx_image motion;                 /* R32G32B32A32_SFLOAT: pixels to the previous keyframe's position (xy) and
                                         to the next one's (zw); background 0 (VGX_CONTEXT_OPTIMIZE) */
    vgx_image ids;                    /* R32_UINT: the surface's object, 0 = background (VGX_CONTEXT_OPTIMIZE) */
} vgx_gbuffer;

/* Which map the warp gives the stereo pair (VGX_CONTEXT_WARP). */
typedef enum vgx_warp_map {
    VGX_WARP_MAP_DEFAULT = 0,         /* f with VGX_CONTEXT_OPTIMIZE, else h */
    VGX_WARP_MAP_G,                   /* the original stereo */
    VGX_WARP_MAP_H,
    VGX_WARP_MAP_F,
} vgx_warp_map;

/* What frame.depth holds. */
typedef enum vgx_depth_kind {
    VGX_DEPTH_LINEAR = 0,             /* R32_SFLOAT metres along the view axis (storage), as vgx_gbuffer says */
    VGX_DEPTH_DEVICE,                 /* the host's z-buffer as rasterised (a depth format, SAMPLED usage, in
                                         DEPTH_READ_ONLY_OPTIMAL or DEPTH_ATTACHMENT_OPTIMAL): the dispatch makes
                                         linear depth from `projection`, any depth range or handedness */
} vgx_depth_kind;

typedef struct vgx_dispatch_desc {
    VkCommandBuffer command_buffer;   /* recording, outside a render pass, of the context's queue family */
    vgx_gbuffer frame;
    vgx_gbuffer keyframes;            /* the atlas (VGX_CONTEXT_OPTIMIZE): its tiles rendered this frame are read */
    vgx_rig rig;
    vgx_depth_kind depth_kind;        /* of frame.depth */
    VkFormat depth_format;            /* VGX_DEPTH_DEVICE: frame.depth's format; 0 = D32_SFLOAT */
    float projection[16];             /* VGX_DEPTH_DEVICE: the projection the z-buffer was drawn with (column-major) */
    /* VGX_CONTEXT_WARP: */
    float view_proj[16];              /* the host camera's world -> clip at the frame (column-major; Vulkan clip:
                                         y down, depth 0..1): where warp.glsl finds a vertex in the maps */
    float background_depth_m;         /* the depth the host writes where there is no geometry (its far plane) */
    vgx_warp_map warp_map;
    /* A profiler's view: record only passes first_pass .. first_pass + pass_count - 1 of the dispatch
     * (vgx_pass_name), in order, each call with the same desc; 0 passes = all of them. */
    uint32_t first_pass, pass_count;
    /* 0.2: */
    vgx_image color;                  /* VGX_CONTEXT_EYES: the frame's shaded centre view (SAMPLED usage, any colour
                                         format), width x height; warp_map picks the disparity it is moved by */
} vgx_dispatch_desc;

/* Records the frame's passes into desc->command_buffer. */
VGX_API vgx_result vgx_dispatch(vgx_context *context, const vgx_dispatch_desc *desc);
/* The dispatch's passes in recording order, for a host that times them one
 * by one ("disparity.original", "mid.solve", ...): fixed for the context's
 * life, but for vgx.depth, which a VGX_DEPTH_DEVICE dispatch adds (the
 * count is the last dispatch's, or for linear depth before the first). */
VGX_API uint32_t vgx_pass_count(const vgx_context *context);
VGX_API const char *vgx_pass_name(const vgx_context *context, uint32_t pass);

typedef enum vgx_output {
    VGX_OUTPUT_G = 0,                 /* original vergence, arcmin */
    VGX_OUTPUT_H = 1,                 /* the operator's, arcmin */
    VGX_OUTPUT_F = 2,                 /* motion in depth restored, arcmin (VGX_CONTEXT_OPTIMIZE) */
} vgx_output;

/* An output map, R32_SFLOAT, owned by the context: after the commands of a
 * dispatch it is in SHADER_READ_ONLY_OPTIMAL with its writes available to
 * fragment and compute shader reads and to transfers (copies need the host
 * to transition it, and back). The handles stay valid for the context's
 * life; the contents are the last recorded dispatch's. */
VGX_API vgx_result vgx_get_output(const vgx_context *context, vgx_output which, vgx_image *out);

/* ------------------------------------------------------------------------- */
/* The warp (VGX_CONTEXT_WARP)                                               */
/* ------------------------------------------------------------------------- */

/* What include/vergence/warp.glsl reads, in the set the host picks
 * (VGX_WARP_SET), after each dispatch:
 *   binding 0  uniform buffer `constants` (std140, constants_size bytes)
 *   binding 1  combined image sampler: the frame's linear depth, the
 *              host's own image given as frame.depth (or `depth` below
 *              with VGX_DEPTH_DEVICE); any sampler, read by texelFetch
 *   binding 2  combined image sampler: `target`, the warp map
 *              (SHADER_READ_ONLY_OPTIMAL after the dispatch)
 *   binding 3  storage buffer `curve` (curve_size bytes), read only
 * The dispatch leaves the buffers written and visible to every later stage.
 * The handles stay the same for the context's life. */
typedef struct vgx_warp {
    VkBuffer constants;
    VkDeviceSize constants_size;
    vgx_image depth;                  /* after a VGX_DEPTH_DEVICE dispatch: the linear depth it made, to bind at 1
                                         instead of the host's (SHADER_READ_ONLY_OPTIMAL); else null */
    vgx_image target;
    VkBuffer curve;
    VkDeviceSize curve_size;
} vgx_warp;
VGX_API vgx_result vgx_get_warp(const vgx_context *context, vgx_warp *warp);
/* The four bindings above for a VkDescriptorSetLayoutCreateInfo, for the
 * given shader stages (the tessellation stages, say). */
VGX_API void vgx_warp_bindings(VkShaderStageFlags stages, VkDescriptorSetLayoutBinding bindings[4]);

/* ------------------------------------------------------------------------- */
/* The stereo pair without tessellation (VGX_CONTEXT_EYES, 0.2)              */
/* ------------------------------------------------------------------------- */

/* Eye 0 (left) or 1 (right), width x height R8G8B8A8_UNORM, owned by the
 * context: after a dispatch in SHADER_READ_ONLY_OPTIMAL, written and
 * visible as the outputs are (vgx_get_output). Colour as the host's
 * `color`; alpha 1 where a surface of the centre view landed, 0.5 where a
 * disocclusion was filled, 0 where nothing within 256 pixels of its row
 * could fill it. */
VGX_API vgx_result vgx_get_eye(const vgx_context *context, uint32_t eye, vgx_image *out);

#ifdef __cplusplus
}
#endif
#endif
