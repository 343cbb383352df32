// vergence — the tessellation decision of warp.stereo, made once per frame
// by warp.classify (the tessellation control shader reads its levels):
// edge levels from the projected length (paper 4.6: down to tess_px pixels)
// or from the disparity error (subdivide an edge only where the target
// departs from linear interpolation along it), and frustum culling.
// Needs common.glsl, stereo.glsl and cascade.glsl.

// The disparity (image px) the warp gives a point: the cascade, or the
// curve's near continuation for points nearer than every pixel. `seen` tells
// whether the direct fetch or the 3x3 neighbourhood resolves it on screen,
// where the warp's error is held to the tolerance. The Halton search is left
// out: the points it resolves are where the centre view does not show the
// surface, their target is a neighbour's carried along the curve anyway, and
// searching 64 samples for every hidden point of every edge was 80 % of this
// pass (balloon 960x540: 396 -> 74 ms; warp p99 0.0294 -> 0.0303 px).
float target_px(vec3 world, out bool seen)
{
    vec4 c = u.view_proj * vec4(world, 1.0);
    seen = false;
    if (c.w * curve.inv_depth_near <= 1.0)
        return near_disparity_times_depth(c.w) / max(c.w, 1e-6);
    vec2 px = centre_pixel(c);
    ivec2 p = ivec2(floor(px)), size = textureSize(depth_map, 0);
    vec2 v = cascade_stages(px, c.w, false);
    seen = all(greaterThanEqual(p, ivec2(0))) && all(lessThan(p, size)) && v.y < float(VG_STAGE_CURVE);
    return px_from_vergence(v.x);
}

// Samples along a long edge for the error-driven level. Keep the arrays
// small: with 49 samples lavapipe drew long garbage triangles (silently).
const int EDGE_SAMPLES = 24;

float edge_level(vec3 a, vec3 b)
{
    // The same edge seen from both of its triangles must get the same level
    // (no cracks): evaluate it in a canonical endpoint order.
    if (a.x > b.x || (a.x == b.x && (a.y > b.y || (a.y == b.y && a.z > b.z)))) {
        vec3 t = a;
        a = b;
        b = t;
    }
    vec4 ca = u.view_proj * vec4(a, 1.0), cb = u.view_proj * vec4(b, 1.0);
    float near_w = 1e-3;
    if (ca.w < near_w && cb.w < near_w)
        return 1.0;
    // Measure the part in front of the camera (clip space is linear in world space).
    if (ca.w < near_w) {
        float k = (near_w - ca.w) / (cb.w - ca.w);
        ca = mix(ca, cb, k);
        a = mix(a, b, k);
    }
    if (cb.w < near_w) {
        float k = (near_w - cb.w) / (ca.w - cb.w);
        cb = mix(cb, ca, k);
        b = mix(b, a, k);
    }
    float len = distance(centre_pixel(ca), centre_pixel(cb));
    if (len <= 1.0)
        return 1.0; /* a pixel or less: nothing to gain */
    float max_level = min(ceil(len), u.warp2.x);
    if (u.warp.x > 0.0)
        return clamp(ceil(len / u.warp.x), 1.0, u.warp2.x);
    // Error-driven: between its vertices the warp interpolates disparity
    // linearly in screen space (perspective-correct interpolation of d w
    // over w). The target need not be smooth at any scale the mesh knows
    // (operator kinks, the solver's coarse grid), so sample the edge about
    // every two pixels (at most EDGE_SAMPLES) and take the fewest equal
    // segments whose vertices, interpolated, stay within the tolerance at
    // every sample inside them; m is a multiple of every level tried, so
    // segment ends are samples. An edge no level fits gets the 1-pixel level.
    int m = len <= 12.0 ? 6 : len <= 24.0 ? 12 : EDGE_SAMPLES;
    float d[EDGE_SAMPLES + 1];
    uint seen = 0u; /* bit i: sample i is on a surface the warp measures */
    for (int i = 0; i <= m; i++) {
        bool s;
        d[i] = target_px(mix(a, b, float(i) / float(m)), s);
        seen |= s ? 1u << i : 0u;
    }
    const int LEVELS[7] = int[7](1, 2, 3, 4, 6, 8, 12);
    float level = 1.0, err = 0.0;
    for (int k = 0; k < 7; k++) {
        int l = LEVELS[k], step = m / l;
        if (float(l) >= max_level || step < 2)
            break;
        if (m % l != 0)
            continue;
        level = float(l);
        err = 0.0;
        for (int i = 0; i < m; i += step) {
            float w0 = mix(ca.w, cb.w, float(i) / float(m)), w1 = mix(ca.w, cb.w, float(i + step) / float(m));
            for (int j = 1; j < step; j++) {
                float t = float(j) / float(step);
                float s = t * w1 / mix(w0, w1, t); /* screen-space parameter of 3D t */
                if ((seen & (1u << (i + j))) != 0u)
                    err = max(err, abs(d[i + j] - mix(d[i], d[i + step], s)));
            }
        }
        if (err <= u.warp.y)
            return level;
    }
    // No level fits: past the sampling the error falls about linearly with
    // the segment length (the targets bend sharply: operator kinks).
    return clamp(ceil(level * err / u.warp.y), level + 1.0, max_level);
}

bool outside(vec4 c0, vec4 c1, vec4 c2)
{
    // Keep a margin for the horizontal eye shift.
    float m = 1.3;
    if (c0.w <= 0.0 && c1.w <= 0.0 && c2.w <= 0.0) return true;
    if (c0.x > m * c0.w && c1.x > m * c1.w && c2.x > m * c2.w) return true;
    if (c0.x < -m * c0.w && c1.x < -m * c1.w && c2.x < -m * c2.w) return true;
    if (c0.y > c0.w && c1.y > c1.w && c2.y > c2.w) return true;
    if (c0.y < -c0.w && c1.y < -c1.w && c2.y < -c2.w) return true;
    return false;
}

