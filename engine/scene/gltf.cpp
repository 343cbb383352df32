/* vergence — glTF 2.0 loading through tinygltf, one of the project's two C++
 * files (engine/flow/flow.cpp wraps OpenCV the same way).
 *
 * tinygltf (Debian's libtinygltf.so, 2.7.0) parses the JSON and reads the
 * buffers; everything it hands back is treated as untrusted: every index is
 * checked before use, every accessor's bufferView is located inside its
 * buffer here and its elements inside the bufferView in accessor.c. The
 * result is the plain C of scene.h; nothing refers to tinygltf afterwards.
 *
 * Bytes that tinygltf 2.7.0 would trust are checked first (container.c: GLB
 * chunks, JSON nesting), and images are not decoded by tinygltf (it indexes
 * image bufferViews without a range check and lets stb allocate whatever a
 * header claims): base-colour images are decoded in container.c after their
 * bytes and dimensions are checked. No exception leaves this file. */
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include <tiny_gltf.h>

extern "C" {
#include "core/io.h"
#include "core/log.h"
#include "scene_internal.h"
}

namespace {

using tinygltf::Model;

/* ------------------------------------------------------------------------- */
/* Small helpers                                                             */
/* ------------------------------------------------------------------------- */

std::string fmt(const char *f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char *f, ...)
{
    char buf[256];
    va_list ap;
    va_start(ap, f);
    std::vsnprintf(buf, sizeof buf, f, ap);
    va_end(ap);
    return buf;
}

/* double -> float without the undefined out-of-range conversion. */
float to_f(double v)
{
    if (v > FLT_MAX)
        return FLT_MAX;
    if (v < -FLT_MAX)
        return -FLT_MAX;
    return static_cast<float>(v);
}

void copy_name(char *dst, const std::string &src)
{
    std::snprintf(dst, SCENE_NAME_MAX, "%s", src.c_str());
}

template <typename T> T *alloc(size_t n)
{
    return static_cast<T *>(std::calloc(n ? n : 1, sizeof(T)));
}

bool valid(int index, size_t size)
{
    return index >= 0 && static_cast<size_t>(index) < size;
}

/* ------------------------------------------------------------------------- */
/* tinygltf callbacks                                                        */
/* ------------------------------------------------------------------------- */

/* Plain file access: URIs from the file get no ~ or $VAR expansion. */
bool fs_exists(const std::string &path, void *)
{
    struct stat st;
    return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string fs_expand(const std::string &path, void *)
{
    return path;
}

bool fs_read(std::vector<unsigned char> *out, std::string *err, const std::string &path, void *user)
{
    /* Every file the scene is read from, for the commands that must not write one (scene.files). */
    static_cast<std::vector<std::string> *>(user)->push_back(path);
    FILE *f = std::fopen(path.c_str(), "rb");
    if (!f) {
        *err = std::strerror(errno);
        return false;
    }
    struct stat st;
    if (fstat(fileno(f), &st) != 0 || st.st_size < 0 || st.st_size > 0x7fffffffLL) {
        std::fclose(f);
        *err = "unreadable or larger than 2 GiB";
        return false;
    }
    out->resize(static_cast<size_t>(st.st_size));
    size_t got = out->empty() ? 0 : std::fread(out->data(), 1, out->size(), f);
    std::fclose(f);
    if (got != out->size()) {
        *err = "short read";
        return false;
    }
    return true;
}

bool fs_write(std::string *, const std::string &, const std::vector<unsigned char> &, void *)
{
    return false;
}

/* Keeps the encoded bytes of URI images for our own decoding. For images in
 * bufferViews tinygltf passes a pointer it has not range-checked: ignored,
 * they are located with checks later. */
bool image_stash(tinygltf::Image *img, const int, std::string *, std::string *, int, int,
                 const unsigned char *bytes, int size, void *)
{
    if (img->bufferView < 0 && bytes && size > 0)
        img->image.assign(bytes, bytes + size);
    img->as_is = true;
    return true;
}

/* tinygltf's messages span lines; the log wants one. */
std::string one_line(const std::string &text)
{
    std::string out;
    for (char c : text) {
        if (c == '\n' || c == '\r') {
            if (!out.empty() && out.back() != ' ')
                out += "; ";
        } else {
            out += c;
        }
    }
    while (!out.empty() && (out.back() == ' ' || out.back() == ';'))
        out.pop_back();
    if (out.size() > 400)
        out = out.substr(0, 400) + "...";
    return out.empty() ? std::string("tinygltf failed without a message") : out;
}

/* ------------------------------------------------------------------------- */
/* Parsing                                                                   */
/* ------------------------------------------------------------------------- */

/* Why a buffer (or image) URI of the file was not read: only files below
 * or beside the glTF's folder (relative references, glTF 2.0 spec 3.3) and
 * data: URIs are; never the network, an absolute path, a folder or a
 * device. tinygltf names the URI as written. */
std::string missing_file(std::string uri, const std::string &dir)
{
    while (!uri.empty() && uri.back() == ' ')
        uri.pop_back();
    size_t colon = uri.find(':'), slash = uri.find('/');
    if (colon != std::string::npos && colon > 1 && (slash == std::string::npos || colon < slash))
        return "the buffer URI '" + uri + "' is not read: vergence reads files beside the glTF and data: URIs, "
               "never a network or other URI scheme";
    if (!uri.empty() && uri[0] == '/')
        return "the buffer URI '" + uri + "' is not read: it is an absolute path, and a glTF's URIs are "
               "relative to its folder (glTF 2.0 spec 3.3)";
    std::string path = dir.empty() ? uri : dir + "/" + uri;
    struct stat st;
    if (stat(path.c_str(), &st) != 0)
        return "cannot find the buffer file '" + uri + "' (" + path + ": " + std::strerror(errno) + ")";
    if (S_ISDIR(st.st_mode))
        return "the buffer URI '" + uri + "' is not read: " + path + " is a folder, not a file";
    return "the buffer URI '" + uri + "' is not read: " + path + " is not a regular file (a device or a pipe)";
}

bool parse(const char *path, Model &model, scene_err *e, std::vector<std::string> *files)
{
    uint8_t *bytes = nullptr;
    size_t size = 0;
    vg_status st = vg_file_read(path, &bytes, &size);
    if (st != VG_OK) {
        e->status = st; /* vg_file_read has logged the one line */
        return false;
    }
    std::string dir = path;
    size_t slash = dir.find_last_of('/');
    dir = slash == std::string::npos ? std::string() : dir.substr(0, slash);

    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(tinygltf::FsCallbacks{fs_exists, fs_expand, fs_read, fs_write, files});
    loader.SetImageLoader(image_stash, nullptr);
    std::string err, warn;
    bool ok = false;
    /* The format is told by the magic bytes, never by the extension. */
    bool binary = size >= 4 && std::memcmp(bytes, "glTF", 4) == 0;
    if (size > 0xffffffffull) {
        scene_fail(e, VG_ERR_UNSUPPORTED, "files of 4 GiB or more are not supported");
    } else if (binary) {
        uint32_t length = 0;
        const uint8_t *json = nullptr;
        size_t json_size = 0;
        if (scene_glb_check(bytes, size, e, &length, &json, &json_size) &&
            scene_json_check(json, json_size, e))
            ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes, length, dir);
    } else if (scene_json_check(bytes, size, e)) {
        ok = loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char *>(bytes),
                                        static_cast<unsigned>(size), dir);
    }
    std::free(bytes);
    if (!warn.empty())
        vg_debug("%s: tinygltf: %s", path, one_line(warn).c_str());
    if (e->status != VG_OK)
        return false;
    if (!ok) {
        /* A missing or unreadable external buffer is an I/O problem; the
         * rest (syntax, sizes, bad types) is a malformed file. */
        bool io = err.find("File not found") != std::string::npos ||
                  err.find("File read error") != std::string::npos;
        std::string msg = one_line(err);
        if (err.find("'uri' is missing") != std::string::npos) {
            msg = "a buffer has no \"uri\" (in a .gltf file every buffer needs one: a file name or a data: URI)";
            io = false;
        } else if (err.find("Failed to decode 'uri'") != std::string::npos ||
                   err.rfind("File not found : data:", 0) == 0) {
            msg = "a buffer's data: URI is not base64 data (\"data:application/octet-stream;base64,...\")";
            io = false;
        } else if (err.rfind("File not found : ", 0) == 0)
            msg = missing_file(one_line(err.substr(17)), dir);
        else if (err.find("Invalid `byteStride' value") != std::string::npos)
            msg = "a bufferView's byteStride is" + one_line(err.substr(err.rfind(':') + 1)) +
                  ": glTF allows a multiple of 4 from 4 to 252";
        else if (err.rfind("File size mismatch : ", 0) == 0)
            msg = "buffer file of the wrong size (truncated?): " + one_line(err.substr(21));
        else if (err.rfind("JSON string too short", 0) == 0)
            msg = "too short to be a glTF file";
        else if (err.rfind("[json.exception.", 0) == 0 && err.find("] ") != std::string::npos)
            msg = "not valid JSON: " + one_line(err.substr(err.find("] ") + 2)); /* nlohmann's tag is no help */
        return scene_fail(e, io ? VG_ERR_IO : VG_ERR_FORMAT, "%s", msg.c_str());
    }
    return true;
}

/* ------------------------------------------------------------------------- */
/* Accessors                                                                 */
/* ------------------------------------------------------------------------- */

struct Ctx {
    Ctx(const Model &model, scene *out, scene_err *err) : m(model), s(out), e(err) {}
    const Model &m;
    scene *s;
    scene_err *e;
    size_t dataless = 0;          /* elements allocated without file bytes */
    int skipped_primitives = 0;   /* points and lines */
    bool warned_texcoord = false, warned_joints1 = false, warned_textures = false;
    bool warned_path = false, warned_matrix = false;
    std::vector<int> texture_slot; /* glTF texture -> scene texture, -1 none, -2 not yet decoded */
};

int type_components(int type)
{
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
    }
}

/* The bytes of a bufferView, checked to lie inside its buffer. */
bool view_bytes(Ctx &c, int view, const std::string &what, const uint8_t **data, size_t *size, size_t *stride)
{
    if (!valid(view, c.m.bufferViews.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "bufferView %d does not exist (%s)", view, what.c_str());
    const tinygltf::BufferView &bv = c.m.bufferViews[static_cast<size_t>(view)];
    if (!valid(bv.buffer, c.m.buffers.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "bufferView %d: buffer %d does not exist (%s)", view, bv.buffer,
                          what.c_str());
    const std::vector<unsigned char> &buf = c.m.buffers[static_cast<size_t>(bv.buffer)].data;
    if (bv.byteOffset > buf.size() || bv.byteLength > buf.size() - bv.byteOffset)
        return scene_fail(c.e, VG_ERR_FORMAT,
                          "bufferView %d (byteOffset %zu, byteLength %zu) runs past the end of buffer %d "
                          "(%zu bytes) (%s)",
                          view, bv.byteOffset, bv.byteLength, bv.buffer, buf.size(), what.c_str());
    *data = buf.data() + bv.byteOffset;
    *size = bv.byteLength;
    if (stride)
        *stride = bv.byteStride;
    return true;
}

/* Locates accessor `index`, used as `what`; `allowed` is a bit mask of the
 * accepted component counts (1 << 3: VEC3, ...). Checks every range. */
bool locate(Ctx &c, int index, unsigned allowed, const std::string &what, scene_accessor_desc *d)
{
    if (!valid(index, c.m.accessors.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "accessor %d does not exist (%s)", index, what.c_str());
    const tinygltf::Accessor &a = c.m.accessors[static_cast<size_t>(index)];
    int comps = type_components(a.type);
    if (comps == 0 || !(allowed & (1u << comps)))
        return scene_fail(c.e, VG_ERR_FORMAT, "accessor %d has the wrong type for %s", index, what.c_str());
    std::string at = fmt("accessor %d, %s", index, what.c_str());
    *d = scene_accessor_desc{};
    if (a.count == 0)
        return scene_fail(c.e, VG_ERR_FORMAT, "accessor %d has count 0; glTF requires at least 1 (%s)", index,
                          what.c_str());
    d->component_type = a.componentType;
    d->components = comps;
    d->normalized = a.normalized;
    d->count = a.count;
    d->offset = a.byteOffset;
    if (a.bufferView != -1) {
        d->has_view = true;
        if (!view_bytes(c, a.bufferView, at, &d->view, &d->view_size, &d->stride))
            return false;
    } else {
        /* All zeros (maybe plus sparse values): nothing in the file backs
         * the count, so it is charged against a budget. */
        if (a.count > SCENE_MAX_DATALESS_ELEMENTS - c.dataless)
            return scene_fail(c.e, VG_ERR_UNSUPPORTED,
                              "accessor %d: %zu elements without a bufferView exceed the limit of %u (%s)", index,
                              a.count, SCENE_MAX_DATALESS_ELEMENTS, what.c_str());
        c.dataless += a.count;
    }
    if (a.sparse.isSparse && a.sparse.count != 0) {
        const auto &sp = a.sparse;
        if (sp.count < 0 || sp.indices.byteOffset < 0 || sp.values.byteOffset < 0)
            return scene_fail(c.e, VG_ERR_FORMAT, "accessor %d: negative sparse count or offset (%s)", index,
                              what.c_str());
        d->sparse_count = static_cast<size_t>(sp.count);
        d->sparse_index_type = sp.indices.componentType;
        size_t io = static_cast<size_t>(sp.indices.byteOffset), vo = static_cast<size_t>(sp.values.byteOffset);
        if (!view_bytes(c, sp.indices.bufferView, at + ", sparse indices", &d->sparse_indices,
                        &d->sparse_indices_size, nullptr) ||
            !view_bytes(c, sp.values.bufferView, at + ", sparse values", &d->sparse_values,
                        &d->sparse_values_size, nullptr))
            return false;
        if (io > d->sparse_indices_size || vo > d->sparse_values_size)
            return scene_fail(c.e, VG_ERR_FORMAT, "accessor %d: sparse byteOffset past its bufferView (%s)", index,
                              what.c_str());
        d->sparse_indices += io, d->sparse_indices_size -= io;
        d->sparse_values += vo, d->sparse_values_size -= vo;
    }
    char why[320];
    if (!scene_accessor_check(d, why, sizeof why))
        return scene_fail(c.e, VG_ERR_FORMAT, "accessor %d (%s): %s", index, what.c_str(), why);
    return true;
}

/* unit_ints: integer data is normalised even without "normalized": true
 * (COLOR_0 and WEIGHTS_0 may only hold normalised integers, spec 3.7.2.1). */
float *decode_floats(Ctx &c, int index, unsigned allowed, const std::string &what, size_t *count, int *comps,
                     bool unit_ints = false)
{
    scene_accessor_desc d;
    if (!locate(c, index, allowed, what, &d))
        return nullptr;
    d.normalized = d.normalized || unit_ints;
    float *out = alloc<float>(d.count * static_cast<size_t>(d.components));
    char why[320];
    if (!out) {
        scene_fail(c.e, VG_ERR_NOMEM, "out of memory decoding accessor %d (%s)", index, what.c_str());
    } else if (!scene_accessor_floats(&d, out, why, sizeof why)) {
        std::free(out);
        out = nullptr;
        scene_fail(c.e, VG_ERR_FORMAT, "accessor %d (%s): %s", index, what.c_str(), why);
    } else {
        size_t n = d.count * static_cast<size_t>(d.components);
        for (size_t k = 0; k < n; k++)
            if (!std::isfinite(out[k])) {
                std::free(out);
                out = nullptr;
                scene_fail(c.e, VG_ERR_FORMAT, "accessor %d (%s): element %zu is not a finite number", index,
                           what.c_str(), k / static_cast<size_t>(d.components));
                break;
            }
    }
    *count = d.count;
    if (comps)
        *comps = d.components;
    return out;
}

uint32_t *decode_uints(Ctx &c, int index, unsigned allowed, const std::string &what, size_t *count)
{
    scene_accessor_desc d;
    if (!locate(c, index, allowed, what, &d))
        return nullptr;
    uint32_t *out = alloc<uint32_t>(d.count * static_cast<size_t>(d.components));
    char why[320];
    if (!out) {
        scene_fail(c.e, VG_ERR_NOMEM, "out of memory decoding accessor %d (%s)", index, what.c_str());
    } else if (!scene_accessor_uints(&d, out, why, sizeof why)) {
        std::free(out);
        out = nullptr;
        scene_fail(c.e, VG_ERR_FORMAT, "accessor %d (%s): %s", index, what.c_str(), why);
    }
    *count = d.count;
    return out;
}

/* ------------------------------------------------------------------------- */
/* Meshes                                                                    */
/* ------------------------------------------------------------------------- */

/* Accessor index of an attribute, or -1 when absent (a present but negative
 * index is reported by locate()). */
int attribute(const std::map<std::string, int> &attrs, const char *name, bool *present)
{
    auto it = attrs.find(name);
    *present = it != attrs.end();
    return *present ? it->second : -1;
}

bool check_count(Ctx &c, size_t got, size_t want, const std::string &what)
{
    if (got == want)
        return true;
    return scene_fail(c.e, VG_ERR_FORMAT, "%s has %zu elements, POSITION has %zu", what.c_str(), got, want);
}

bool convert_targets(Ctx &c, const tinygltf::Primitive &p, int mi, int pi, scene_primitive *o)
{
    size_t vc = o->vertex_count, tc = p.targets.size();
    if (tc == 0)
        return true;
    if (tc > 4096 || tc * vc > (1u << 26))
        return scene_fail(c.e, VG_ERR_UNSUPPORTED, "mesh %d primitive %d: %zu morph targets of %zu vertices is too many",
                          mi, pi, tc, vc);
    o->target_count = static_cast<int>(tc);
    if (!(o->target_positions = alloc<float>(tc * vc * 3)))
        return scene_fail(c.e, VG_ERR_NOMEM, "out of memory (mesh %d primitive %d targets)", mi, pi);
    for (size_t k = 0; k < tc; k++) {
        const char *names[2] = {"POSITION", "NORMAL"};
        for (int a = 0; a < 2; a++) {
            bool present;
            int idx = attribute(p.targets[k], names[a], &present);
            if (!present)
                continue;
            std::string what = fmt("mesh %d primitive %d target %zu %s", mi, pi, k, names[a]);
            size_t n = 0;
            float *v = decode_floats(c, idx, 1u << 3, what, &n, nullptr);
            if (!v || !check_count(c, n, vc, what)) {
                std::free(v);
                return false;
            }
            float *&dst = a == 0 ? o->target_positions : o->target_normals;
            if (!dst && !(dst = alloc<float>(tc * vc * 3))) {
                std::free(v);
                return scene_fail(c.e, VG_ERR_NOMEM, "out of memory (mesh %d primitive %d targets)", mi, pi);
            }
            std::memcpy(dst + k * vc * 3, v, vc * 3 * sizeof(float));
            std::free(v);
        }
    }
    return true;
}

bool convert_primitive(Ctx &c, int mi, int pi, int mode, scene_primitive *o)
{
    const tinygltf::Primitive &p = c.m.meshes[static_cast<size_t>(mi)].primitives[static_cast<size_t>(pi)];
    o->mesh = mi;
    o->material = p.material;
    if (p.material != -1 && !valid(p.material, c.m.materials.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "mesh %d primitive %d: material %d does not exist", mi, pi, p.material);
    bool present;
    int pos = attribute(p.attributes, "POSITION", &present);
    if (!present)
        return scene_fail(c.e, VG_ERR_FORMAT, "mesh %d primitive %d has no POSITION attribute", mi, pi);
    size_t vc = 0, n = 0;
    std::string what = fmt("mesh %d primitive %d POSITION", mi, pi);
    if (!(o->positions = decode_floats(c, pos, 1u << 3, what, &vc, nullptr)))
        return false;
    if (vc > SCENE_MAX_INSTANCE_VERTICES)
        return scene_fail(c.e, VG_ERR_UNSUPPORTED, "%s: %zu vertices is more than %u", what.c_str(), vc,
                          SCENE_MAX_INSTANCE_VERTICES);
    o->vertex_count = static_cast<uint32_t>(vc);
    /* Plausibility: a vertex farther than SCENE_POSITION_MAX cannot be
     * drawn (the view's products overflow float and nothing is seen). */
    for (size_t i = 0; i < vc * 3; i++)
        if (std::fabs(o->positions[i]) > SCENE_POSITION_MAX) {
            size_t v = i / 3;
            return scene_fail(c.e, VG_ERR_FORMAT, "%s: vertex %zu at (%g, %g, %g) lies beyond %g of the origin on "
                              "an axis: too far to draw (positions are metres)", what.c_str(), v,
                              o->positions[3 * v], o->positions[3 * v + 1], o->positions[3 * v + 2],
                              SCENE_POSITION_MAX);
        }

    /* NORMAL, TEXCOORD_0, COLOR_0 (vec3 or vec4), spec 3.7.2.1. */
    struct { const char *name; unsigned allowed; float **dst; bool unit; } attrs[] = {
        {"NORMAL", 1u << 3, &o->normals, false},
        {"TEXCOORD_0", 1u << 2, &o->texcoords, false},
        {"COLOR_0", (1u << 3) | (1u << 4), &o->colors, true},
    };
    for (auto &a : attrs) {
        int idx = attribute(p.attributes, a.name, &present);
        if (!present)
            continue;
        int comps = 0;
        what = fmt("mesh %d primitive %d %s", mi, pi, a.name);
        if (!(*a.dst = decode_floats(c, idx, a.allowed, what, &n, &comps, a.unit)) || !check_count(c, n, vc, what))
            return false;
        if (a.dst == &o->colors && comps == 3) {
            float *rgba = alloc<float>(vc * 4);
            if (!rgba)
                return scene_fail(c.e, VG_ERR_NOMEM, "out of memory (%s)", what.c_str());
            for (size_t i = 0; i < vc; i++) {
                std::memcpy(rgba + i * 4, o->colors + i * 3, 3 * sizeof(float));
                rgba[i * 4 + 3] = 1.0f;
            }
            std::free(o->colors);
            o->colors = rgba;
        }
    }
    if (p.attributes.count("TEXCOORD_1") && p.material >= 0 && !c.warned_texcoord) {
        /* Only TEXCOORD_0 is kept (scene.h); say so once if a set 1 exists. */
        c.warned_texcoord = true;
        vg_warn("%s: only TEXCOORD_0 is loaded; other texture coordinate sets are ignored", c.e->path);
    }

    /* Skinning attributes count only as a pair (spec 3.7.3.3). */
    bool has_j, has_w;
    int ji = attribute(p.attributes, "JOINTS_0", &has_j), wi = attribute(p.attributes, "WEIGHTS_0", &has_w);
    if (has_j && has_w) {
        what = fmt("mesh %d primitive %d JOINTS_0", mi, pi);
        uint32_t *j = decode_uints(c, ji, 1u << 4, what, &n);
        if (!j || !check_count(c, n, vc, what)) {
            std::free(j);
            return false;
        }
        o->joints = alloc<uint16_t>(vc * 4);
        for (size_t i = 0; o->joints && i < vc * 4; i++) {
            if (j[i] > 0xffff) {
                uint32_t bad = j[i];
                std::free(j);
                return scene_fail(c.e, VG_ERR_FORMAT, "%s: joint %u does not fit 16 bits", what.c_str(), bad);
            }
            o->joints[i] = static_cast<uint16_t>(j[i]);
        }
        std::free(j);
        if (!o->joints)
            return scene_fail(c.e, VG_ERR_NOMEM, "out of memory (%s)", what.c_str());
        what = fmt("mesh %d primitive %d WEIGHTS_0", mi, pi);
        if (!(o->weights = decode_floats(c, wi, 1u << 4, what, &n, nullptr, true)) || !check_count(c, n, vc, what))
            return false;
        if (p.attributes.count("JOINTS_1") && !c.warned_joints1) {
            c.warned_joints1 = true;
            vg_warn("%s: only 4 joint influences per vertex are used (JOINTS_1 ignored)", c.e->path);
        }
    }

    bool has_indices = p.indices != -1;
    if (has_indices) {
        what = fmt("mesh %d primitive %d indices", mi, pi);
        if (!(o->indices = decode_uints(c, p.indices, 1u << 1, what, &n)))
            return false;
        if (n > SCENE_MAX_INSTANCE_INDICES)
            return scene_fail(c.e, VG_ERR_UNSUPPORTED, "%s: %zu indices is too many", what.c_str(), n);
        o->index_count = static_cast<uint32_t>(n);
    }
    /* Vertices that make no whole triangle are dropped, with a word. */
    size_t corners = has_indices ? n : vc;
    size_t spare = mode == 4 ? corners % 3 : corners < 3 ? corners : 0;
    if (spare)
        vg_warn("%s: mesh %d primitive %d: %zu %s make %zu whole triangle(s) and %zu left over, dropped", c.e->path,
                mi, pi, corners, has_indices ? "indices" : "vertices",
                mode == 4 ? corners / 3 : corners >= 3 ? corners - 2 : 0, spare);
    return convert_targets(c, p, mi, pi, o) && scene_primitive_finish(o, mode, has_indices, c.e, mi, pi);
}

bool convert_meshes(Ctx &c)
{
    scene *s = c.s;
    size_t total = 0;
    for (size_t mi = 0; mi < c.m.meshes.size(); mi++)
        for (size_t pi = 0; pi < c.m.meshes[mi].primitives.size(); pi++) {
            int mode = c.m.meshes[mi].primitives[pi].mode;
            if (mode < 0 || mode > 6)
                return scene_fail(c.e, VG_ERR_FORMAT, "mesh %zu primitive %zu: %d is not a primitive mode", mi, pi,
                                  mode);
            total += mode >= 4;
        }
    s->meshes = alloc<scene_mesh>(c.m.meshes.size());
    s->primitives = alloc<scene_primitive>(total);
    if (!s->meshes || !s->primitives)
        return scene_fail(c.e, VG_ERR_NOMEM, "out of memory for %zu meshes", c.m.meshes.size());
    s->mesh_count = static_cast<int>(c.m.meshes.size());
    s->primitive_count = static_cast<int>(total);
    int next = 0;
    for (int mi = 0; mi < s->mesh_count; mi++) {
        const tinygltf::Mesh &m = c.m.meshes[static_cast<size_t>(mi)];
        scene_mesh *o = &s->meshes[mi];
        copy_name(o->name, m.name);
        o->first_primitive = next;
        for (int pi = 0; pi < static_cast<int>(m.primitives.size()); pi++) {
            int mode = m.primitives[static_cast<size_t>(pi)].mode;
            if (mode < 4) { /* points and lines: the G-buffer draws triangles only */
                c.skipped_primitives++;
                continue;
            }
            scene_primitive *p = &s->primitives[next++];
            o->primitive_count++;
            if (!convert_primitive(c, mi, pi, mode, p))
                return false;
            o->weight_count = std::max(o->weight_count, p->target_count);
        }
        /* Default morph weights (spec 3.7.2.2): one per target. */
        if (!m.weights.empty() && m.weights.size() != static_cast<size_t>(o->weight_count))
            return scene_fail(c.e, VG_ERR_FORMAT, "mesh %d has %zu morph weights for %d targets (glTF: one each)", mi,
                              m.weights.size(), o->weight_count);
        if (!(o->weights = alloc<float>(static_cast<size_t>(o->weight_count))))
            return scene_fail(c.e, VG_ERR_NOMEM, "out of memory (mesh %d weights)", mi);
        for (size_t k = 0; k < m.weights.size() && k < static_cast<size_t>(o->weight_count); k++)
            o->weights[k] = to_f(m.weights[k]);
    }
    return true;
}

/* ------------------------------------------------------------------------- */
/* Nodes                                                                     */
/* ------------------------------------------------------------------------- */

bool copy_vec(Ctx &c, const std::vector<double> &v, size_t n, float *dst, int node, const char *what)
{
    if (v.empty())
        return true;
    if (v.size() != n)
        return scene_fail(c.e, VG_ERR_FORMAT, "node %d: %s has %zu numbers, not %zu", node, what, v.size(), n);
    for (size_t i = 0; i < n; i++) {
        if (!std::isfinite(v[i]))
            return scene_fail(c.e, VG_ERR_FORMAT, "node %d: %s holds a number that is not finite", node, what);
        dst[i] = to_f(v[i]);
    }
    return true;
}

bool convert_node(Ctx &c, int i, scene_node *o)
{
    const tinygltf::Node &n = c.m.nodes[static_cast<size_t>(i)];
    copy_name(o->name, n.name);
    o->mesh = n.mesh, o->camera = n.camera, o->skin = n.skin;
    if (n.mesh != -1 && !valid(n.mesh, c.m.meshes.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "node %d: mesh %d does not exist", i, n.mesh);
    if (n.camera != -1 && !valid(n.camera, c.m.cameras.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "node %d: camera %d does not exist", i, n.camera);
    if (n.skin != -1 && !valid(n.skin, c.m.skins.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "node %d: skin %d does not exist", i, n.skin);
    o->rotation[3] = 1.0f;
    o->scale[0] = o->scale[1] = o->scale[2] = 1.0f;
    if (!copy_vec(c, n.translation, 3, o->translation, i, "translation") ||
        !copy_vec(c, n.rotation, 4, o->rotation, i, "rotation") || !copy_vec(c, n.scale, 3, o->scale, i, "scale") ||
        !copy_vec(c, n.matrix, 16, o->matrix, i, "matrix"))
        return false;
    /* glTF requires a unit quaternion: one of length 0 is no rotation at
     * all, one near unit length is normalised (with a word when far off). */
    const float *q = o->rotation;
    double len = std::sqrt((double)q[0] * q[0] + (double)q[1] * q[1] + (double)q[2] * q[2] + (double)q[3] * q[3]);
    if (!(len > 1e-6))
        return scene_fail(c.e, VG_ERR_FORMAT, "node %d: rotation (%g, %g, %g, %g) has length %g: glTF requires a "
                          "unit quaternion", i, q[0], q[1], q[2], q[3], len);
    if (std::fabs(len - 1.0) > 0.01)
        vg_warn("%s: node %d: rotation (%g, %g, %g, %g) has length %g, not 1 (glTF requires a unit quaternion): "
                "normalised", c.e->path, i, q[0], q[1], q[2], q[3], len);
    scene_quat_normalize(o->rotation);
    o->has_matrix = !n.matrix.empty();
    if (!o->has_matrix)
        scene_mat4_from_trs(o->matrix, o->translation, o->rotation, o->scale);
    if (n.extras.IsObject() && n.extras.Has("saliency") && n.extras.Get("saliency").IsNumber()) {
        double v = n.extras.Get("saliency").GetNumberAsDouble();
        o->saliency = v >= 1.0 ? 1.0f : v > 0.0 ? static_cast<float>(v) : 0.0f; /* NaN -> 0 */
        o->has_saliency = true;
    }
    /* Node weights override the mesh's (spec 3.7.2.2), padded with zeros. */
    int wc = o->mesh >= 0 ? c.s->meshes[o->mesh].weight_count : 0;
    if (!n.weights.empty() && n.weights.size() != static_cast<size_t>(wc))
        return scene_fail(c.e, VG_ERR_FORMAT, "node %d has %zu morph weights for %d targets of its mesh (glTF: one "
                          "each)", i, n.weights.size(), wc);
    if (wc > 0 && !n.weights.empty()) {
        if (!(o->weights = alloc<float>(static_cast<size_t>(wc))))
            return scene_fail(c.e, VG_ERR_NOMEM, "out of memory (node %d weights)", i);
        for (size_t k = 0; k < n.weights.size() && k < static_cast<size_t>(wc); k++)
            o->weights[k] = to_f(n.weights[k]);
    }
    return true;
}

/* Nodes, with each child's single parent (spec 3.5.1: the hierarchy is a
 * set of disjoint trees); cycles are found by scene_build. */
bool convert_nodes(Ctx &c, std::vector<int> &start, std::vector<int> &list)
{
    scene *s = c.s;
    size_t nc = c.m.nodes.size();
    if (nc > 0x3fffffff)
        return scene_fail(c.e, VG_ERR_UNSUPPORTED, "too many nodes");
    if (!(s->nodes = alloc<scene_node>(nc)))
        return scene_fail(c.e, VG_ERR_NOMEM, "out of memory for %zu nodes", nc);
    s->node_count = static_cast<int>(nc);
    for (int i = 0; i < s->node_count; i++)
        s->nodes[i].parent = -1;
    start.assign(nc + 1, 0);
    for (int i = 0; i < s->node_count; i++) {
        if (!convert_node(c, i, &s->nodes[i]))
            return false;
        for (int ch : c.m.nodes[static_cast<size_t>(i)].children) {
            if (!valid(ch, nc))
                return scene_fail(c.e, VG_ERR_FORMAT, "node %d: child %d does not exist", i, ch);
            if (ch == i)
                return scene_fail(c.e, VG_ERR_FORMAT, "node %d is its own child (a cycle in the node hierarchy)", i);
            if (s->nodes[ch].parent >= 0)
                return scene_fail(c.e, VG_ERR_FORMAT, "node %d is a child of both node %d and node %d", ch,
                                  s->nodes[ch].parent, i);
            s->nodes[ch].parent = i;
            list.push_back(ch);
        }
        start[static_cast<size_t>(i) + 1] = static_cast<int>(list.size());
    }
    return true;
}

/* Roots of the default scene (spec 3.5.2): "scene", else scene 0, else
 * (no scenes at all) every root node, so a bare file still shows something. */
bool convert_roots(Ctx &c)
{
    scene *s = c.s;
    std::vector<int> roots;
    if (!c.m.scenes.empty()) {
        int sc = c.m.defaultScene == -1 ? 0 : c.m.defaultScene;
        if (!valid(sc, c.m.scenes.size()))
            return scene_fail(c.e, VG_ERR_FORMAT, "the default scene %d does not exist", c.m.defaultScene);
        for (int n : c.m.scenes[static_cast<size_t>(sc)].nodes) {
            if (!valid(n, c.m.nodes.size()))
                return scene_fail(c.e, VG_ERR_FORMAT, "scene %d: node %d does not exist", sc, n);
            roots.push_back(n);
        }
    } else {
        for (int i = 0; i < s->node_count; i++)
            if (s->nodes[i].parent < 0)
                roots.push_back(i);
    }
    if (!(s->roots = alloc<int>(roots.size())))
        return scene_fail(c.e, VG_ERR_NOMEM, "out of memory");
    std::copy(roots.begin(), roots.end(), s->roots);
    s->root_count = static_cast<int>(roots.size());
    return true;
}

/* ------------------------------------------------------------------------- */
/* Materials and textures                                                    */
/* ------------------------------------------------------------------------- */

/* Decodes glTF texture `tex` into the next scene texture; *slot is -1 when
 * it cannot be used (a warning says why; the material draws untextured). */
bool texture_slot(Ctx &c, int tex, int *slot)
{
    int &cached = c.texture_slot[static_cast<size_t>(tex)];
    if (cached != -2) {
        *slot = cached;
        return true;
    }
    cached = *slot = -1;
    const tinygltf::Texture &t = c.m.textures[static_cast<size_t>(tex)];
    if (t.sampler != -1 && !valid(t.sampler, c.m.samplers.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "texture %d: sampler %d does not exist", tex, t.sampler);
    if (t.source != -1 && !valid(t.source, c.m.images.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "texture %d: image %d does not exist", tex, t.source);
    if (c.s->texture_count >= SCENE_MAX_TEXTURES) {
        if (!c.warned_textures)
            vg_warn("%s: more than %d base-colour textures; the rest are drawn untextured", c.e->path,
                    SCENE_MAX_TEXTURES);
        c.warned_textures = true;
        return true;
    }
    if (t.source == -1) {
        vg_warn("%s: texture %d has no image in a format we decode; drawn untextured", c.e->path, tex);
        return true;
    }
    const tinygltf::Image &img = c.m.images[static_cast<size_t>(t.source)];
    const uint8_t *bytes = img.image.data();
    size_t size = img.image.size();
    if (img.bufferView >= 0 && !view_bytes(c, img.bufferView, fmt("image %d", t.source), &bytes, &size, nullptr))
        return false;
    scene_texture o = {};
    char why[320];
    if (!scene_texture_decode(bytes, size, &o, why, sizeof why)) {
        vg_warn("%s: image %d (%s): %s; drawn untextured", c.e->path, t.source,
                img.uri.empty() ? img.name.c_str() : img.uri.c_str(), why);
        return true;
    }
    copy_name(o.name, !img.name.empty() ? img.name : !t.name.empty() ? t.name : img.uri);
    o.wrap_repeat_s = o.wrap_repeat_t = true; /* no sampler: repeat, linear (spec 3.8.4) */
    if (t.sampler >= 0) {
        const tinygltf::Sampler &sm = c.m.samplers[static_cast<size_t>(t.sampler)];
        o.wrap_repeat_s = sm.wrapS != TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
        o.wrap_repeat_t = sm.wrapT != TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
        o.mirror_s = sm.wrapS == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
        o.mirror_t = sm.wrapT == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
        o.nearest = sm.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
    }
    c.s->textures[c.s->texture_count] = o;
    cached = *slot = c.s->texture_count++;
    return true;
}

bool convert_materials(Ctx &c)
{
    scene *s = c.s;
    c.texture_slot.assign(c.m.textures.size(), -2);
    s->materials = alloc<scene_material>(c.m.materials.size());
    s->textures = alloc<scene_texture>(SCENE_MAX_TEXTURES);
    if (!s->materials || !s->textures)
        return scene_fail(c.e, VG_ERR_NOMEM, "out of memory for materials");
    s->material_count = static_cast<int>(c.m.materials.size());
    for (int i = 0; i < s->material_count; i++) {
        const tinygltf::Material &m = c.m.materials[static_cast<size_t>(i)];
        scene_material *o = &s->materials[i];
        copy_name(o->name, m.name);
        const auto &f = m.pbrMetallicRoughness.baseColorFactor;
        for (size_t k = 0; k < 4; k++)
            o->base_color[k] = f.size() == 4 ? to_f(f[k]) : 1.0f;
        o->double_sided = m.doubleSided;
        const tinygltf::TextureInfo &ti = m.pbrMetallicRoughness.baseColorTexture;
        o->texcoord = ti.texCoord;
        o->base_color_texture = -1;
        if (ti.index == -1)
            continue;
        if (!valid(ti.index, c.m.textures.size()))
            return scene_fail(c.e, VG_ERR_FORMAT, "material %d: texture %d does not exist", i, ti.index);
        if (!texture_slot(c, ti.index, &o->base_color_texture))
            return false;
        if (ti.texCoord != 0 && !c.warned_texcoord) {
            c.warned_texcoord = true;
            vg_warn("%s: material %d samples TEXCOORD_%d; only TEXCOORD_0 is loaded", c.e->path, i, ti.texCoord);
        }
    }
    return true;
}

/* ------------------------------------------------------------------------- */
/* Cameras and skins                                                         */
/* ------------------------------------------------------------------------- */

bool convert_cameras(Ctx &c)
{
    scene *s = c.s;
    if (!(s->cameras = alloc<scene_camera>(c.m.cameras.size())))
        return scene_fail(c.e, VG_ERR_NOMEM, "out of memory");
    s->camera_count = static_cast<int>(c.m.cameras.size());
    for (int i = 0; i < s->camera_count; i++) {
        const tinygltf::Camera &cam = c.m.cameras[static_cast<size_t>(i)];
        scene_camera *o = &s->cameras[i];
        copy_name(o->name, cam.name);
        /* Ranges of spec 3.10.2 / 5.13 (camera.perspective, .orthographic). */
        if (cam.type == "perspective") {
            const auto &p = cam.perspective;
            o->yfov = to_f(p.yfov), o->aspect = to_f(p.aspectRatio);
            o->znear = to_f(p.znear), o->zfar = to_f(p.zfar);
            if (!(o->yfov > 0.0f && o->yfov < 3.14159f) || !(o->znear > 0.0f) || !(o->aspect >= 0.0f) ||
                !(o->zfar == 0.0f || o->zfar > o->znear))
                return scene_fail(c.e, VG_ERR_FORMAT, "camera %d: perspective yfov/znear/zfar/aspectRatio out of range",
                                  i);
        } else if (cam.type == "orthographic") {
            const auto &p = cam.orthographic;
            o->orthographic = true;
            o->xmag = to_f(p.xmag), o->ymag = to_f(p.ymag), o->znear = to_f(p.znear), o->zfar = to_f(p.zfar);
            if (o->xmag == 0.0f || o->ymag == 0.0f || !(o->znear >= 0.0f) || !(o->zfar > o->znear) ||
                !std::isfinite(o->xmag) || !std::isfinite(o->ymag) || !std::isfinite(o->zfar))
                return scene_fail(c.e, VG_ERR_FORMAT, "camera %d: orthographic xmag/ymag/znear/zfar out of range", i);
        } else {
            return scene_fail(c.e, VG_ERR_FORMAT, "camera %d: type '%s' is neither perspective nor orthographic", i,
                              cam.type.c_str());
        }
    }
    return true;
}

bool convert_skins(Ctx &c)
{
    scene *s = c.s;
    if (!(s->skins = alloc<scene_skin>(c.m.skins.size())))
        return scene_fail(c.e, VG_ERR_NOMEM, "out of memory");
    s->skin_count = static_cast<int>(c.m.skins.size());
    for (int i = 0; i < s->skin_count; i++) {
        const tinygltf::Skin &sk = c.m.skins[static_cast<size_t>(i)];
        scene_skin *o = &s->skins[i];
        copy_name(o->name, sk.name);
        size_t jc = sk.joints.size();
        if (jc == 0)
            return scene_fail(c.e, VG_ERR_FORMAT, "skin %d has no joints (glTF requires at least one)", i);
        o->joints = alloc<int>(jc);
        o->inverse_bind = alloc<float>(jc * 16);
        if (!o->joints || !o->inverse_bind)
            return scene_fail(c.e, VG_ERR_NOMEM, "out of memory (skin %d)", i);
        o->joint_count = static_cast<int>(jc);
        for (size_t j = 0; j < jc; j++) {
            if (!valid(sk.joints[j], c.m.nodes.size()))
                return scene_fail(c.e, VG_ERR_FORMAT, "skin %d: joint node %d does not exist", i, sk.joints[j]);
            o->joints[j] = sk.joints[j];
            scene_mat4_identity(o->inverse_bind + j * 16); /* spec 3.7.3.1: identity when absent */
        }
        o->skeleton = sk.skeleton;
        if (sk.skeleton != -1 && !valid(sk.skeleton, c.m.nodes.size()))
            return scene_fail(c.e, VG_ERR_FORMAT, "skin %d: skeleton node %d does not exist", i, sk.skeleton);
        if (sk.inverseBindMatrices == -1)
            continue;
        size_t n = 0;
        std::string what = fmt("skin %d inverseBindMatrices", i);
        float *m = decode_floats(c, sk.inverseBindMatrices, 1u << 16, what, &n, nullptr);
        if (!m)
            return false;
        if (n < jc) {
            std::free(m);
            return scene_fail(c.e, VG_ERR_FORMAT, "%s: %zu matrices for %zu joints", what.c_str(), n, jc);
        }
        std::memcpy(o->inverse_bind, m, jc * 16 * sizeof(float));
        std::free(m);
    }
    return true;
}

/* ------------------------------------------------------------------------- */
/* Animations                                                                */
/* ------------------------------------------------------------------------- */

bool convert_sampler(Ctx &c, int ai, int si, scene_sampler *o)
{
    const tinygltf::AnimationSampler &sm =
        c.m.animations[static_cast<size_t>(ai)].samplers[static_cast<size_t>(si)];
    if (sm.interpolation == "LINEAR")
        o->interp = SCENE_INTERP_LINEAR;
    else if (sm.interpolation == "STEP")
        o->interp = SCENE_INTERP_STEP;
    else if (sm.interpolation == "CUBICSPLINE")
        o->interp = SCENE_INTERP_CUBIC;
    else
        return scene_fail(c.e, VG_ERR_FORMAT, "animation %d sampler %d: unknown interpolation '%s'", ai, si,
                          sm.interpolation.c_str());
    size_t keys = 0, n = 0;
    int comps = 0;
    std::string what = fmt("animation %d sampler %d input", ai, si);
    if (!(o->times = decode_floats(c, sm.input, 1u << 1, what, &keys, nullptr)))
        return false;
    if (keys == 0 || keys > 0x7fffffff)
        return scene_fail(c.e, VG_ERR_FORMAT, "%s: %zu keys", what.c_str(), keys);
    o->key_count = static_cast<int>(keys);
    /* Key times must increase (spec 3.11); equal neighbours are tolerated. */
    for (size_t k = 0; k < keys; k++)
        if (!std::isfinite(o->times[k]) || (k > 0 && o->times[k] < o->times[k - 1]))
            return scene_fail(c.e, VG_ERR_FORMAT, "%s: key time %zu is not finite or decreases", what.c_str(), k);
    what = fmt("animation %d sampler %d output", ai, si);
    if (!(o->values = decode_floats(c, sm.output, (1u << 1) | (1u << 3) | (1u << 4), what, &n, &comps)))
        return false;
    /* CUBICSPLINE stores (in-tangent, value, out-tangent) per key; morph
     * weights are scalars, components = weights per key. */
    size_t per = (o->interp == SCENE_INTERP_CUBIC ? 3 : 1) * keys;
    size_t c_per_key = comps == 1 ? n / per : static_cast<size_t>(comps);
    if (n == 0 || (comps == 1 ? n % per != 0 : n != per) || c_per_key > 0x7fffffff)
        return scene_fail(c.e, VG_ERR_FORMAT, "%s: %zu elements do not match %zu keys (%s)", what.c_str(), n, keys,
                          sm.interpolation.c_str());
    o->components = static_cast<int>(c_per_key);
    return true;
}

bool convert_channel(Ctx &c, int ai, int ci, int sampler_base, bool *keep, scene_channel *o)
{
    const tinygltf::Animation &a = c.m.animations[static_cast<size_t>(ai)];
    const tinygltf::AnimationChannel &ch = a.channels[static_cast<size_t>(ci)];
    *keep = false;
    if (!valid(ch.sampler, a.samplers.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "animation %d channel %d: sampler %d does not exist", ai, ci, ch.sampler);
    if (ch.target_node == -1)
        return true; /* targets something an extension names: not ours */
    if (!valid(ch.target_node, c.m.nodes.size()))
        return scene_fail(c.e, VG_ERR_FORMAT, "animation %d channel %d: node %d does not exist", ai, ci,
                          ch.target_node);
    const scene_node *nd = &c.s->nodes[ch.target_node];
    int weights = nd->mesh >= 0 ? c.s->meshes[nd->mesh].weight_count : 0, need = 0;
    if (ch.target_path == "translation")
        o->path = SCENE_PATH_TRANSLATION, need = 3;
    else if (ch.target_path == "rotation")
        o->path = SCENE_PATH_ROTATION, need = 4;
    else if (ch.target_path == "scale")
        o->path = SCENE_PATH_SCALE, need = 3;
    else if (ch.target_path == "weights")
        o->path = SCENE_PATH_WEIGHTS, need = weights;
    if (need == 0 || nd->has_matrix) {
        /* Unknown paths, weights without morph targets, and TRS animation
         * of a node given by a matrix (forbidden by spec 3.11) are skipped. */
        if (!c.warned_path)
            vg_warn("%s: animation %d channel %d (%s of node %d) is ignored", c.e->path, ai, ci,
                    ch.target_path.c_str(), ch.target_node);
        c.warned_path = true;
        return true;
    }
    o->node = ch.target_node;
    o->sampler = sampler_base + ch.sampler;
    if (c.s->samplers[o->sampler].components != need)
        return scene_fail(c.e, VG_ERR_FORMAT, "animation %d channel %d: sampler gives %d values per key, %s needs %d",
                          ai, ci, c.s->samplers[o->sampler].components, ch.target_path.c_str(), need);
    *keep = true;
    return true;
}

bool convert_animations(Ctx &c)
{
    scene *s = c.s;
    size_t samplers = 0, channels = 0;
    for (const auto &a : c.m.animations)
        samplers += a.samplers.size(), channels += a.channels.size();
    s->animations = alloc<scene_animation>(c.m.animations.size());
    s->samplers = alloc<scene_sampler>(samplers);
    s->channels = alloc<scene_channel>(channels);
    if (!s->animations || !s->samplers || !s->channels)
        return scene_fail(c.e, VG_ERR_NOMEM, "out of memory for animations");
    s->animation_count = static_cast<int>(c.m.animations.size());
    s->sampler_count = static_cast<int>(samplers);
    int base = 0;
    for (int ai = 0; ai < s->animation_count; ai++) {
        const tinygltf::Animation &a = c.m.animations[static_cast<size_t>(ai)];
        scene_animation *o = &s->animations[ai];
        copy_name(o->name, a.name);
        o->start = a.samplers.empty() ? 0.0f : INFINITY;
        o->end = a.samplers.empty() ? 0.0f : -INFINITY;
        for (int si = 0; si < static_cast<int>(a.samplers.size()); si++) {
            scene_sampler *sm = &s->samplers[base + si];
            if (!convert_sampler(c, ai, si, sm))
                return false;
            o->start = std::min(o->start, sm->times[0]);
            o->end = std::max(o->end, sm->times[sm->key_count - 1]);
        }
        o->first_channel = s->channel_count;
        for (int ci = 0; ci < static_cast<int>(a.channels.size()); ci++) {
            bool keep = false;
            if (!convert_channel(c, ai, ci, base, &keep, &s->channels[s->channel_count]))
                return false;
            s->channel_count += keep;
        }
        o->channel_count = s->channel_count - o->first_channel;
        base += static_cast<int>(a.samplers.size());
    }
    return true;
}

/* ------------------------------------------------------------------------- */
/* Conversion                                                                */
/* ------------------------------------------------------------------------- */

bool check_extensions(Ctx &c)
{
    /* Extensions a file may require that change nothing we load (unlit,
     * emissive strength) or that the accessor decoder covers (quantization). */
    static const char *const known[] = {"KHR_mesh_quantization", "KHR_materials_unlit",
                                        "KHR_materials_emissive_strength"};
    for (const std::string &ext : c.m.extensionsRequired) {
        bool ok = false;
        for (const char *k : known)
            ok = ok || ext == k;
        if (!ok)
            return scene_fail(c.e, VG_ERR_UNSUPPORTED, "requires the unsupported extension %s", ext.c_str());
    }
    return true;
}

bool convert(const Model &m, scene *s, scene_err *e)
{
    Ctx c(m, s, e);
    std::vector<int> start, list;
    /* glTF 2.x only (asset.version "2.0", "2.1", ...); 1.0 is another format. */
    if (m.asset.version.rfind("2.", 0) != 0)
        return scene_fail(e, VG_ERR_FORMAT, "asset.version is \"%.16s\"; vergence reads glTF 2.x",
                          m.asset.version.c_str());
    /* Order matters: nodes need mesh weight counts, channels need nodes. */
    if (!check_extensions(c) || !convert_cameras(c) || !convert_materials(c) || !convert_meshes(c) ||
        !convert_nodes(c, start, list) || !convert_roots(c) || !convert_skins(c) || !convert_animations(c))
        return false;
    if (c.skipped_primitives)
        vg_warn("%s: %d point or line primitive(s) skipped (only triangles are drawn)", e->path,
                c.skipped_primitives);
    scene_children children = {start.data(), list.data()};
    return scene_build(s, &children, e);
}

} // namespace

/* ------------------------------------------------------------------------- */
/* Entry point                                                               */
/* ------------------------------------------------------------------------- */

extern "C" vg_status scene_load(const char *path, scene **out)
{
    if (out)
        *out = nullptr;
    scene_err err = {path ? path : "(null)", VG_OK};
    if (!path || !out)
        return scene_fail(&err, VG_ERR_ARG, "scene_load: no file or no output given"), err.status;
    scene *s = static_cast<scene *>(std::calloc(1, sizeof *s));
    if (!s)
        return scene_fail(&err, VG_ERR_NOMEM, "out of memory"), err.status;
    std::snprintf(s->path, sizeof s->path, "%s", path);
    try {
        Model model;
        std::vector<std::string> files{path};
        if (parse(path, model, &err, &files) && convert(model, s, &err)) {
            s->files = static_cast<char (*)[512]>(std::calloc(files.size(), sizeof *s->files));
            if (!s->files)
                throw std::bad_alloc();
            for (const std::string &f : files)
                std::snprintf(s->files[s->file_count++], sizeof *s->files, "%s", f.c_str());
        }
    } catch (const std::bad_alloc &) {
        scene_fail(&err, VG_ERR_NOMEM, "out of memory");
    } catch (const std::exception &ex) {
        scene_fail(&err, VG_ERR_FORMAT, "%s", ex.what());
    } catch (...) {
        scene_fail(&err, VG_ERR_FORMAT, "unexpected failure inside tinygltf");
    }
    if (err.status != VG_OK) {
        scene_destroy(s);
        return err.status;
    }
    *out = s;
    return VG_OK;
}
