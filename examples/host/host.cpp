// vergence_host — a small Vulkan renderer of its own that adds vergence's
// comfortable stereo with motion in depth kept, through the installed SDK
// only (docs/sdk.md).
//
// It loads a glTF scene with tinygltf, evaluates its node animations at any
// time, and each frame draws its own G-buffer (linear depth, saliency,
// motion, object ids) for the keyframes vergence asks for (its scene
// seconds ahead, into tiles of the atlas) and for the frame, then records
// vgx_dispatch into the same command buffer and copies g, h and f back.
// Rigid meshes only (no skins or morph targets): it is an example.
//
//   vergence_host --scene FILE --out DIR [--size WxH] [--time T] [--frames N] [--fps HZ]
//                 [--interaxial M] [--convergence M] [--causal] [--validate]
//
// --causal renders the keyframes as a host that cannot see its future would:
// extrapolated from the last two frames (VGX_LOOK_AHEAD_CAUSAL).
//
// Exit codes: 0 done, 1 bad arguments or scene, 2 Vulkan or SDK failure,
// 3 validation messages (with --validate).
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <sys/stat.h>

#include <tiny_gltf.h>
#include <vergence/vergence.h>

#include "host_eye_frag.h"
#include "host_eye_tesc.h"
#include "host_eye_tese.h"
#include "host_eye_vert.h"
#include "host_gbuffer_frag.h"
#include "host_gbuffer_vert.h"

namespace {

// ---------------------------------------------------------------------------
// Small maths: column-major 4x4 matrices, as GLSL and glTF store them.
// ---------------------------------------------------------------------------

struct Mat4 {
    float m[16];
};

Mat4 identity()
{
    Mat4 r{};
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0f;
    return r;
}

Mat4 mul(const Mat4 &a, const Mat4 &b)
{
    Mat4 r{};
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++) {
            float s = 0;
            for (int k = 0; k < 4; k++)
                s += a.m[k * 4 + row] * b.m[c * 4 + k];
            r.m[c * 4 + row] = s;
        }
    return r;
}

Mat4 trs(const double t[3], const double q[4], const double s[3])
{
    double x = q[0], y = q[1], z = q[2], w = q[3];
    Mat4 r = identity();
    r.m[0] = float((1 - 2 * (y * y + z * z)) * s[0]);
    r.m[1] = float((2 * (x * y + z * w)) * s[0]);
    r.m[2] = float((2 * (x * z - y * w)) * s[0]);
    r.m[4] = float((2 * (x * y - z * w)) * s[1]);
    r.m[5] = float((1 - 2 * (x * x + z * z)) * s[1]);
    r.m[6] = float((2 * (y * z + x * w)) * s[1]);
    r.m[8] = float((2 * (x * z + y * w)) * s[2]);
    r.m[9] = float((2 * (y * z - x * w)) * s[2]);
    r.m[10] = float((1 - 2 * (x * x + y * y)) * s[2]);
    r.m[12] = float(t[0]), r.m[13] = float(t[1]), r.m[14] = float(t[2]);
    return r;
}

// ---------------------------------------------------------------------------
// The scene: glTF nodes at a time t
// ---------------------------------------------------------------------------

struct Node {
    double t[3] = {0, 0, 0}, r[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
    bool has_matrix = false;
    Mat4 matrix = identity();
};

// Reads accessor element i as n floats (float components only: the
// animation and position accessors this host supports).
bool read_floats(const tinygltf::Model &m, int accessor, size_t i, int n, double *out)
{
    if (accessor < 0 || accessor >= (int)m.accessors.size())
        return false;
    const tinygltf::Accessor &a = m.accessors[accessor];
    if (a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT || a.bufferView < 0 || i >= a.count)
        return false;
    const tinygltf::BufferView &v = m.bufferViews[a.bufferView];
    const tinygltf::Buffer &b = m.buffers[v.buffer];
    size_t stride = v.byteStride ? v.byteStride : (size_t)n * 4;
    size_t at = v.byteOffset + a.byteOffset + i * stride;
    if (at + (size_t)n * 4 > b.data.size())
        return false;
    for (int k = 0; k < n; k++) {
        float f;
        std::memcpy(&f, &b.data[at + 4 * k], 4);
        out[k] = f;
    }
    return true;
}

void slerp(const double *a, const double *b, double u, double *out)
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3], sign = d < 0 ? -1 : 1;
    d = std::fabs(d);
    double wa = 1 - u, wb = u;
    if (d < 0.9995) {
        double th = std::acos(d), sn = std::sin(th);
        wa = std::sin((1 - u) * th) / sn;
        wb = std::sin(u * th) / sn;
    }
    double len = 0;
    for (int k = 0; k < 4; k++) {
        out[k] = wa * a[k] + sign * wb * b[k];
        len += out[k] * out[k];
    }
    for (int k = 0; k < 4; k++)
        out[k] /= std::sqrt(len);
}

// Applies every animation channel of translation, rotation or scale at time t.
void animate(const tinygltf::Model &m, double t, std::vector<Node> &nodes)
{
    for (const tinygltf::Animation &an : m.animations)
        for (const tinygltf::AnimationChannel &ch : an.channels) {
            if (ch.sampler < 0 || ch.sampler >= (int)an.samplers.size() || ch.target_node < 0 ||
                ch.target_node >= (int)nodes.size())
                continue;
            const tinygltf::AnimationSampler &sm = an.samplers[ch.sampler];
            int n = ch.target_path == "rotation" ? 4 : 3;
            double *dst = ch.target_path == "translation" ? nodes[ch.target_node].t
                          : ch.target_path == "rotation"  ? nodes[ch.target_node].r
                          : ch.target_path == "scale"     ? nodes[ch.target_node].s
                                                          : nullptr;
            if (!dst)
                continue;
            size_t count = m.accessors[sm.input].count, k = 0;
            bool cubic = sm.interpolation == "CUBICSPLINE";
            double t0, t1, a[4], b[4];
            while (k + 1 < count && read_floats(m, sm.input, k + 1, 1, &t1) && t1 <= t)
                k++;
            read_floats(m, sm.input, k, 1, &t0);
            // A cubic spline stores (in-tangent, value, out-tangent) per key.
            auto element = [&](size_t key, int which, double *v) {
                return read_floats(m, sm.output, cubic ? 3 * key + which : key, n, v);
            };
            if (!element(k, 1, a))
                continue;
            if (k + 1 >= count || t <= t0 || sm.interpolation == "STEP" || !read_floats(m, sm.input, k + 1, 1, &t1) ||
                !element(k + 1, 1, b) || !(t1 > t0)) {
                std::memcpy(dst, a, sizeof(double) * n);
                continue;
            }
            double u = (t - t0) / (t1 - t0);
            if (cubic) { // glTF 2.0 Appendix C: a Hermite spline, tangents scaled by the key interval
                double out0[4], in1[4], dt = t1 - t0, u2 = u * u, u3 = u2 * u, len = 0;
                element(k, 2, out0);
                element(k + 1, 0, in1);
                for (int c = 0; c < n; c++) {
                    dst[c] = (2 * u3 - 3 * u2 + 1) * a[c] + (u3 - 2 * u2 + u) * dt * out0[c] +
                             (-2 * u3 + 3 * u2) * b[c] + (u3 - u2) * dt * in1[c];
                    len += dst[c] * dst[c];
                }
                if (n == 4)
                    for (int c = 0; c < 4; c++)
                        dst[c] /= std::sqrt(len);
            } else if (n == 4)
                slerp(a, b, u, dst);
            else
                for (int c = 0; c < n; c++)
                    dst[c] = a[c] + u * (b[c] - a[c]);
        }
}

struct Draw {
    uint32_t first_index, index_count;
    float saliency;
    uint32_t id; // 1-based, one per node and primitive: the same surface has the same id at any time
    float color[4]; // the material's base colour factor (linear)
};

// The scene's draws (fixed) and, at a time, its world-space vertices and camera.
struct Scene {
    tinygltf::Model model;
    std::vector<Node> rest;          // the nodes as authored (before animation)
    std::vector<uint32_t> indices;
    std::vector<Draw> draws;
    size_t vertex_count = 0;
    double yfov = 0, znear = 0, zfar = 0;
};

struct Pose {
    std::vector<float> positions;    // xyz per vertex, world space
    Mat4 camera_world = identity();
    bool has_camera = false;
};

// Walks the node tree: world positions and the first perspective camera into
// pose; with scene non-null (the first walk), the draws too.
void visit(const tinygltf::Model &m, const std::vector<Node> &nodes, int index, const Mat4 &parent, float saliency,
           Pose &pose, Scene *scene, int depth)
{
    if (index < 0 || index >= (int)nodes.size() || depth > 64)
        return;
    const tinygltf::Node &gn = m.nodes[index];
    const Node &n = nodes[index];
    Mat4 world = mul(parent, n.has_matrix ? n.matrix : trs(n.t, n.r, n.s));
    if (gn.extras.IsObject() && gn.extras.Has("saliency") && gn.extras.Get("saliency").IsNumber())
        saliency = (float)std::fmin(1.0, std::fmax(0.0, gn.extras.Get("saliency").GetNumberAsDouble()));
    if (gn.camera >= 0 && gn.camera < (int)m.cameras.size() && !pose.has_camera &&
        m.cameras[gn.camera].type == "perspective") {
        pose.has_camera = true;
        pose.camera_world = world;
        if (scene) {
            const tinygltf::PerspectiveCamera &p = m.cameras[gn.camera].perspective;
            scene->yfov = p.yfov, scene->znear = p.znear, scene->zfar = p.zfar;
        }
    }
    if (gn.mesh >= 0 && gn.mesh < (int)m.meshes.size())
        for (const tinygltf::Primitive &pr : m.meshes[gn.mesh].primitives) {
            auto pos = pr.attributes.find("POSITION");
            if (pos == pr.attributes.end() || pr.mode != TINYGLTF_MODE_TRIANGLES)
                continue;
            uint32_t base = (uint32_t)(pose.positions.size() / 3);
            size_t vcount = m.accessors[pos->second].count;
            for (size_t i = 0; i < vcount; i++) {
                double p[3] = {0, 0, 0};
                read_floats(m, pos->second, i, 3, p);
                for (int r = 0; r < 3; r++)
                    pose.positions.push_back(float(world.m[r] * p[0] + world.m[4 + r] * p[1] + world.m[8 + r] * p[2] +
                                                   world.m[12 + r]));
            }
            if (!scene)
                continue;
            Draw d{(uint32_t)scene->indices.size(), 0, saliency, (uint32_t)scene->draws.size() + 1, {0.8f, 0.8f, 0.8f, 1}};
            if (pr.material >= 0 && pr.material < (int)m.materials.size()) {
                const std::vector<double> &f = m.materials[pr.material].pbrMetallicRoughness.baseColorFactor;
                for (size_t k = 0; k < f.size() && k < 4; k++)
                    d.color[k] = (float)f[k];
            }
            if (pr.indices < 0 || pr.indices >= (int)m.accessors.size()) {
                for (uint32_t i = 0; i < vcount; i++)
                    scene->indices.push_back(base + i);
            } else {
                const tinygltf::Accessor &a = m.accessors[pr.indices];
                size_t size = a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                              : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2 : 4;
                if (a.bufferView < 0 || a.bufferView >= (int)m.bufferViews.size())
                    continue;
                const tinygltf::BufferView &v = m.bufferViews[a.bufferView];
                const std::vector<unsigned char> &data = m.buffers[v.buffer].data;
                size_t at = v.byteOffset + a.byteOffset;
                if (at + a.count * size > data.size())
                    continue;
                for (size_t i = 0; i < a.count; i++) {
                    uint32_t x = 0;
                    std::memcpy(&x, &data[at + i * size], size); // little-endian, as glTF
                    scene->indices.push_back(base + (x < vcount ? x : 0));
                }
            }
            d.index_count = (uint32_t)scene->indices.size() - d.first_index;
            scene->draws.push_back(d);
        }
    for (int child : gn.children)
        visit(m, nodes, child, world, saliency, pose, scene, depth + 1);
}

void pose_at(const Scene &s, double t, Pose &out, Scene *build = nullptr)
{
    std::vector<Node> nodes = s.rest;
    animate(s.model, t, nodes);
    out = Pose{};
    int sc = s.model.defaultScene >= 0 ? s.model.defaultScene : 0;
    if (sc < (int)s.model.scenes.size())
        for (int root : s.model.scenes[sc].nodes)
            visit(s.model, nodes, root, identity(), 0.0f, out, build, 0);
}

// What a renderer that cannot see its future knows of time t, at the frame
// of time now: the scene itself up to now, after it a prediction from the
// last frame and the one a step before (every vertex and the camera's
// origin at their last velocity, the camera's rotation held), as the
// engine's `--look-ahead causal` predicts (scene_evaluate_known).
void pose_known(const Scene &s, double t, double now, double step, Pose &out)
{
    if (t <= now) {
        pose_at(s, t, out);
        return;
    }
    Pose a, b;
    pose_at(s, now, a);
    pose_at(s, now - step, b);
    double u = (t - now) / step;
    out = a;
    for (size_t i = 0; i < out.positions.size(); i++)
        out.positions[i] = (float)(a.positions[i] + u * (a.positions[i] - b.positions[i]));
    for (int k = 12; k < 15; k++)
        out.camera_world.m[k] = (float)(a.camera_world.m[k] + u * (a.camera_world.m[k] - b.camera_world.m[k]));
}

bool load_scene(const std::string &path, Scene &out)
{
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    bool binary = path.size() > 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
    bool ok = binary ? loader.LoadBinaryFromFile(&out.model, &err, &warn, path)
                     : loader.LoadASCIIFromFile(&out.model, &err, &warn, path);
    if (!ok) {
        std::fprintf(stderr, "vergence_host: error: %s: %s\n", path.c_str(), err.c_str());
        return false;
    }
    const tinygltf::Model &m = out.model;
    out.rest.resize(m.nodes.size());
    for (size_t i = 0; i < m.nodes.size(); i++) {
        const tinygltf::Node &gn = m.nodes[i];
        Node &n = out.rest[i];
        if (gn.matrix.size() == 16) {
            n.has_matrix = true;
            for (int k = 0; k < 16; k++)
                n.matrix.m[k] = (float)gn.matrix[k];
        }
        for (size_t k = 0; k < gn.translation.size() && k < 3; k++) n.t[k] = gn.translation[k];
        for (size_t k = 0; k < gn.rotation.size() && k < 4; k++) n.r[k] = gn.rotation[k];
        for (size_t k = 0; k < gn.scale.size() && k < 3; k++) n.s[k] = gn.scale[k];
    }
    Pose first;
    pose_at(out, 0.0, first, &out);
    out.vertex_count = first.positions.size() / 3;
    if (!first.has_camera || !(out.zfar > out.znear) || !(out.znear > 0)) {
        std::fprintf(stderr, "vergence_host: error: %s: needs a perspective camera node with znear and zfar\n",
                     path.c_str());
        return false;
    }
    if (out.draws.empty()) {
        std::fprintf(stderr, "vergence_host: error: %s: no triangle meshes in the scene\n", path.c_str());
        return false;
    }
    return true;
}

// The camera node's view (its world matrix without scale, inverted) and a
// Vulkan projection: y down, depth 0..1 from near to far.
void camera_matrices(const Scene &s, const Pose &pose, float aspect, Mat4 &view, Mat4 &proj)
{
    const float *w = pose.camera_world.m;
    float ax[3][3];
    for (int c = 0; c < 3; c++) {
        float len = std::sqrt(w[c * 4] * w[c * 4] + w[c * 4 + 1] * w[c * 4 + 1] + w[c * 4 + 2] * w[c * 4 + 2]);
        for (int r = 0; r < 3; r++)
            ax[c][r] = w[c * 4 + r] / len;
    }
    view = identity();
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            view.m[r * 4 + c] = ax[c][r];
    for (int c = 0; c < 3; c++)
        view.m[12 + c] = -(ax[c][0] * w[12] + ax[c][1] * w[13] + ax[c][2] * w[14]);
    float t = 1.0f / std::tan(0.5f * (float)s.yfov), n = (float)s.znear, f = (float)s.zfar;
    proj = Mat4{};
    proj.m[0] = t / aspect;
    proj.m[5] = -t;
    proj.m[10] = f / (n - f);
    proj.m[11] = -1.0f;
    proj.m[14] = n * f / (n - f);
}

// ---------------------------------------------------------------------------
// Vulkan
// ---------------------------------------------------------------------------

int g_validation_messages;

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                          const VkDebugUtilsMessengerCallbackDataEXT *data, void *)
{
    g_validation_messages++;
    std::fprintf(stderr, "vergence_host: validation: %s\n", data->pMessage);
    return VK_FALSE;
}

void on_vgx_message(vgx_severity severity, const char *message, void *)
{
    std::fprintf(stderr, "vergence_host: vergence %s: %s\n",
                 severity == VGX_SEVERITY_ERROR ? "error" : severity == VGX_SEVERITY_WARNING ? "warning" : "info",
                 message);
}

#define CHECK(call)                                                                        \
    do {                                                                                   \
        VkResult r_ = (call);                                                              \
        if (r_ != VK_SUCCESS) {                                                            \
            std::fprintf(stderr, "vergence_host: error: %s failed (%d)\n", #call, (int)r_); \
            std::exit(2);                                                                  \
        }                                                                                  \
    } while (0)

struct Vk {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice phys = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    uint32_t family = 0;
    VkQueue queue = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties mem{};
};

void create_vk(Vk &vk, bool validate)
{
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "vergence_host";
    app.apiVersion = VK_API_VERSION_1_3;
    const char *layer = "VK_LAYER_KHRONOS_validation", *ext = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    mi.pfnUserCallback = on_message;
    VkValidationFeatureEnableEXT sync = VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT;
    VkValidationFeaturesEXT vf{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
    vf.enabledValidationFeatureCount = 1;
    vf.pEnabledValidationFeatures = &sync;
    VkInstanceCreateInfo ii{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ii.pApplicationInfo = &app;
    if (validate) {
        ii.enabledLayerCount = 1;
        ii.ppEnabledLayerNames = &layer;
        ii.enabledExtensionCount = 1;
        ii.ppEnabledExtensionNames = &ext;
        ii.pNext = &vf;
    }
    CHECK(vkCreateInstance(&ii, nullptr, &vk.instance));
    if (validate) {
        auto create = (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(vk.instance,
                                                                                "vkCreateDebugUtilsMessengerEXT");
        CHECK(create(vk.instance, &mi, nullptr, &vk.messenger));
    }
    uint32_t n = 0;
    vkEnumeratePhysicalDevices(vk.instance, &n, nullptr);
    std::vector<VkPhysicalDevice> devs(n);
    vkEnumeratePhysicalDevices(vk.instance, &n, devs.data());
    // Everything a device lacks, at once (this host's eyes tessellate: a warp context's requirements).
    std::string missing = "a Vulkan device";
    for (VkPhysicalDevice p : devs) {
        const char *names[16];
        uint32_t count = 0;
        if (vgx_get_missing_requirements(p, VGX_CONTEXT_WARP, names, 16, &count) == VGX_SUCCESS) {
            vk.phys = p;
            break;
        }
        missing.clear();
        for (uint32_t i = 0; i < count && i < 16; i++)
            missing += (i ? ", " : "") + std::string(names[i]);
    }
    if (!vk.phys) {
        std::fprintf(stderr, "vergence_host: error: no device has what vergence needs (missing %s)\n", missing.c_str());
        std::exit(2);
    }
    vkGetPhysicalDeviceMemoryProperties(vk.phys, &vk.mem);
    uint32_t nf = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(vk.phys, &nf, nullptr);
    std::vector<VkQueueFamilyProperties> fams(nf);
    vkGetPhysicalDeviceQueueFamilyProperties(vk.phys, &nf, fams.data());
    for (uint32_t i = 0; i < nf; i++)
        if ((fams[i].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
            (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) {
            vk.family = i;
            break;
        }
    // What vergence asks the host to enable (vergence.h, "Device requirements").
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    f13.dynamicRendering = f13.synchronization2 = f13.maintenance4 = VK_TRUE;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.pNext = &f13;
    f12.hostQueryReset = f12.scalarBlockLayout = VK_TRUE;
    VkPhysicalDeviceFeatures2 f{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f.pNext = &f12;
    f.features.shaderStorageImageWriteWithoutFormat = f.features.drawIndirectFirstInstance = VK_TRUE;
    f.features.tessellationShader = VK_TRUE; // this renderer's eyes: vergence's warp tessellates
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = vk.family;
    qi.queueCount = 1;
    qi.pQueuePriorities = &prio;
    uint32_t next = 0;
    const char *const *exts = vgx_device_extensions(&next);
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    di.pNext = &f;
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    di.enabledExtensionCount = next;
    di.ppEnabledExtensionNames = exts;
    CHECK(vkCreateDevice(vk.phys, &di, nullptr, &vk.device));
    vkGetDeviceQueue(vk.device, vk.family, 0, &vk.queue);
}

uint32_t memory_type(const Vk &vk, uint32_t bits, VkMemoryPropertyFlags want)
{
    for (uint32_t i = 0; i < vk.mem.memoryTypeCount; i++)
        if ((bits & (1u << i)) && (vk.mem.memoryTypes[i].propertyFlags & want) == want)
            return i;
    std::fprintf(stderr, "vergence_host: error: no suitable memory type\n");
    std::exit(2);
}

VkDeviceMemory allocate(const Vk &vk, const VkMemoryRequirements &req, VkMemoryPropertyFlags want)
{
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = memory_type(vk, req.memoryTypeBits, want);
    VkDeviceMemory m;
    CHECK(vkAllocateMemory(vk.device, &ai, nullptr, &m));
    return m;
}

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    void *mapped = nullptr;
};

Buffer make_buffer(const Vk &vk, VkDeviceSize size, VkBufferUsageFlags usage)
{
    Buffer b;
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = size;
    bi.usage = usage;
    CHECK(vkCreateBuffer(vk.device, &bi, nullptr, &b.buffer));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(vk.device, b.buffer, &req);
    b.memory = allocate(vk, req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    CHECK(vkBindBufferMemory(vk.device, b.buffer, b.memory, 0));
    CHECK(vkMapMemory(vk.device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped));
    return b;
}

void free_buffer(const Vk &vk, Buffer &b)
{
    vkDestroyBuffer(vk.device, b.buffer, nullptr);
    vkFreeMemory(vk.device, b.memory, nullptr);
}

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
};

Image make_image(const Vk &vk, VkFormat format, uint32_t w, uint32_t h, VkImageUsageFlags usage,
                 VkImageAspectFlags aspect)
{
    Image im;
    VkImageCreateInfo ii{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ii.imageType = VK_IMAGE_TYPE_2D;
    ii.format = format;
    ii.extent = {w, h, 1};
    ii.mipLevels = ii.arrayLayers = 1;
    ii.samples = VK_SAMPLE_COUNT_1_BIT;
    ii.tiling = VK_IMAGE_TILING_OPTIMAL;
    ii.usage = usage;
    CHECK(vkCreateImage(vk.device, &ii, nullptr, &im.image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(vk.device, im.image, &req);
    im.memory = allocate(vk, req, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    CHECK(vkBindImageMemory(vk.device, im.image, im.memory, 0));
    VkImageViewCreateInfo vi{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vi.image = im.image;
    vi.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vi.format = format;
    vi.subresourceRange = {aspect, 0, 1, 0, 1};
    CHECK(vkCreateImageView(vk.device, &vi, nullptr, &im.view));
    return im;
}

void free_image(const Vk &vk, Image &im)
{
    vkDestroyImageView(vk.device, im.view, nullptr);
    vkDestroyImage(vk.device, im.image, nullptr);
    vkFreeMemory(vk.device, im.memory, nullptr);
}

void barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
             VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stage,
             VkAccessFlags2 dst_access)
{
    VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
    b.srcStageMask = src_stage;
    b.srcAccessMask = src_access;
    b.dstStageMask = dst_stage;
    b.dstAccessMask = dst_access;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, 1, 0, 1};
    VkDependencyInfo d{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
    d.imageMemoryBarrierCount = 1;
    d.pImageMemoryBarriers = &b;
    vkCmdPipelineBarrier2(cmd, &d);
}

VkShaderModule shader(const Vk &vk, const uint32_t *code, size_t size)
{
    VkShaderModuleCreateInfo si{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    si.codeSize = size;
    si.pCode = code;
    VkShaderModule m;
    CHECK(vkCreateShaderModule(vk.device, &si, nullptr, &m));
    return m;
}

// Per render (the frame, or one keyframe tile): the camera of its time and
// of the two times its motion goes to, and the viewport motion is measured in.
struct View {
    float vp[16], vp_prev[16], vp_next[16];
    float view_z[4];   // row 2 of the view matrix: view-space z
    float viewport[4]; // width, height of the render target's viewport
};
const VkDeviceSize VIEW_STRIDE = 256; // minUniformBufferOffsetAlignment is at most 256

struct Push {
    float color[4]; // shaded: the material's base colour
    float saliency;
    uint32_t id;
};

// The G-buffer formats, in the fragment shader's output order: the four
// vergence reads, then the shaded colour the SDK's eyes move.
const VkFormat GBUFFER_FORMATS[5] = {VK_FORMAT_R32_SFLOAT, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R32G32B32A32_SFLOAT,
                                     VK_FORMAT_R32_UINT, VK_FORMAT_R8G8B8A8_UNORM};
const float SKY[4] = {0.78f, 0.86f, 0.95f, 1.0f}; // host_eye.frag's fog colour, the eyes' clear colour

// This renderer's pipeline kit: one descriptor set, push constants, vec3
// position streams, depth-tested colour attachments, dynamic viewport.
struct PipelineDesc {
    std::vector<std::pair<VkShaderStageFlagBits, VkShaderModule>> stages; // destroyed by create_pipeline
    uint32_t streams;                 // vec3 vertex streams, one binding and location each
    bool patches;                     // 3-point patches (tessellation) instead of triangles
    const VkFormat *colors;
    uint32_t color_count;
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    VkPushConstantRange push;
};

struct Pipeline {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipe;
    VkDescriptorPool pool;
    VkDescriptorSet set;
};

Pipeline create_pipeline(const Vk &vk, const PipelineDesc &d)
{
    Pipeline p;
    VkDescriptorSetLayoutCreateInfo sl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    sl.bindingCount = (uint32_t)d.bindings.size(), sl.pBindings = d.bindings.data();
    CHECK(vkCreateDescriptorSetLayout(vk.device, &sl, nullptr, &p.set_layout));
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.setLayoutCount = 1, li.pSetLayouts = &p.set_layout;
    li.pushConstantRangeCount = 1, li.pPushConstantRanges = &d.push;
    CHECK(vkCreatePipelineLayout(vk.device, &li, nullptr, &p.layout));
    std::vector<VkDescriptorPoolSize> ps;
    for (const VkDescriptorSetLayoutBinding &b : d.bindings)
        ps.push_back({b.descriptorType, b.descriptorCount});
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.maxSets = 1, pi.poolSizeCount = (uint32_t)ps.size(), pi.pPoolSizes = ps.data();
    CHECK(vkCreateDescriptorPool(vk.device, &pi, nullptr, &p.pool));
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = p.pool, ai.descriptorSetCount = 1, ai.pSetLayouts = &p.set_layout;
    CHECK(vkAllocateDescriptorSets(vk.device, &ai, &p.set));

    std::vector<VkPipelineShaderStageCreateInfo> st;
    for (const auto &[stage, module] : d.stages) {
        VkPipelineShaderStageCreateInfo si{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        si.stage = stage, si.module = module, si.pName = "main";
        st.push_back(si);
    }
    std::vector<VkVertexInputBindingDescription> vb;
    std::vector<VkVertexInputAttributeDescription> va;
    for (uint32_t i = 0; i < d.streams; i++) {
        vb.push_back({i, 12, VK_VERTEX_INPUT_RATE_VERTEX});
        va.push_back({i, i, VK_FORMAT_R32G32B32_SFLOAT, 0});
    }
    VkPipelineVertexInputStateCreateInfo vin{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vin.vertexBindingDescriptionCount = d.streams, vin.pVertexBindingDescriptions = vb.data();
    vin.vertexAttributeDescriptionCount = d.streams, vin.pVertexAttributeDescriptions = va.data();
    VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    ia.topology = d.patches ? VK_PRIMITIVE_TOPOLOGY_PATCH_LIST : VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineTessellationStateCreateInfo ts{VK_STRUCTURE_TYPE_PIPELINE_TESSELLATION_STATE_CREATE_INFO};
    ts.patchControlPoints = 3;
    VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    vp.viewportCount = vp.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    rs.cullMode = VK_CULL_MODE_NONE; // single-sided surfaces seen from behind still occlude
    rs.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
    VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    ds.depthTestEnable = ds.depthWriteEnable = VK_TRUE;
    ds.depthCompareOp = VK_COMPARE_OP_LESS;
    std::vector<VkPipelineColorBlendAttachmentState> cb(d.color_count);
    for (VkPipelineColorBlendAttachmentState &c : cb)
        c = {}, c.colorWriteMask = 0xf;
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = d.color_count, blend.pAttachments = cb.data();
    VkDynamicState dyn[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dy{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dy.dynamicStateCount = 2, dy.pDynamicStates = dyn;
    VkPipelineRenderingCreateInfo ri{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    ri.colorAttachmentCount = d.color_count, ri.pColorAttachmentFormats = d.colors;
    ri.depthAttachmentFormat = VK_FORMAT_D32_SFLOAT;
    VkGraphicsPipelineCreateInfo gi{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    gi.pNext = &ri;
    gi.stageCount = (uint32_t)st.size(), gi.pStages = st.data();
    gi.pVertexInputState = &vin, gi.pInputAssemblyState = &ia, gi.pTessellationState = d.patches ? &ts : nullptr;
    gi.pViewportState = &vp, gi.pRasterizationState = &rs, gi.pMultisampleState = &ms, gi.pDepthStencilState = &ds;
    gi.pColorBlendState = &blend, gi.pDynamicState = &dy, gi.layout = p.layout;
    CHECK(vkCreateGraphicsPipelines(vk.device, VK_NULL_HANDLE, 1, &gi, nullptr, &p.pipe));
    for (const auto &stage : d.stages)
        vkDestroyShaderModule(vk.device, stage.second, nullptr);
    return p;
}

void destroy_pipeline(const Vk &vk, Pipeline &p)
{
    vkDestroyPipeline(vk.device, p.pipe, nullptr);
    vkDestroyPipelineLayout(vk.device, p.layout, nullptr);
    vkDestroyDescriptorPool(vk.device, p.pool, nullptr);
    vkDestroyDescriptorSetLayout(vk.device, p.set_layout, nullptr);
}

// The G-buffer: linear depth, saliency (alpha), motion to two other times
// and the object id; three position streams (t, prev, next); the views at
// a dynamic offset.
Pipeline create_gbuffer_pipeline(const Vk &vk, VkBuffer views)
{
    PipelineDesc d;
    d.stages = {{VK_SHADER_STAGE_VERTEX_BIT, shader(vk, host_gbuffer_vert, sizeof host_gbuffer_vert)},
                {VK_SHADER_STAGE_FRAGMENT_BIT, shader(vk, host_gbuffer_frag, sizeof host_gbuffer_frag)}};
    d.streams = 3, d.patches = false;
    d.colors = GBUFFER_FORMATS, d.color_count = 5;
    d.bindings = {{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1,
                   VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
    d.push = {VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(Push)};
    Pipeline p = create_pipeline(vk, d);
    VkDescriptorBufferInfo bi{views, 0, sizeof(View)};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = p.set, w.descriptorCount = 1, w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
    w.pBufferInfo = &bi;
    vkUpdateDescriptorSets(vk.device, 1, &w, 0, nullptr);
    return p;
}

// Starts dynamic rendering into colour images (cleared to their values, their
// old contents discarded) and a z-buffer of w x h.
void begin_targets(VkCommandBuffer cmd, const std::vector<const Image *> &colors,
                   const std::vector<VkClearColorValue> &clears, const Image &zbuffer, uint32_t w, uint32_t h)
{
    const VkPipelineStageFlags2 OUT = VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT;
    const VkPipelineStageFlags2 TESTS =
        VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
    std::vector<VkRenderingAttachmentInfo> att;
    for (size_t i = 0; i < colors.size(); i++) {
        barrier(cmd, colors[i]->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0, OUT,
                VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
        VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        a.imageView = colors[i]->view;
        a.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        a.clearValue.color = clears[i];
        att.push_back(a);
    }
    barrier(cmd, zbuffer.image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
            VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL, TESTS, VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, TESTS,
            VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT);
    VkRenderingAttachmentInfo dat{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    dat.imageView = zbuffer.view;
    dat.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    dat.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    dat.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    dat.clearValue.depthStencil = {1.0f, 0};
    VkRenderingInfo ri{VK_STRUCTURE_TYPE_RENDERING_INFO};
    ri.renderArea = {{0, 0}, {w, h}};
    ri.layerCount = 1;
    ri.colorAttachmentCount = (uint32_t)att.size();
    ri.pColorAttachments = att.data();
    ri.pDepthAttachment = &dat;
    vkCmdBeginRendering(cmd, &ri);
    VkViewport viewport{0, 0, (float)w, (float)h, 0, 1};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
}

// Ends it: the colour images go to `layout`, their writes available to `stage` / `access`.
void end_targets(VkCommandBuffer cmd, const std::vector<const Image *> &colors, VkImageLayout layout,
                 VkPipelineStageFlags2 stage, VkAccessFlags2 access)
{
    vkCmdEndRendering(cmd);
    for (const Image *im : colors)
        barrier(cmd, im->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, layout,
                VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, stage, access);
}

// A G-buffer of this renderer: the four images vergence reads, the shaded
// colour and a z-buffer.
struct GBuffer {
    Image images[5];
    Image zbuffer;
    uint32_t width = 0, height = 0;
};

GBuffer make_gbuffer(const Vk &vk, uint32_t w, uint32_t h)
{
    GBuffer g;
    g.width = w, g.height = h;
    for (int i = 0; i < 5; i++)
        g.images[i] = make_image(vk, GBUFFER_FORMATS[i], w, h,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_STORAGE_BIT |
                                     VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                 VK_IMAGE_ASPECT_COLOR_BIT); // sampled: the warp reads the frame's depth
    g.zbuffer = make_image(vk, VK_FORMAT_D32_SFLOAT, w, h, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                           VK_IMAGE_ASPECT_DEPTH_BIT);
    return g;
}

void free_gbuffer(const Vk &vk, GBuffer &g)
{
    for (Image &im : g.images)
        free_image(vk, im);
    free_image(vk, g.zbuffer);
}

vgx_gbuffer as_vgx(const GBuffer &g)
{
    vgx_gbuffer v = {};
    vgx_image *dst[4] = {&v.depth, &v.saliency, &v.motion, &v.ids};
    for (int i = 0; i < 4; i++)
        *dst[i] = {g.images[i].image, g.images[i].view, VK_IMAGE_LAYOUT_GENERAL};
    return v;
}

// One render of the scene into the G-buffer (the frame, or one keyframe
// tile of the atlas): its streams at three times and its View slot.
struct Render {
    uint32_t slot;                  // index into the views and the vertex streams
    VkRect2D scissor;
};

// Renders into g: clears it (depth at the far plane, the colour to the sky,
// the rest 0), draws each
// render in its scissor, and leaves the four images in GENERAL with their
// writes available to compute shaders (what vgx_dispatch is told).
void render_gbuffer(VkCommandBuffer cmd, const GBuffer &g, const Pipeline &p, const Scene &scene, VkBuffer vbuf,
                    VkBuffer ibuf, const std::vector<Render> &renders)
{
    // The last frame's contents are not needed: vergence has read them.
    std::vector<const Image *> colors = {&g.images[0], &g.images[1], &g.images[2], &g.images[3], &g.images[4]};
    VkClearColorValue sky;
    std::memcpy(sky.float32, SKY, sizeof SKY);
    begin_targets(cmd, colors, {{{(float)scene.zfar, 0, 0, 0}}, {}, {}, {}, sky}, g.zbuffer, g.width, g.height);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.pipe);
    vkCmdBindIndexBuffer(cmd, ibuf, 0, VK_INDEX_TYPE_UINT32);
    VkDeviceSize stream = (VkDeviceSize)scene.vertex_count * 12;
    for (const Render &r : renders) {
        vkCmdSetScissor(cmd, 0, 1, &r.scissor);
        uint32_t offset = (uint32_t)(r.slot * VIEW_STRIDE);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.layout, 0, 1, &p.set, 1, &offset);
        VkBuffer bufs[3] = {vbuf, vbuf, vbuf};
        VkDeviceSize offs[3] = {(3 * r.slot + 0) * stream, (3 * r.slot + 1) * stream, (3 * r.slot + 2) * stream};
        vkCmdBindVertexBuffers(cmd, 0, 3, bufs, offs);
        for (const Draw &d : scene.draws) {
            Push push{{d.color[0], d.color[1], d.color[2], d.color[3]}, d.saliency, d.id};
            vkCmdPushConstants(cmd, p.layout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof push, &push);
            vkCmdDrawIndexed(cmd, d.index_count, 1, d.first_index, 0, 0);
        }
    }
    end_targets(cmd, colors, VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT,
                VK_ACCESS_2_SHADER_STORAGE_READ_BIT);
}

// Fills slot `slot` of the views and the streams: the scene at t (and its
// camera), its motion to t_prev and t_next, all through `atlas` (identity
// for the frame) with a viewport of vw x vh.
void set_render(const Scene &scene, uint32_t W, uint32_t H, uint32_t slot, double t, double t_prev, double t_next,
                const float *atlas, float vw, float vh, Buffer &views, Buffer &vbuf, double known_until = INFINITY,
                double step = 0)
{
    double times[3] = {t, t_prev, t_next};
    View v{};
    float *dst[3] = {v.vp, v.vp_prev, v.vp_next};
    Mat4 a = identity();
    if (atlas)
        std::memcpy(a.m, atlas, 64);
    VkDeviceSize stream = (VkDeviceSize)scene.vertex_count * 3;
    for (int k = 0; k < 3; k++) {
        Pose pose;
        if (std::isinf(known_until))
            pose_at(scene, times[k], pose);
        else
            pose_known(scene, times[k], known_until, step, pose);
        Mat4 view, proj;
        camera_matrices(scene, pose, (float)W / (float)H, view, proj);
        Mat4 vp = mul(a, mul(proj, view));
        std::memcpy(dst[k], vp.m, 64);
        if (k == 0)
            for (int c = 0; c < 4; c++)
                v.view_z[c] = view.m[c * 4 + 2];
        std::memcpy((float *)vbuf.mapped + (3 * slot + k) * stream, pose.positions.data(), stream * 4);
    }
    v.viewport[0] = vw, v.viewport[1] = vh;
    std::memcpy((char *)views.mapped + slot * VIEW_STRIDE, &v, sizeof v);
}

// ---------------------------------------------------------------------------
// The stereo pair: this renderer's geometry, tessellated and warped by
// vergence's GLSL (include/vergence/warp.glsl), once per eye.
// ---------------------------------------------------------------------------

struct EyePush {
    float color[4];
    uint32_t right_eye;
};

const VkFormat EYE_FORMATS[2] = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R32_SFLOAT}; // colour, centre-view x
const float NO_SURFACE = -1e30f; // the centre-view x of an eye pixel that shows sky

// The eyes: the warp's four bindings (vgx_warp_bindings) in set 0.
Pipeline create_eye_pipeline(const Vk &vk, const vgx_warp &warp, VkImageView depth_view, VkSampler sampler)
{
    const VkShaderStageFlags stages = VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT |
                                      VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    PipelineDesc d;
    d.stages = {{VK_SHADER_STAGE_VERTEX_BIT, shader(vk, host_eye_vert, sizeof host_eye_vert)},
                {VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT, shader(vk, host_eye_tesc, sizeof host_eye_tesc)},
                {VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT, shader(vk, host_eye_tese, sizeof host_eye_tese)},
                {VK_SHADER_STAGE_FRAGMENT_BIT, shader(vk, host_eye_frag, sizeof host_eye_frag)}};
    d.streams = 1, d.patches = true;
    d.colors = EYE_FORMATS, d.color_count = 2;
    d.bindings.resize(4);
    vgx_warp_bindings(stages, d.bindings.data()); // what warp.glsl reads
    d.push = {VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(EyePush)};
    Pipeline p = create_pipeline(vk, d);
    // The handles vergence gives stay the same for the context's life: written once.
    VkDescriptorBufferInfo constants{warp.constants, 0, warp.constants_size}, curve{warp.curve, 0, warp.curve_size};
    VkDescriptorImageInfo depth{sampler, depth_view, VK_IMAGE_LAYOUT_GENERAL};
    VkDescriptorImageInfo target{sampler, warp.target.view, warp.target.layout};
    VkWriteDescriptorSet w[4];
    for (uint32_t i = 0; i < 4; i++) {
        w[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w[i].dstSet = p.set, w[i].dstBinding = i, w[i].descriptorCount = 1;
        w[i].descriptorType = d.bindings[i].descriptorType;
    }
    w[0].pBufferInfo = &constants, w[1].pImageInfo = &depth, w[2].pImageInfo = &target, w[3].pBufferInfo = &curve;
    vkUpdateDescriptorSets(vk.device, 4, w, 0, nullptr);
    return p;
}

struct Eye {
    Image color, centre_x, zbuffer;
};

Eye make_eye(const Vk &vk, uint32_t w, uint32_t h)
{
    Eye e;
    e.color = make_image(vk, EYE_FORMATS[0], w, h, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                         VK_IMAGE_ASPECT_COLOR_BIT);
    e.centre_x = make_image(vk, EYE_FORMATS[1], w, h,
                            VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                            VK_IMAGE_ASPECT_COLOR_BIT);
    e.zbuffer = make_image(vk, VK_FORMAT_D32_SFLOAT, w, h, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                           VK_IMAGE_ASPECT_DEPTH_BIT);
    return e;
}

void free_eye(const Vk &vk, Eye &e)
{
    free_image(vk, e.color);
    free_image(vk, e.centre_x);
    free_image(vk, e.zbuffer);
}

// One eye: the sky, then every draw as patches; leaves the colour and the
// centre-view x in TRANSFER_SRC_OPTIMAL.
void render_eye(VkCommandBuffer cmd, const Eye &e, const Pipeline &p, const Scene &scene, VkBuffer vbuf,
                VkBuffer ibuf, uint32_t w, uint32_t h, bool right)
{
    std::vector<const Image *> colors = {&e.color, &e.centre_x};
    // Sky; no surface (a centre-view x may be negative: a point just left of
    // the centre view that the right eye shows).
    VkClearColorValue sky;
    std::memcpy(sky.float32, SKY, sizeof SKY);
    begin_targets(cmd, colors, {sky, {{NO_SURFACE, 0, 0, 0}}}, e.zbuffer, w, h);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.pipe);
    VkRect2D scissor{{0, 0}, {w, h}};
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p.layout, 0, 1, &p.set, 0, nullptr);
    VkDeviceSize zero = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &vbuf, &zero); // slot 0: the frame's positions
    vkCmdBindIndexBuffer(cmd, ibuf, 0, VK_INDEX_TYPE_UINT32);
    // At most 16 patches a draw: lavapipe corrupts a draw whose tessellation
    // makes more than 65,535 vertices, silently (a level-64 patch makes about
    // 3,200); bounded draws cost nothing on a GPU.
    const uint32_t PATCHES_PER_DRAW = 16;
    for (const Draw &d : scene.draws) {
        EyePush push{{d.color[0], d.color[1], d.color[2], d.color[3]}, right ? 1u : 0u};
        vkCmdPushConstants(cmd, p.layout, VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                           sizeof push, &push);
        for (uint32_t at = 0; at < d.index_count; at += 3 * PATCHES_PER_DRAW) {
            uint32_t n = d.index_count - at < 3 * PATCHES_PER_DRAW ? d.index_count - at : 3 * PATCHES_PER_DRAW;
            vkCmdDrawIndexed(cmd, n, 1, d.first_index + at, 0, 0);
        }
    }
    end_targets(cmd, colors, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT,
                VK_ACCESS_2_TRANSFER_READ_BIT);
}

// Copies a w x h colour image into `buffer` at `offset`: out of `layout`
// (whatever wrote it finished) and back into it afterwards.
void copy_out(VkCommandBuffer cmd, VkImage image, VkImageLayout layout, VkBuffer buffer, VkDeviceSize offset,
              uint32_t w, uint32_t h)
{
    barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
            VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, VK_ACCESS_2_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
            VK_ACCESS_2_TRANSFER_READ_BIT);
    VkBufferImageCopy region{};
    region.bufferOffset = offset;
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {w, h, 1};
    vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer, 1, &region);
    barrier(cmd, image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout,
            VK_PIPELINE_STAGE_2_COPY_BIT, 0, VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT, 0);
}

// Writes a file whole or not at all: into path.tmp, then renamed.
template <typename Body> bool write_file(const std::string &path, Body body)
{
    std::string tmp = path + ".tmp";
    FILE *f = std::fopen(tmp.c_str(), "wb");
    if (!f)
        return false;
    bool ok = body(f);
    ok = std::fclose(f) == 0 && ok;
    if (!ok)
        std::remove(tmp.c_str());
    return ok && std::rename(tmp.c_str(), path.c_str()) == 0;
}

// PPM, 8-bit RGB: the eyes for people.
bool write_ppm(const std::string &path, const uint8_t *rgba, uint32_t w, uint32_t h)
{
    return write_file(path, [&](FILE *f) {
        bool ok = std::fprintf(f, "P6\n%u %u\n255\n", w, h) > 0;
        for (size_t i = 0; i < (size_t)w * h && ok; i++)
            ok = std::fwrite(rgba + 4 * i, 1, 3, f) == 3;
        return ok;
    });
}

// PFM, one channel, little-endian, rows bottom to top (the format's order).
bool write_pfm(const std::string &path, const float *data, uint32_t w, uint32_t h)
{
    return write_file(path, [&](FILE *f) {
        bool ok = std::fprintf(f, "Pf\n%u %u\n-1.0\n", w, h) > 0;
        for (uint32_t y = h; y-- > 0 && ok;)
            ok = std::fwrite(data + (size_t)y * w, 4, w, f) == w;
        return ok;
    });
}

int usage(const char *why)
{
    std::fprintf(stderr,
                 "vergence_host: error: %s\n"
                 "usage: vergence_host --scene FILE --out DIR [--size WxH] [--time T] [--frames N] [--fps HZ]\n"
                 "                     [--interaxial M] [--convergence M] [--causal] [--validate]\n",
                 why);
    return 1;
}

} // namespace

// Renders frames round(T fps) .. + N - 1 of the scene and writes, for frame
// i of them, frame_NNNN_h.pfm and _f.pfm, and for the last one also its depth
// and g (the names `vergence capture` uses) and its stereo pair:
// frame_NNNN_left.ppm and _right.ppm, and _left_x.pfm and _right_x.pfm, the
// centre-view x of the surface each eye pixel shows (-1e30: none).
int main(int argc, char **argv)
{
    std::string scene_path, out_dir;
    uint32_t W = 960, H = 540;
    double t0 = 0, fps = 60, interaxial = 0.25, convergence = 6.0;
    int frames = 1;
    bool validate = false, causal = false;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        bool has = i + 1 < argc;
        if (a == "--validate")
            validate = true;
        else if (a == "--causal")
            causal = true;
        else if (a == "--scene" && has)
            scene_path = argv[++i];
        else if (a == "--out" && has)
            out_dir = argv[++i];
        else if (a == "--size" && has) {
            if (std::sscanf(argv[++i], "%ux%u", &W, &H) != 2 || W < 8 || H < 8 || W > 8192 || H > 8192)
                return usage("--size: give WxH, 8 to 8192 each");
        } else if (a == "--time" && has)
            t0 = std::atof(argv[++i]);
        else if (a == "--frames" && has)
            frames = std::atoi(argv[++i]);
        else if (a == "--fps" && has)
            fps = std::atof(argv[++i]);
        else if (a == "--interaxial" && has)
            interaxial = std::atof(argv[++i]);
        else if (a == "--convergence" && has)
            convergence = std::atof(argv[++i]);
        else
            return usage(("unknown or incomplete option " + a).c_str());
    }
    if (scene_path.empty() || out_dir.empty())
        return usage("--scene and --out are required");
    if (frames < 1 || frames > 100000 || !(fps > 0 && fps <= 1000) || !(t0 >= 0))
        return usage("--frames 1 to 100000, --fps in (0, 1000], --time >= 0");
    if (mkdir(out_dir.c_str(), 0777) != 0 && errno != EEXIST)
        return usage(("--out " + out_dir + ": cannot create the folder").c_str());
    if (VGX_VERSION_MAJOR(vgx_version()) != VGX_VERSION_MAJOR(VGX_HEADER_VERSION)) {
        std::fprintf(stderr, "vergence_host: error: libvergence %u.%u does not match the header\n",
                     VGX_VERSION_MAJOR(vgx_version()), VGX_VERSION_MINOR(vgx_version()));
        return 2;
    }
    Scene scene;
    if (!load_scene(scene_path, scene))
        return 1;

    Vk vk;
    create_vk(vk, validate);

    // The SDK's context over this renderer's device.
    vgx_context_desc cd = {};
    cd.header_version = VGX_HEADER_VERSION;
    cd.instance = vk.instance;
    cd.physical_device = vk.phys;
    cd.device = vk.device;
    cd.queue_family = vk.family;
    cd.width = W;
    cd.height = H;
    cd.fps = fps;
    cd.look_ahead = causal ? VGX_LOOK_AHEAD_CAUSAL : VGX_LOOK_AHEAD_PREDICTED;
    // The warp for this renderer's tessellated eyes, and the SDK's own eyes
    // beside them (the pair a host without tessellation would show).
    cd.flags = VGX_CONTEXT_SALIENCY | VGX_CONTEXT_OPTIMIZE | VGX_CONTEXT_WARP | VGX_CONTEXT_EYES;
    if (validate) // the instance has VK_EXT_debug_utils then: the SDK's objects and passes get names
        cd.flags |= VGX_CONTEXT_DEBUG_UTILS;
    cd.message = on_vgx_message;
    // What the context will hold of this device's memory, before making it.
    vgx_memory_footprint fp;
    vgx_result vr = vgx_get_memory_footprint(&cd, &fp);
    if (vr != VGX_SUCCESS) {
        std::fprintf(stderr, "vergence_host: error: vgx_get_memory_footprint: %s\n", vgx_result_name(vr));
        return 2;
    }
    std::printf("vergence_host: the context holds %.2f MiB of device memory in %u blocks (%.2f MiB host-visible; "
                "%.2f MiB more while a configuration change is in flight)\n", fp.bytes / 1048576.0, fp.blocks,
                fp.host_visible_bytes / 1048576.0, fp.configuration_bytes / 1048576.0);
    vgx_context *ctx = nullptr;
    vr = vgx_context_create(&cd, &ctx);
    if (vr != VGX_SUCCESS) {
        std::fprintf(stderr, "vergence_host: error: vgx_context_create: %s\n", vgx_result_name(vr));
        return 2;
    }
    vgx_context_info info;
    vgx_get_info(ctx, &info);
    uint32_t AW = info.atlas_width, AH = info.atlas_height;

    // This renderer's resources: its frame and keyframe G-buffers, the
    // scene's streams and views (slot 0 the frame, 1.. the keyframes).
    const uint32_t MAX_RENDERS = 1 + info.atlas_tiles;
    GBuffer frame_gb = make_gbuffer(vk, W, H), atlas_gb = make_gbuffer(vk, AW, AH);
    Buffer vbuf = make_buffer(vk, (VkDeviceSize)MAX_RENDERS * 3 * scene.vertex_count * 12,
                              VK_BUFFER_USAGE_VERTEX_BUFFER_BIT);
    Buffer ibuf = make_buffer(vk, scene.indices.size() * 4, VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    Buffer views = make_buffer(vk, MAX_RENDERS * VIEW_STRIDE, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT);
    std::memcpy(ibuf.mapped, scene.indices.data(), scene.indices.size() * 4);
    VkDeviceSize map_bytes = (VkDeviceSize)W * H * 4;
    Buffer readback = make_buffer(vk, 4 * map_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT);
    Buffer eye_readback = make_buffer(vk, 4 * map_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT); // colour, x per eye
    Buffer sdk_readback = make_buffer(vk, 2 * map_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT); // the SDK's eyes
    Pipeline pipe = create_gbuffer_pipeline(vk, views.buffer);
    VkSampler sampler; // the warp reads its maps with texelFetch: any sampler
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    CHECK(vkCreateSampler(vk.device, &sci, nullptr, &sampler));
    vgx_warp warp;
    vgx_get_warp(ctx, &warp);
    Pipeline eye_pipe = create_eye_pipeline(vk, warp, frame_gb.images[0].view, sampler);
    Eye eyes[2] = {make_eye(vk, W, H), make_eye(vk, W, H)};

    VkCommandPool pool;
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = vk.family;
    CHECK(vkCreateCommandPool(vk.device, &pi, nullptr, &pool));
    VkCommandBuffer cmd;
    VkCommandBufferAllocateInfo ca{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ca.commandPool = pool;
    ca.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ca.commandBufferCount = 1;
    CHECK(vkAllocateCommandBuffers(vk.device, &ca, &cmd));

    const double yfov = scene.yfov;
    vgx_rig rig = {};
    rig.hfov_deg = 2.0 * std::atan(std::tan(0.5 * yfov) * W / H) * 180.0 / M_PI;
    rig.interaxial_m = interaxial;
    rig.convergence_m = convergence;
    int64_t first = (int64_t)std::llround(t0 * fps);
    int rc = 0;
    uint32_t keyframes_rendered = 0;
    vgx_frame_plan plan;
    for (int i = 0; i < frames && rc == 0; i++) {
        vr = vgx_begin_frame(ctx, first + i, &plan);
        if (vr != VGX_SUCCESS) {
            std::fprintf(stderr, "vergence_host: error: vgx_begin_frame: %s\n", vgx_result_name(vr));
            return 2;
        }
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        CHECK(vkBeginCommandBuffer(cmd, &bi));

        // 1. The keyframes vergence asks for: this renderer's scene at their
        //    (future) times, each into its tile of the atlas (--causal: as
        //    predicted from this frame and the one before).
        std::vector<Render> tiles;
        for (uint32_t k = 0; k < plan.keyframe_count; k++) {
            vgx_keyframe kf;
            vgx_get_keyframe(ctx, k, &kf);
            set_render(scene, W, H, 1 + k, kf.time_s, kf.prev_time_s, kf.next_time_s, kf.atlas_from_clip, (float)AW,
                       (float)AH, views, vbuf, causal ? plan.time_s : INFINITY, 1.0 / fps);
            tiles.push_back({1 + k, kf.scissor});
        }
        if (!tiles.empty())
            render_gbuffer(cmd, atlas_gb, pipe, scene, vbuf.buffer, ibuf.buffer, tiles);
        keyframes_rendered += plan.keyframe_count;
        // 2. The frame's own G-buffer, its motion to the neighbouring keyframes.
        set_render(scene, W, H, 0, plan.time_s, plan.prev_key_time_s, plan.next_key_time_s, nullptr, (float)W,
                   (float)H, views, vbuf);
        render_gbuffer(cmd, frame_gb, pipe, scene, vbuf.buffer, ibuf.buffer, {{0, {{0, 0}, {W, H}}}});

        // 3. vergence, recorded into the same command buffer.
        vgx_dispatch_desc dd = {};
        dd.command_buffer = cmd;
        dd.frame = as_vgx(frame_gb);
        dd.keyframes = as_vgx(atlas_gb);
        dd.rig = rig;
        std::memcpy(dd.view_proj, ((const View *)views.mapped)->vp, sizeof dd.view_proj); // slot 0: the frame
        dd.background_depth_m = (float)scene.zfar;
        dd.color = {frame_gb.images[4].image, frame_gb.images[4].view, VK_IMAGE_LAYOUT_GENERAL};
        vr = vgx_dispatch(ctx, &dd);
        if (vr != VGX_SUCCESS) {
            std::fprintf(stderr, "vergence_host: error: vgx_dispatch: %s\n", vgx_result_name(vr));
            return 2;
        }

        // 4. The stereo pair of the frame it writes (the last): this
        //    renderer's geometry warped by vergence's GLSL.
        bool last = i + 1 == frames;
        for (int e = 0; e < 2 && last; e++) {
            render_eye(cmd, eyes[e], eye_pipe, scene, vbuf.buffer, ibuf.buffer, W, H, e == 1);
            const Image *src[2] = {&eyes[e].color, &eyes[e].centre_x};
            for (int k = 0; k < 2; k++) {
                VkBufferImageCopy region{};
                region.bufferOffset = (2 * e + k) * map_bytes;
                region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
                region.imageExtent = {W, H, 1};
                vkCmdCopyImageToBuffer(cmd, src[k]->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, eye_readback.buffer, 1,
                                       &region);
            }
        }

        // 4b. The SDK's own eyes of that frame (VGX_CONTEXT_EYES), for the test to compare.
        for (int e = 0; e < 2 && last; e++) {
            vgx_image eye;
            vgx_get_eye(ctx, (uint32_t)e, &eye);
            copy_out(cmd, eye.image, eye.layout, sdk_readback.buffer, e * map_bytes, W, H);
        }

        // 5. Copies of depth, g, h and f (the maps leave the dispatch in SHADER_READ_ONLY_OPTIMAL).
        VkImage copies[4] = {frame_gb.images[0].image, VK_NULL_HANDLE, VK_NULL_HANDLE, VK_NULL_HANDLE};
        VkImageLayout layouts[4] = {VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        const vgx_output outputs[3] = {VGX_OUTPUT_G, VGX_OUTPUT_H, VGX_OUTPUT_F};
        for (int k = 1; k < 4; k++) {
            vgx_image out;
            vgx_get_output(ctx, outputs[k - 1], &out);
            copies[k] = out.image;
        }
        for (int k = 0; k < 4; k++)
            copy_out(cmd, copies[k], layouts[k], readback.buffer, k * map_bytes, W, H);
        VkMemoryBarrier2 host{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2};
        host.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
        host.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
        host.dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT;
        host.dstAccessMask = VK_ACCESS_2_HOST_READ_BIT;
        VkDependencyInfo hd{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
        hd.memoryBarrierCount = 1;
        hd.pMemoryBarriers = &host;
        vkCmdPipelineBarrier2(cmd, &hd);
        CHECK(vkEndCommandBuffer(cmd));
        VkCommandBufferSubmitInfo ci{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
        ci.commandBuffer = cmd;
        VkSubmitInfo2 si{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
        si.commandBufferInfoCount = 1;
        si.pCommandBufferInfos = &ci;
        CHECK(vkQueueSubmit2(vk.queue, 1, &si, VK_NULL_HANDLE));
        CHECK(vkQueueWaitIdle(vk.queue)); // an example: one frame at a time

        const float *maps = (const float *)readback.mapped;
        static const char *const names[4] = {"depth", "g", "h", "f"};
        for (int k = last ? 0 : 2; k < 4; k++) {
            char name[64];
            std::snprintf(name, sizeof name, "/frame_%04d_%s.pfm", i, names[k]);
            if (!write_pfm(out_dir + name, maps + (size_t)k * W * H, W, H)) {
                std::fprintf(stderr, "vergence_host: error: %s%s: cannot write\n", out_dir.c_str(), name);
                rc = 2;
            }
        }
        for (int e = 0; e < 2 && last; e++) {
            const char *side = e ? "right" : "left";
            const uint8_t *eye = (const uint8_t *)eye_readback.mapped + (size_t)2 * e * map_bytes;
            char name[64], xname[64];
            std::snprintf(name, sizeof name, "/frame_%04d_%s.ppm", i, side);
            std::snprintf(xname, sizeof xname, "/frame_%04d_%s_x.pfm", i, side);
            if (!write_ppm(out_dir + name, eye, W, H) ||
                !write_pfm(out_dir + xname, (const float *)(eye + map_bytes), W, H)) {
                std::fprintf(stderr, "vergence_host: error: %s%s: cannot write\n", out_dir.c_str(), name);
                rc = 2;
            }
            // The SDK's eye: its colour, and its alpha (1 a surface, 0.5 a filled disocclusion, 0 none).
            const uint8_t *sdk = (const uint8_t *)sdk_readback.mapped + (size_t)e * map_bytes;
            std::vector<float> alpha((size_t)W * H);
            for (size_t p = 0; p < alpha.size(); p++)
                alpha[p] = sdk[4 * p + 3] / 255.0f;
            std::snprintf(name, sizeof name, "/frame_%04d_sdk_%s.ppm", i, side);
            std::snprintf(xname, sizeof xname, "/frame_%04d_sdk_%s_alpha.pfm", i, side);
            if (!write_ppm(out_dir + name, sdk, W, H) || !write_pfm(out_dir + xname, alpha.data(), W, H)) {
                std::fprintf(stderr, "vergence_host: error: %s%s: cannot write\n", out_dir.c_str(), name);
                rc = 2;
            }
        }
    }
    double lo = info.range_lo_arcmin, hi = info.range_hi_arcmin;
    std::printf("vergence_host: libvergence %u.%u.%u, %zu triangles, %ux%u, frames %lld..%lld, %u keyframes rendered "
                "(atlas %ux%u), h and f in [%.1f, %.1f] arcmin\n",
                VGX_VERSION_MAJOR(vgx_version()), VGX_VERSION_MINOR(vgx_version()), VGX_VERSION_PATCH(vgx_version()),
                scene.indices.size() / 3, W, H, (long long)first, (long long)(first + frames - 1), keyframes_rendered,
                AW, AH, lo, hi);

    vkDeviceWaitIdle(vk.device);
    vgx_context_destroy(ctx);
    vkDestroyCommandPool(vk.device, pool, nullptr);
    destroy_pipeline(vk, pipe);
    destroy_pipeline(vk, eye_pipe);
    vkDestroySampler(vk.device, sampler, nullptr);
    for (Eye &e : eyes)
        free_eye(vk, e);
    for (Buffer *b : {&readback, &eye_readback, &sdk_readback, &views, &ibuf, &vbuf})
        free_buffer(vk, *b);
    free_gbuffer(vk, atlas_gb);
    free_gbuffer(vk, frame_gb);
    vkDestroyDevice(vk.device, nullptr);
    if (vk.messenger) {
        auto destroy = (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(vk.instance,
                                                                                  "vkDestroyDebugUtilsMessengerEXT");
        destroy(vk.instance, vk.messenger, nullptr);
    }
    vkDestroyInstance(vk.instance, nullptr);
    if (g_validation_messages > 0) {
        std::fprintf(stderr, "vergence_host: %d validation messages\n", g_validation_messages);
        return 3;
    }
    return rc;
}
