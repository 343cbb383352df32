// vergence — the tessellation decision of warp.stereo, shared by the
// tessellation control shader and warp.classify (so both decide alike):
// edge levels from the projected length (paper 4.6: down to tess_px pixels)
// or from the disparity error (subdivide an edge only where the target
// departs from linear interpolation along it), and frustum culling.
// Needs common.glsl, stereo.glsl and cascade.glsl.

// Target disparity (image px) where the depth map sees this point (the
// cascade's direct stage), else -1e9.
float visible_target_px(vec3 world)
{
    vec4 c = u.view_proj * vec4(world, 1.0);
    if (c.w <= 1e-6)
        return -1e9;
    ivec2 size = textureSize(depth_map, 0);
    ivec2 p = ivec2(floor(centre_pixel(c)));
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size)))
        return -1e9;
    if (!same_surface(texelFetch(depth_map, p, 0).r, c.w))
        return -1e9;
    return px_from_vergence(cascade(centre_pixel(c), c.w).x);
}

// The disparity (image px) the warp will give a vertex: the cascade, or the
// curve's near continuation for points nearer than every pixel.
float vertex_target_px(vec3 world)
{
    vec4 c = u.view_proj * vec4(world, 1.0);
    if (c.w * curve.inv_depth_near > 1.0)
        return px_from_vergence(cascade(centre_pixel(c), c.w).x);
    return near_disparity_times_depth(c.w) / max(c.w, 1e-6);
}

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
    float level = 1.0;
    if (u.warp.x > 0.0) {
        level = len / u.warp.x;
    } else if (u.warp.y > 0.0) {
        // Between its vertices the warp interpolates disparity linearly in
        // screen space (perspective-correct interpolation of d w over w):
        // compare the target along the edge with that line.
        const int N = 6;
        float da = vertex_target_px(a), db = vertex_target_px(b), err = 0.0;
        for (int i = 1; i < N; i++) {
            float t = float(i) / float(N);
            float di = visible_target_px(mix(a, b, t));
            float s = t * cb.w / mix(ca.w, cb.w, t); /* screen-space parameter of 3D t */
            if (di > -1e8)
                err = max(err, abs(di - mix(da, db, s)));
        }
        // The manipulated and optimised maps bend sharply (the operators are
        // piecewise linear in disparity), so the error falls only linearly
        // with the number of segments: size them for that.
        level = min(err / u.warp.y, len);
    }
    return clamp(ceil(level), 1.0, u.warp2.x);
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

