#version 460
#extension GL_GOOGLE_include_directive : require
// warp.stereo tessellation control: edge levels from the projected length
// (paper 4.6: down to tess_px pixels) or from the disparity error (subdivide
// an edge only where the target departs from linear interpolation along it).
#include "common.glsl"
#include "stereo.glsl"
#include "cascade.glsl"

layout(vertices = 3) out;
layout(location = 0) in vec3 v_pos[];
layout(location = 1) in vec3 v_normal[];
layout(location = 2) in vec2 v_uv[];
layout(location = 3) in vec4 v_color[];
layout(location = 0) out vec3 tc_pos[];
layout(location = 1) out vec3 tc_normal[];
layout(location = 2) out vec2 tc_uv[];
layout(location = 3) out vec4 tc_color[];

// Target disparity (image px) where the depth map sees this point, else NaN-free -1e9.
float visible_target_px(vec3 world)
{
    vec4 c = u.view_proj * vec4(world, 1.0);
    if (c.w <= u.camera_pos.w * 1e-6)
        return -1e9;
    vec2 px = centre_pixel(c);
    ivec2 size = textureSize(depth_map, 0);
    ivec2 p = ivec2(floor(px));
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size)))
        return -1e9;
    if (!same_surface(texelFetch(depth_map, p, 0).r, c.w))
        return -1e9;
    return px_from_vergence(cascade(px, c.w).x);
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
    // Measure the part in front of the camera.
    if (ca.w < near_w)
        ca = mix(ca, cb, (near_w - ca.w) / (cb.w - ca.w));
    if (cb.w < near_w)
        cb = mix(cb, ca, (near_w - cb.w) / (ca.w - cb.w));
    float len = distance(centre_pixel(ca), centre_pixel(cb));
    float level = 1.0;
    if (u.warp.x > 0.0) {
        level = len / u.warp.x;
    } else if (u.warp.y > 0.0) {
        const int N = 8;
        float da = visible_target_px(a), db = visible_target_px(b), err = 0.0;
        if (da > -1e8 && db > -1e8)
            for (int i = 1; i < N; i++) {
                float t = float(i) / float(N);
                float di = visible_target_px(mix(a, b, t));
                if (di > -1e8)
                    err = max(err, abs(di - mix(da, db, t)));
            }
        // Linear interpolation error falls with the square of the segment length.
        level = min(sqrt(err / u.warp.y), len);
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

void main()
{
    tc_pos[gl_InvocationID] = v_pos[gl_InvocationID];
    tc_normal[gl_InvocationID] = v_normal[gl_InvocationID];
    tc_uv[gl_InvocationID] = v_uv[gl_InvocationID];
    tc_color[gl_InvocationID] = v_color[gl_InvocationID];
    if (gl_InvocationID != 0)
        return;
    vec4 c0 = u.view_proj * vec4(v_pos[0], 1.0);
    vec4 c1 = u.view_proj * vec4(v_pos[1], 1.0);
    vec4 c2 = u.view_proj * vec4(v_pos[2], 1.0);
    if (outside(c0, c1, c2)) {
        gl_TessLevelOuter[0] = gl_TessLevelOuter[1] = gl_TessLevelOuter[2] = 0.0;
        gl_TessLevelInner[0] = 0.0;
        return;
    }
    float e0 = edge_level(v_pos[1], v_pos[2]);
    float e1 = edge_level(v_pos[2], v_pos[0]);
    float e2 = edge_level(v_pos[0], v_pos[1]);
    gl_TessLevelOuter[0] = e0;
    gl_TessLevelOuter[1] = e1;
    gl_TessLevelOuter[2] = e2;
    gl_TessLevelInner[0] = max(e0, max(e1, e2));
}
