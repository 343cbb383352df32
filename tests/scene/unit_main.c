/* scene_unit TEST: one CTest test per behaviour of the scene module. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/io.h"
#include "unit.h"


/* ------------------------------------------------------------------------- */
/* Files                                                                     */
/* ------------------------------------------------------------------------- */

const char *unit_asset(const char *rel)
{
    static char buf[8][512];
    static int next;
    char *b = buf[next++ % 8];
    snprintf(b, sizeof buf[0], "../shared/assets/gltf/%s", rel);
    return b;
}

scene *unit_load(const char *path)
{
    scene *s = NULL;
    vg_status st = scene_load(path, &s);
    EXPECT(st == VG_OK && s, "%s does not load (status %d)", path, (int)st);
    return st == VG_OK ? s : NULL;
}

uint8_t *unit_read(const char *path, size_t *size)
{
    uint8_t *data = NULL;
    EXPECT(vg_file_read(path, &data, size) == VG_OK, "cannot read %s", path);
    return data;
}

float unit_f32(const uint8_t *b, size_t off)
{
    float v;
    memcpy(&v, b + off, 4);
    return v;
}

uint16_t unit_u16(const uint8_t *b, size_t off)
{
    uint16_t v;
    memcpy(&v, b + off, 2);
    return v;
}

static int b64_value(char c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
}

uint8_t *unit_base64(const char *text, size_t *size)
{
    const char *p = strstr(text, "base64,");
    p = p ? p + 7 : text;
    size_t n = strlen(p);
    uint8_t *out = malloc(n / 4 * 3 + 3);
    size_t o = 0;
    unsigned acc = 0;
    int bits = 0;
    for (; *p && *p != '"'; p++) {
        int v = b64_value(*p);
        if (v < 0)
            break;
        acc = (acc << 6) | (unsigned)v;
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out[o++] = (uint8_t)(acc >> bits);
        }
    }
    *size = o;
    return out;
}

static void base64_encode(const uint8_t *d, size_t n, char *out)
{
    static const char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        unsigned v = (unsigned)d[i] << 16 | (i + 1 < n ? (unsigned)d[i + 1] << 8 : 0) | (i + 2 < n ? d[i + 2] : 0);
        out[o++] = t[v >> 18 & 63];
        out[o++] = t[v >> 12 & 63];
        out[o++] = i + 1 < n ? t[v >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? t[v & 63] : '=';
    }
    out[o] = 0;
}

/* The temporary folder and what was written there, removed at exit. */
static char g_dir[64], g_written[32][128];
static int g_written_count;

static void remove_written(void)
{
    for (int i = 0; i < g_written_count; i++)
        unlink(g_written[i]);
    if (g_dir[0])
        rmdir(g_dir);
}

const char *unit_write_gltf(const char *name, const char *json, const void *data, size_t size)
{
    static char path[128];
    if (!g_dir[0]) {
        strcpy(g_dir, "/tmp/vergence-scene-unit-XXXXXX");
        if (!mkdtemp(g_dir))
            return NULL;
        atexit(remove_written);
    }
    snprintf(path, sizeof path, "%s/%s", g_dir, name);
    if (g_written_count < 32)
        snprintf(g_written[g_written_count++], sizeof g_written[0], "%s", path);
    const char *prefix = "data:application/octet-stream;base64,";
    char *uri = malloc(strlen(prefix) + size / 3 * 4 + 8);
    strcpy(uri, prefix);
    base64_encode(data, size, uri + strlen(prefix));
    size_t cap = strlen(json) * 2 + strlen(uri) * 4 + 16, o = 0;
    char *text = malloc(cap);
    for (const char *p = json; *p;) {
        if (!strncmp(p, "@BUF@", 5)) {
            o += (size_t)sprintf(text + o, "%s", uri);
            p += 5;
        } else {
            text[o++] = *p++;
        }
    }
    text[o] = 0;
    vg_status st = vg_file_write_atomic(path, text, o);
    EXPECT(st == VG_OK, "cannot write %s", path);
    free(uri);
    free(text);
    return path;
}

/* ------------------------------------------------------------------------- */
/* Reference math                                                            */
/* ------------------------------------------------------------------------- */

void unit_mat_identity(double m[16])
{
    for (int i = 0; i < 16; i++)
        m[i] = i % 5 == 0;
}

void unit_mat_mul(double out[16], const double a[16], const double b[16])
{
    double r[16];
    for (int row = 0; row < 4; row++)
        for (int col = 0; col < 4; col++) {
            double acc = 0;
            for (int k = 0; k < 4; k++)
                acc += a[k * 4 + row] * b[col * 4 + k];
            r[col * 4 + row] = acc;
        }
    memcpy(out, r, sizeof r);
}

/* T * R * S with R from the quaternion's rotation matrix. */
void unit_mat_trs(double m[16], const double t[3], const double q[4], const double s[3])
{
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                      {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                      {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    unit_mat_identity(m);
    for (int row = 0; row < 3; row++)
        for (int col = 0; col < 3; col++)
            m[col * 4 + row] = r[row][col] * s[col];
    m[12] = t[0], m[13] = t[1], m[14] = t[2];
}

void unit_mat_from_f(double m[16], const float f[16])
{
    for (int i = 0; i < 16; i++)
        m[i] = f[i];
}

void unit_mat_point(const double m[16], const double p[3], double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r];
}

void unit_sample(const float *times, int keys, const float *values, int comps, int mode, bool rotation,
                 double t, double *out)
{
    int stride = mode == UNIT_CUBIC ? 3 * comps : comps, at = mode == UNIT_CUBIC ? comps : 0;
    int k = 0;
    while (k + 1 < keys && times[k + 1] <= t)
        k++;
    if (t <= times[0] || k + 1 >= keys) {
        int key = t <= times[0] ? 0 : keys - 1;
        for (int c = 0; c < comps; c++)
            out[c] = values[key * stride + at + c];
        return;
    }
    double td = (double)times[k + 1] - times[k], u = (t - times[k]) / td;
    const float *a = values + k * stride, *b = values + (k + 1) * stride;
    if (mode == UNIT_STEP) {
        for (int c = 0; c < comps; c++)
            out[c] = a[c];
    } else if (mode == UNIT_CUBIC) {
        /* glTF 2.0 Appendix C: Hermite with tangents scaled by the interval. */
        for (int c = 0; c < comps; c++) {
            double p0 = a[comps + c], m0 = td * a[2 * comps + c], p1 = b[comps + c], m1 = td * b[c];
            out[c] = (2 * u * u * u - 3 * u * u + 1) * p0 + (u * u * u - 2 * u * u + u) * m0 +
                     (-2 * u * u * u + 3 * u * u) * p1 + (u * u * u - u * u) * m1;
        }
    } else if (rotation) {
        double d = 0, sign = 1;
        for (int c = 0; c < 4; c++)
            d += (double)a[c] * b[c];
        if (d < 0)
            d = -d, sign = -1;
        double th = acos(d > 1 ? 1 : d);
        double wa = th < 1e-6 ? 1 - u : sin((1 - u) * th) / sin(th), wb = th < 1e-6 ? u : sin(u * th) / sin(th);
        for (int c = 0; c < 4; c++)
            out[c] = wa * a[c] + sign * wb * b[c];
    } else {
        for (int c = 0; c < comps; c++)
            out[c] = a[c] * (1 - u) + b[c] * u;
    }
    if (rotation) {
        double len = sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
        for (int c = 0; c < 4; c++)
            out[c] /= len;
    }
}

/* ------------------------------------------------------------------------- */
/* Main                                                                      */
/* ------------------------------------------------------------------------- */

static const struct {
    const char *name;
    void (*run)(void);
} tests[] = {
    {"interpolation", test_interpolation},   {"cubic_tangents", test_cubic_tangents},
    {"morph", test_morph},                   {"morph_override", test_morph_override},
    {"skin", test_skin},                     {"skin_bind_pose", test_skin_bind_pose}, {"skin_reference", test_skin_reference},
    {"hierarchy", test_hierarchy},           {"sparse", test_sparse},
    {"predict", test_predict},              {"placement_cache", test_placement_cache},
    {"interleaved", test_interleaved},       {"no_indices", test_no_indices},
    {"topology", test_topology}, {"normals", test_normals}, {"colors", test_colors}, {"magic", test_magic},             {"saliency", test_saliency},
    {"textures", test_textures},             {"cameras", test_cameras},
    {"camera_resolve", test_camera_resolve}, {"camera_infinite", test_camera_infinite},
};

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: scene_unit TEST\n");
        return 2;
    }
    for (size_t i = 0; i < sizeof tests / sizeof tests[0]; i++) {
        if (strcmp(argv[1], tests[i].name))
            continue;
        tests[i].run();
        printf("%s: %s (%d failed checks)\n", argv[1], vg_test_failures ? "FAILED" : "ok", vg_test_failures);
        return vg_test_failures ? 1 : 0;
    }
    fprintf(stderr, "scene_unit: unknown test '%s'\n", argv[1]);
    return 2;
}
