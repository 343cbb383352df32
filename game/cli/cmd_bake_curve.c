/* vergence bake-curve — the global depth -> vergence curve (paper 4.6) built
 * offline from a capture: for every captured frame, Embree tests which scene
 * vertices the centre camera sees (occlusion rays), the pixel of each visible
 * vertex gives a (depth, disparity) pair from the captured maps, and the pairs of
 * all frames make one curve (disparity/disp_curve.h) that `--curve FILE` loads
 * instead of the per-frame one. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <embree3/rtcore.h>

#include "commands.h"
#include "core/io.h"
#include "core/json_read.h"
#include "core/log.h"
#include "core/manifest.h"
#include "scene/scene.h"
#include "disparity/disp_curve.h"

static struct {
    const char *scene, *capture, *out, *map, *frames;
} o;

static const vg_opt k_opts[] = {
    {"--scene", VG_OPT_STRING, &o.scene, "FILE", "the glTF scene the capture rendered", NULL, 0, 0},
    {"--capture", VG_OPT_STRING, &o.capture, "DIR", "a folder written by 'vergence capture'", NULL, 0, 0},
    {"--out", VG_OPT_STRING, &o.out, "FILE", "the curve file to write", NULL, 0, 0},
    {"--map", VG_OPT_STRING, &o.map, "g|h|f", "disparity map to pair with depth (default: f, else h, else g)", NULL, 0, 0},
    {"--frames", VG_OPT_STRING, &o.frames, "A:B", "captured frames to use (default: all)", NULL, 0, 0},
};

typedef struct pairs {
    float *depth, *vergence;
    size_t count, cap;
} pairs;

static vg_status pairs_add(pairs *p, float z, float v)
{
    if (p->count == p->cap) {
        size_t cap = p->cap ? 2 * p->cap : 1 << 14;
        float *d = realloc(p->depth, cap * sizeof *d), *g = d ? realloc(p->vergence, cap * sizeof *g) : NULL;
        if (!d || !g) {
            free(d ? d : p->depth);
            p->depth = NULL;
            return VG_ERR_NOMEM;
        }
        p->depth = d;
        p->vergence = g;
        p->cap = cap;
    }
    p->depth[p->count] = z;
    p->vergence[p->count++] = v;
    return VG_OK;
}

/* A triangle mesh of the evaluated scene. */
static RTCScene build_scene(RTCDevice dev, const scene *s, const scene_state *st)
{
    RTCScene rs = rtcNewScene(dev);
    RTCGeometry geo = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                       s->vertex_count ? s->vertex_count : 1);
    uint32_t *idx = rtcSetNewGeometryBuffer(geo, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
                                            s->index_count ? s->index_count / 3 : 1);
    if (s->vertex_count)
        memcpy(v, st->positions, (size_t)s->vertex_count * 3 * sizeof(float));
    else
        memset(v, 0, 3 * sizeof(float));
    memset(idx, 0, 3 * sizeof(uint32_t));
    for (int i = 0; i < s->instance_count; i++) {
        const scene_instance *in = &s->instances[i];
        uint32_t count = s->primitives[in->primitive].index_count;
        for (uint32_t k = 0; k < count; k++)
            idx[in->first_index + k] = s->indices[in->first_index + k] + in->first_vertex;
    }
    rtcCommitGeometry(geo);
    rtcAttachGeometry(rs, geo);
    rtcReleaseGeometry(geo);
    rtcCommitScene(rs);
    return rs;
}

static void mat_mul(const float *a, const float *b, float *out) /* column-major a * b */
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            float sum = 0;
            for (int k = 0; k < 4; k++)
                sum += a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = sum;
        }
}

static bool read_matrix(const vg_jvalue *frame, const char *key, float *m)
{
    const vg_jvalue *a = vg_jget(frame, key);
    if (!a || a->type != VG_JARRAY || a->count != 16)
        return false;
    for (int i = 0; i < 16; i++)
        m[i] = (float)vg_jat(a, (size_t)i)->number;
    return true;
}

/* Pairs of one frame: visible vertices, depth checked against the capture. */
static vg_status bake_frame(RTCDevice dev, const scene *s, scene_state *st, const vg_jvalue *cam, int n,
                            const char *map, pairs *out, size_t *visible)
{
    char name[64], path[4096];
    float view[16], proj[16], vp[16], eye[3];
    if (!read_matrix(cam, "view", view) || !read_matrix(cam, "proj", proj) || !vg_jget(cam, "position")) {
        vg_error("%s/capture.json: camera of frame %d lacks view, proj or position", o.capture, n);
        return VG_ERR_FORMAT;
    }
    for (int k = 0; k < 3; k++)
        eye[k] = (float)vg_jat(vg_jget(cam, "position"), (size_t)k)->number;
    mat_mul(proj, view, vp);
    vg_imagef depth = {0}, disp = {0};
    snprintf(name, sizeof name, "frame_%04d_depth.pfm", n);
    vg_status st2 = vg_path_join(path, sizeof path, o.capture, name);
    if (st2 == VG_OK)
        st2 = vg_pfm_read(path, &depth);
    snprintf(name, sizeof name, "frame_%04d_%s.pfm", n, map);
    if (st2 == VG_OK && (st2 = vg_path_join(path, sizeof path, o.capture, name)) == VG_OK)
        st2 = vg_pfm_read(path, &disp);
    if (st2 == VG_OK && (disp.width != depth.width || disp.height != depth.height)) {
        vg_error("%s: size differs from its depth map", path);
        st2 = VG_ERR_FORMAT;
    }
    if (st2 != VG_OK) {
        vg_imagef_free(&depth);
        vg_imagef_free(&disp);
        return st2;
    }
    scene_evaluate(s, (float)vg_jnum(cam, "time", 0), st);
    RTCScene rs = build_scene(dev, s, st);
    struct RTCIntersectContext ctx;
    for (uint32_t i = 0; i < s->vertex_count && st2 == VG_OK; i++) {
        const float *p = st->positions + 3 * (size_t)i;
        float c[4];
        for (int r = 0; r < 4; r++)
            c[r] = vp[r] * p[0] + vp[4 + r] * p[1] + vp[8 + r] * p[2] + vp[12 + r];
        if (c[3] <= 1e-4f)
            continue;
        float px = (c[0] / c[3] * 0.5f + 0.5f) * (float)depth.width;
        float py = (c[1] / c[3] * 0.5f + 0.5f) * (float)depth.height;
        int x = (int)floorf(px), y = (int)floorf(py);
        if (x < 0 || y < 0 || x >= depth.width || y >= depth.height)
            continue;
        float d[3] = {p[0] - eye[0], p[1] - eye[1], p[2] - eye[2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        struct RTCRay ray = {.org_x = eye[0], .org_y = eye[1], .org_z = eye[2], .dir_x = d[0] / len,
                             .dir_y = d[1] / len, .dir_z = d[2] / len, .tnear = 0, .tfar = len * 0.999f,
                             .mask = UINT32_MAX, .flags = 0};
        rtcInitIntersectContext(&ctx);
        rtcOccluded1(rs, &ctx, &ray);
        if (ray.tfar < 0)
            continue; /* something is in front of it */
        size_t k = (size_t)y * depth.width + x;
        /* The pixel may still show the neighbour across a silhouette. */
        if (fabsf(depth.data[k] - c[3]) > 0.01f * c[3])
            continue;
        (*visible)++;
        /* The pixel's own depth: the map holds the disparity of that surface
         * point, not of the vertex a fraction of a pixel away. */
        st2 = pairs_add(out, depth.data[k], disp.data[k]);
    }
    rtcReleaseScene(rs);
    vg_imagef_free(&depth);
    vg_imagef_free(&disp);
    return st2;
}

/* The capture was made of this scene (the same file, or one of the same name
 * when the capture's path does not resolve from here). */
static const char *basename_of(const char *p)
{
    const char *slash = strrchr(p, '/');
    return slash ? slash + 1 : p;
}

static vg_status same_scene(const vg_jdoc *doc, const char *json, const scene *s)
{
    const vg_jvalue *v = vg_jget(doc->root, "scene");
    const char *captured = v && v->type == VG_JSTRING ? v->string : NULL;
    if (!captured) {
        vg_error("%s: no \"scene\": not a capture of vergence", json);
        return VG_ERR_FORMAT;
    }
    struct stat a, b;
    bool same = stat(captured, &a) == 0 && stat(s->path, &b) == 0 ? a.st_dev == b.st_dev && a.st_ino == b.st_ino
                                                                  : !strcmp(basename_of(captured), basename_of(s->path));
    if (!same) {
        vg_error("--capture %s was made of %s, not of --scene %s", o.capture, captured, s->path);
        return VG_ERR_ARG;
    }
    return VG_OK;
}

static const char *pick_map(void)
{
    static const char *const maps[] = {"f", "h", "g"};
    if (o.map)
        return o.map;
    for (int i = 0; i < 3; i++) {
        char path[4096], name[32];
        snprintf(name, sizeof name, "frame_0000_%s.pfm", maps[i]);
        FILE *f = vg_path_join(path, sizeof path, o.capture, name) == VG_OK ? fopen(path, "rb") : NULL;
        if (f) {
            fclose(f);
            return maps[i];
        }
    }
    return "g";
}

static int run(int argc, char **argv)
{
    bool help;
    if (vg_cli_parse(&vg_cmd_bake_curve, argc, argv, &help) != VG_OK)
        return 2;
    if (help)
        return 0;
    if (vg_cli_require(&vg_cmd_bake_curve, "--scene", o.scene) ||
        vg_cli_require(&vg_cmd_bake_curve, "--capture", o.capture) || vg_cli_require(&vg_cmd_bake_curve, "--out", o.out))
        return 2;
    const char *map = pick_map();
    if (strcmp(map, "g") && strcmp(map, "h") && strcmp(map, "f")) {
        vg_error("bake-curve --map: '%s' is not one of g, h, f", map);
        return 2;
    }
    char path[4096];
    vg_jdoc doc = {0};
    vg_status st = vg_path_join(path, sizeof path, o.capture, "capture.json");
    if (st == VG_OK)
        st = vg_json_read_file(path, &doc);
    if (st != VG_OK)
        return vg_status_exit_code(st);
    const vg_jvalue *cams = vg_jpath(doc.root, "camera.frames");
    int total = cams && cams->type == VG_JARRAY ? (int)cams->count : 0, a = 0, b = total - 1;
    if (!total) {
        vg_error("%s: no camera.frames in the capture", path);
        vg_jdoc_free(&doc);
        return vg_status_exit_code(VG_ERR_FORMAT);
    }
    /* The capture's own account of itself must hold together. */
    double frames = vg_jnum(doc.root, "frames", -1);
    if (frames != (double)total) {
        vg_error("%s: \"frames\" is %g but camera.frames holds %d frames: not a complete capture", path, frames, total);
        vg_jdoc_free(&doc);
        return vg_status_exit_code(VG_ERR_FORMAT);
    }
    if (o.frames && (sscanf(o.frames, "%d:%d", &a, &b) != 2 || a < 0 || b < a || b >= total)) {
        vg_error("bake-curve --frames: '%s' is not A:B within the %d captured frames", o.frames, total);
        vg_jdoc_free(&doc);
        return 2;
    }
    scene *s = NULL;
    scene_state ss = {0};
    pairs p = {0};
    size_t visible = 0;
    RTCDevice dev = NULL;
    st = scene_load(o.scene, &s);
    if (st == VG_OK)
        st = same_scene(&doc, path, s);
    /* Nothing it writes may be an input; the earlier curve goes first. */
    vg_inputs in = {0};
    for (int i = 0; st == VG_OK && i < s->file_count; i++)
        st = vg_inputs_add(&in, "--scene", s->files[i]);
    if (st == VG_OK)
        st = vg_inputs_add(&in, "--capture", path);
    for (int n = a; n <= b && st == VG_OK; n++) {
        char name[64], file[4096];
        const char *kinds[2] = {"depth", map};
        for (int k = 0; k < 2 && st == VG_OK; k++) {
            snprintf(name, sizeof name, "frame_%04d_%s.pfm", n, kinds[k]);
            if ((st = vg_path_join(file, sizeof file, o.capture, name)) == VG_OK)
                st = vg_inputs_add(&in, "--capture", file);
        }
    }
    if (st == VG_OK)
        st = vg_inputs_check(&in, "--out", o.out);
    vg_inputs_free(&in);
    /* --out is a file: the earlier curve goes before the run (a failed run
     * never leaves an old curve looking new). */
    struct stat sb;
    if (st == VG_OK && stat(o.out, &sb) == 0 && !S_ISREG(sb.st_mode)) {
        vg_error("--out %s: is %s, not a curve file: give the name of the .curve file to write", o.out,
                 S_ISDIR(sb.st_mode) ? "a folder" : "a device or a pipe");
        st = VG_ERR_IO;
    }
    if (st == VG_OK && unlink(o.out) != 0 && errno != ENOENT && errno != ENOTDIR) {
        vg_error("%s: cannot remove the earlier curve: %s", o.out, strerror(errno));
        st = VG_ERR_IO;
    }
    if (st == VG_OK && !(dev = rtcNewDevice(NULL))) {
        vg_error("bake-curve: Embree could not start a device");
        st = VG_ERR_DEVICE;
    }
    if (st == VG_OK)
        st = scene_state_init(s, &ss);
    for (int n = a; n <= b && st == VG_OK; n++) {
        vg_progress("bake-curve", n - a, b - a + 1);
        st = bake_frame(dev, s, &ss, vg_jat(cams, (size_t)n), n, map, &p, &visible);
    }
    vgx_curve_data curve;
    if (st == VG_OK && p.count == 0) {
        vg_error("%s: no scene vertex is visible in frames %d..%d", o.capture, a, b);
        st = VG_ERR_FORMAT;
    }
    if (st == VG_OK) {
        vg_progress("bake-curve", b - a + 1, b - a + 1);
        st = disp_curve_build(p.depth, p.vergence, p.count, &curve);
    }
    if (st == VG_OK)
        st = disp_curve_write(o.out, &curve);
    if (st == VG_OK)
        vg_info("baked %s from %zu visible vertices of %d frame(s) (map %s), depth %.2f..%.2f m", o.out, visible,
                b - a + 1, map, 1.0 / curve.inv_depth_near, 1.0 / curve.inv_depth_far);
    free(p.depth);
    free(p.vergence);
    scene_state_free(&ss);
    scene_destroy(s);
    if (dev)
        rtcReleaseDevice(dev);
    vg_jdoc_free(&doc);
    return vg_status_exit_code(st);
}

const vg_cmd vg_cmd_bake_curve = {
    .name = "bake-curve",
    .summary = "bake the warp's global depth -> disparity curve from a capture (Embree visibility)",
    .usage = "vergence bake-curve --scene FILE --capture DIR --out FILE [--map g|h|f] [--frames A:B]",
    .details = "Pairs the depth of every scene vertex the centre camera sees (Embree occlusion rays)\n"
               "with the captured disparity map at its pixel, over the captured frames, and writes\n"
               "the curve that 'vergence capture --curve FILE' uses instead of the per-frame one.",
    .opts = k_opts,
    .opt_count = sizeof k_opts / sizeof k_opts[0],
    .run = run,
};
