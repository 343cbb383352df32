#version 460
#extension GL_GOOGLE_include_directive : require
// vgx.eyes.fill: an eye pixel nothing landed in is a disocclusion (or the
// frame's edge): it takes the colour of the nearest covered pixel along its
// row on the farther side, the background the moved surface uncovered
// (alpha 0.5: filled). Nothing within EYES_REACH: black, alpha 0.
#include "eyes.glsl"

#define EYES_REACH 256

void main()
{
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(pc.width))
        return;
    uint eye = gl_GlobalInvocationID.z;
    if (nearest[eyes_index(eye, p)] != EYES_EMPTY)
        return;
    int left = -1, right = -1;
    for (int d = 1; d <= EYES_REACH && (left < 0 || right < 0); d++) {
        if (left < 0 && p.x - d >= 0 && nearest[eyes_index(eye, ivec2(p.x - d, p.y))] != EYES_EMPTY)
            left = p.x - d;
        if (right < 0 && p.x + d < int(pc.width) && nearest[eyes_index(eye, ivec2(p.x + d, p.y))] != EYES_EMPTY)
            right = p.x + d;
    }
    int from = left;
    if (right >= 0 && (left < 0 || uintBitsToFloat(nearest[eyes_index(eye, ivec2(right, p.y))]) >
                                       uintBitsToFloat(nearest[eyes_index(eye, ivec2(left, p.y))])))
        from = right;
    vec4 c = from >= 0 ? vec4(eyes_load(eye, ivec2(from, p.y)).rgb, 0.5) : vec4(0.0);
    eyes_store(eye, p, c);
}
