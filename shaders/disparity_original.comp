#version 460
#extension GL_GOOGLE_include_directive : require
// disparity.original (DESIGN.md step 3): g, the vergence a viewer of the
// display gets from the original parallel stereo camera, from linear depth.
// Same formula as stereo_camera_vergence() (engine/stereo).
#include "common.glsl"
#include "stereo.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 1, r32f) uniform readonly image2D depth_image;
layout(set = 0, binding = 2, r32f) uniform writeonly image2D g_image;

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(g_image))))
        return;
    imageStore(g_image, p, vec4(vergence_from_depth(imageLoad(depth_image, p).r)));
}
