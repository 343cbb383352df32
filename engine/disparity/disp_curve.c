/* vergence — the global depth -> vergence curve on the CPU, and its file. */
#include "disp_curve.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "core/io.h"
#include "core/log.h"

static bool pair_ok(float z, float v) { return z > 0.0f && isfinite(z) && v > 0.0f && isfinite(v); }

vg_status disp_curve_build(const float *depth, const float *vergence, size_t n, vgx_curve_data *out)
{
    memset(out, 0, sizeof *out);
    double lo = INFINITY, hi = 0;
    for (size_t i = 0; i < n; i++)
        if (pair_ok(depth[i], vergence[i])) {
            double q = 1.0 / depth[i];
            lo = q < lo ? q : lo;
            hi = q > hi ? q : hi;
        }
    if (!(hi > 0))
        return VG_OK;
    /* As the GPU: float bounds; a single depth still needs a span to index bins. */
    out->valid = 1;
    out->inv_depth_far = (float)lo;
    out->inv_depth_near = hi > lo ? (float)hi : (float)(lo * 1.001 + 1e-6);
    double span = (double)out->inv_depth_near - out->inv_depth_far;
    /* Per bin: how many pairs, their vergences and where they sit in the bin. */
    double count[VGX_CURVE_BINS] = {0}, sum[VGX_CURVE_BINS] = {0}, offset[VGX_CURVE_BINS] = {0};
    for (size_t i = 0; i < n; i++) {
        if (!pair_ok(depth[i], vergence[i]))
            continue;
        double pos = (1.0 / depth[i] - out->inv_depth_far) / span * VGX_CURVE_BINS;
        pos = pos < 0 ? 0 : pos > VGX_CURVE_BINS - 1e-3 ? VGX_CURVE_BINS - 1e-3 : pos;
        int b = (int)pos;
        count[b] += 1;
        sum[b] += vergence[i];
        offset[b] += pos - b;
    }
    /* Nodes: the centroid of a populated bin, the centre of an empty one. */
    float q[VGX_CURVE_BINS], v[VGX_CURVE_BINS];
    for (int b = 0; b < VGX_CURVE_BINS; b++) {
        double inside = count[b] > 0 ? offset[b] / count[b] : 0.5;
        q[b] = (float)(out->inv_depth_far + (b + inside) / VGX_CURVE_BINS * span);
        v[b] = count[b] > 0 ? (float)(sum[b] / count[b]) : 0.0f;
    }
    /* Empty bins: linear in inverse depth between the nearest populated nodes. */
    for (int b = 0; b < VGX_CURVE_BINS; b++) {
        out->inv_depth[b] = q[b];
        if (count[b] > 0) {
            out->vergence[b] = v[b];
            continue;
        }
        int l = b, r = b;
        while (l >= 0 && count[l] == 0)
            l--;
        while (r < VGX_CURVE_BINS && count[r] == 0)
            r++;
        if (l >= 0 && r < VGX_CURVE_BINS)
            out->vergence[b] = v[l] + (v[r] - v[l]) * (q[b] - q[l]) / (q[r] - q[l]);
        else
            out->vergence[b] = l >= 0 ? v[l] : v[r];
    }
    return VG_OK;
}

/* ------------------------------------------------------------------------- */
/* File                                                                      */
/* ------------------------------------------------------------------------- */

vg_status disp_curve_write(const char *path, const vgx_curve_data *c)
{
    uint8_t buf[12 + sizeof(vgx_curve_data)];
    uint32_t head[3] = {0, 1, VGX_CURVE_BINS};
    memcpy(head, "VGCV", 4);
    memcpy(buf, head, 12);
    memcpy(buf + 12, c, sizeof *c);
    return vg_file_write_atomic(path, buf, sizeof buf);
}

vg_status disp_curve_read(const char *path, vgx_curve_data *c)
{
    uint8_t *data;
    size_t size;
    vg_status st = vg_file_read(path, &data, &size);
    if (st != VG_OK)
        return st;
    uint32_t head[3];
    if (size != 12 + sizeof *c) {
        vg_error("%s: not a vergence curve file (%zu bytes, want %zu)", path, size, 12 + sizeof *c);
        st = VG_ERR_FORMAT;
    } else {
        memcpy(head, data, 12);
        if (memcmp(data, "VGCV", 4) || head[1] != 1 || head[2] != VGX_CURVE_BINS) {
            vg_error("%s: not a vergence curve file (bad magic, version or bin count)", path);
            st = VG_ERR_FORMAT;
        } else {
            memcpy(c, data + 12, sizeof *c);
            bool ok = c->valid == 1 && isfinite(c->inv_depth_near) && isfinite(c->inv_depth_far) &&
                      c->inv_depth_near > c->inv_depth_far && c->inv_depth_far >= 0;
            for (int b = 0; b < VGX_CURVE_BINS && ok; b++)
                ok = isfinite(c->inv_depth[b]) && (b == 0 || c->inv_depth[b] >= c->inv_depth[b - 1]);
            bool range = true;
            for (int b = 0; b < VGX_CURVE_BINS && ok && range; b++)
                range = c->vergence[b] > 0 && c->vergence[b] < DISP_CURVE_MAX_ARCMIN;
            if (!ok) {
                vg_error("%s: curve values are not finite or not increasing in inverse depth", path);
                st = VG_ERR_FORMAT;
            } else if (!range) {
                vg_error("%s: a vergence of the curve is outside (0, %g) arcmin: not a curve of a scene", path,
                         DISP_CURVE_MAX_ARCMIN);
                st = VG_ERR_FORMAT;
            }
        }
    }
    free(data);
    return st;
}
