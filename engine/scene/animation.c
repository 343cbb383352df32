/* vergence — animation sampling and the small transform math it needs.
 *
 * Samplers follow glTF 2.0 spec 3.11 ("Animations") and Appendix C
 * ("Animation sampler interpolation modes"): outside the key range the first
 * or last key holds; LINEAR rotations use spherical interpolation along the
 * shortest arc; CUBICSPLINE is a Hermite spline whose tangents are scaled by
 * the key interval, and rotations are renormalised afterwards. */
#include <math.h>
#include <string.h>

#include "scene_internal.h"

/* ------------------------------------------------------------------------- */
/* Math                                                                      */
/* ------------------------------------------------------------------------- */

void scene_mat4_identity(float m[16])
{
    memset(m, 0, 16 * sizeof *m);
    m[0] = m[5] = m[10] = m[15] = 1.0f;
}

void scene_mat4_mul(float out[16], const float a[16], const float b[16])
{
    float r[16];
    for (int c = 0; c < 4; c++)
        for (int i = 0; i < 4; i++)
            r[c * 4 + i] = a[i] * b[c * 4] + a[4 + i] * b[c * 4 + 1] + a[8 + i] * b[c * 4 + 2] +
                           a[12 + i] * b[c * 4 + 3];
    memcpy(out, r, sizeof r);
}

/* M = T * R * S (spec 3.5.3, "Transformations"). */
void scene_mat4_from_trs(float m[16], const float t[3], const float q[4], const float s[3])
{
    float x = q[0], y = q[1], z = q[2], w = q[3];
    float xx = x * x, yy = y * y, zz = z * z, xy = x * y, xz = x * z, yz = y * z;
    float wx = w * x, wy = w * y, wz = w * z;
    m[0] = (1 - 2 * (yy + zz)) * s[0];
    m[1] = 2 * (xy + wz) * s[0];
    m[2] = 2 * (xz - wy) * s[0];
    m[3] = 0;
    m[4] = 2 * (xy - wz) * s[1];
    m[5] = (1 - 2 * (xx + zz)) * s[1];
    m[6] = 2 * (yz + wx) * s[1];
    m[7] = 0;
    m[8] = 2 * (xz + wy) * s[2];
    m[9] = 2 * (yz - wx) * s[2];
    m[10] = (1 - 2 * (xx + yy)) * s[2];
    m[11] = 0;
    m[12] = t[0], m[13] = t[1], m[14] = t[2], m[15] = 1;
}

bool scene_mat4_invert(float out[16], const float m[16])
{
    /* Cofactor expansion through 2x2 sub-determinants of the top and bottom
     * row pairs; double precision so that near-singular inputs stay usable. */
    double a[16];
    for (int i = 0; i < 16; i++)
        a[i] = m[i];
    /* a is column-major: element (row r, col c) = a[c * 4 + r]. */
#define E(r, c) a[(c) * 4 + (r)]
    double s0 = E(0, 0) * E(1, 1) - E(1, 0) * E(0, 1);
    double s1 = E(0, 0) * E(1, 2) - E(1, 0) * E(0, 2);
    double s2 = E(0, 0) * E(1, 3) - E(1, 0) * E(0, 3);
    double s3 = E(0, 1) * E(1, 2) - E(1, 1) * E(0, 2);
    double s4 = E(0, 1) * E(1, 3) - E(1, 1) * E(0, 3);
    double s5 = E(0, 2) * E(1, 3) - E(1, 2) * E(0, 3);
    double c5 = E(2, 2) * E(3, 3) - E(3, 2) * E(2, 3);
    double c4 = E(2, 1) * E(3, 3) - E(3, 1) * E(2, 3);
    double c3 = E(2, 1) * E(3, 2) - E(3, 1) * E(2, 2);
    double c2 = E(2, 0) * E(3, 3) - E(3, 0) * E(2, 3);
    double c1 = E(2, 0) * E(3, 2) - E(3, 0) * E(2, 2);
    double c0 = E(2, 0) * E(3, 1) - E(3, 0) * E(2, 1);
    double det = s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
    if (det == 0.0 || !isfinite(det)) {
        scene_mat4_identity(out);
        return false;
    }
    double k = 1.0 / det;
    double r[4][4]; /* r[row][col] of the inverse */
    r[0][0] = (E(1, 1) * c5 - E(1, 2) * c4 + E(1, 3) * c3) * k;
    r[0][1] = (-E(0, 1) * c5 + E(0, 2) * c4 - E(0, 3) * c3) * k;
    r[0][2] = (E(3, 1) * s5 - E(3, 2) * s4 + E(3, 3) * s3) * k;
    r[0][3] = (-E(2, 1) * s5 + E(2, 2) * s4 - E(2, 3) * s3) * k;
    r[1][0] = (-E(1, 0) * c5 + E(1, 2) * c2 - E(1, 3) * c1) * k;
    r[1][1] = (E(0, 0) * c5 - E(0, 2) * c2 + E(0, 3) * c1) * k;
    r[1][2] = (-E(3, 0) * s5 + E(3, 2) * s2 - E(3, 3) * s1) * k;
    r[1][3] = (E(2, 0) * s5 - E(2, 2) * s2 + E(2, 3) * s1) * k;
    r[2][0] = (E(1, 0) * c4 - E(1, 1) * c2 + E(1, 3) * c0) * k;
    r[2][1] = (-E(0, 0) * c4 + E(0, 1) * c2 - E(0, 3) * c0) * k;
    r[2][2] = (E(3, 0) * s4 - E(3, 1) * s2 + E(3, 3) * s0) * k;
    r[2][3] = (-E(2, 0) * s4 + E(2, 1) * s2 - E(2, 3) * s0) * k;
    r[3][0] = (-E(1, 0) * c3 + E(1, 1) * c1 - E(1, 2) * c0) * k;
    r[3][1] = (E(0, 0) * c3 - E(0, 1) * c1 + E(0, 2) * c0) * k;
    r[3][2] = (-E(3, 0) * s3 + E(3, 1) * s1 - E(3, 2) * s0) * k;
    r[3][3] = (E(2, 0) * s3 - E(2, 1) * s1 + E(2, 2) * s0) * k;
#undef E
    for (int c = 0; c < 4; c++)
        for (int rr = 0; rr < 4; rr++)
            out[c * 4 + rr] = (float)r[rr][c];
    return true;
}

void scene_quat_normalize(float q[4])
{
    float len = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(len > 1e-30f) || !isfinite(len)) {
        q[0] = q[1] = q[2] = 0.0f; /* a zero or broken quaternion: identity */
        q[3] = 1.0f;
        return;
    }
    for (int i = 0; i < 4; i++)
        q[i] /= len;
}

/* Shortest-arc spherical interpolation (spec Appendix C, "Spherical linear
 * interpolation"); nearly parallel keys fall back to normalised lerp. */
static void quat_slerp(const float *a, const float *b_in, float u, float *out)
{
    float b[4] = {b_in[0], b_in[1], b_in[2], b_in[3]};
    float d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (d < 0.0f) {
        for (int i = 0; i < 4; i++)
            b[i] = -b[i];
        d = -d;
    }
    float wa = 1.0f - u, wb = u;
    if (d < 0.9995f) {
        float theta = acosf(d), s = sinf(theta);
        wa = sinf((1.0f - u) * theta) / s;
        wb = sinf(u * theta) / s;
    }
    for (int i = 0; i < 4; i++)
        out[i] = wa * a[i] + wb * b[i];
    scene_quat_normalize(out);
}

/* ------------------------------------------------------------------------- */
/* Sampling                                                                  */
/* ------------------------------------------------------------------------- */

/* Largest k with times[k] <= t, given times[0] <= t < times[n - 1]. */
static int find_key(const float *times, int n, float t)
{
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = lo + (hi - lo) / 2;
        if (times[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

void scene_sampler_sample(const scene_sampler *smp, float t, bool rotation, float *out)
{
    int n = smp->key_count, c = smp->components;
    bool cubic = smp->interp == SCENE_INTERP_CUBIC;
    /* In CUBICSPLINE each key stores (in-tangent, value, out-tangent). */
    const float *v = smp->values;
    size_t key_stride = (size_t)c * (cubic ? 3 : 1), value_at = cubic ? (size_t)c : 0;
    if (n <= 0 || c <= 0)
        return;
    if (n == 1 || !(t > smp->times[0])) {
        memcpy(out, v + value_at, (size_t)c * sizeof *out);
        return;
    }
    if (t >= smp->times[n - 1]) {
        memcpy(out, v + (size_t)(n - 1) * key_stride + value_at, (size_t)c * sizeof *out);
        return;
    }
    int k = find_key(smp->times, n, t);
    float t0 = smp->times[k], dt = smp->times[k + 1] - t0;
    float u = dt > 0.0f ? (t - t0) / dt : 0.0f;
    const float *p0 = v + (size_t)k * key_stride, *p1 = p0 + key_stride;

    if (smp->interp == SCENE_INTERP_STEP) {
        memcpy(out, p0, (size_t)c * sizeof *out);
    } else if (cubic) {
        /* p(u) = (2u^3 - 3u^2 + 1) v_k + dt (u^3 - 2u^2 + u) b_k
         *      + (-2u^3 + 3u^2) v_k+1 + dt (u^3 - u^2) a_k+1 */
        float u2 = u * u, u3 = u2 * u;
        float h00 = 2 * u3 - 3 * u2 + 1, h10 = (u3 - 2 * u2 + u) * dt;
        float h01 = -2 * u3 + 3 * u2, h11 = (u3 - u2) * dt;
        const float *vk = p0 + c, *bk = p0 + 2 * c, *ak1 = p1, *vk1 = p1 + c;
        for (int i = 0; i < c; i++)
            out[i] = h00 * vk[i] + h10 * bk[i] + h01 * vk1[i] + h11 * ak1[i];
        if (rotation)
            scene_quat_normalize(out);
    } else if (rotation && c == 4) {
        quat_slerp(p0, p1, u, out);
    } else {
        for (int i = 0; i < c; i++)
            out[i] = p0[i] + (p1[i] - p0[i]) * u;
    }
}
