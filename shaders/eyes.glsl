// vergence — the SDK's own stereo pair (engine/warp/gpu/eyes_gpu.h): the
// host's shaded centre view moved per pixel by half the disparity its
// target map asks for, each eye at once (gl_GlobalInvocationID.z: 0 left,
// 1 right). Every kernel of the pass includes this.
#include "common.glsl"
#include "stereo.glsl"

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;
layout(set = 0, binding = 1, r32f) uniform readonly image2D depth_map;  // linear depth, metres
layout(set = 0, binding = 2, r32f) uniform readonly image2D target_map; // target vergence, arcmin
layout(set = 0, binding = 3) uniform sampler2D color_map;               // the host's shaded centre view
// Per eye and pixel: the nearest depth that landed there (its float bits:
// positive floats order as their bits), EYES_EMPTY where none did.
layout(set = 0, binding = 4, std430) buffer Nearest { uint nearest[]; };
layout(set = 0, binding = 5, rgba8) uniform image2D left_eye;
layout(set = 0, binding = 6, rgba8) uniform image2D right_eye;

layout(push_constant) uniform EyesPush {
    uint width, height;
    float same_surface;   // neighbours within this relative depth are one surface
    uint max_span;        // the widest span one pixel fills, eye pixels
} pc;

#define EYES_EMPTY 0xffffffffu

void eyes_store(uint eye, ivec2 p, vec4 c)
{
    if (eye == 0u)
        imageStore(left_eye, p, c);
    else
        imageStore(right_eye, p, c);
}

vec4 eyes_load(uint eye, ivec2 p)
{
    return eye == 0u ? imageLoad(left_eye, p) : imageLoad(right_eye, p);
}

uint eyes_index(uint eye, ivec2 p)
{
    return (eye * pc.height + uint(p.y)) * pc.width + uint(p.x);
}

// Where centre pixel p lands in the eye, its left edge in eye pixels.
float eyes_x(ivec2 p, float side)
{
    return float(p.x) + side * 0.5 * vgx_px_from_vergence(imageLoad(target_map, p).r);
}

// The eye pixels centre pixel p covers: from its own landing place to its
// right neighbour's when both are one surface (a stretched surface leaves
// no crack), else its own pixel. x: first, y: one past the last.
ivec2 eyes_span(ivec2 p, float side, float z)
{
    float x0 = eyes_x(p, side);
    float x1 = x0 + 1.0;
    if (p.x + 1 < int(pc.width)) {
        ivec2 q = ivec2(p.x + 1, p.y);
        float zq = imageLoad(depth_map, q).r;
        if (abs(zq - z) < pc.same_surface * z)
            x1 = max(x0 + 1.0, eyes_x(q, side));
    }
    int a = int(floor(x0 + 0.5)), b = int(floor(x1 + 0.5));
    b = min(max(b, a + 1), a + int(pc.max_span));
    return ivec2(max(a, 0), min(b, int(pc.width)));
}
