#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_scalar_block_layout : require
// probe: over the pixels whose instance id is one of the push constant's,
// the number of pixels and the sum of (shown map - g), one partial per
// workgroup (a tree in shared memory; the host adds the partials).
#include "shared.h"

layout(local_size_x = 16, local_size_y = 16) in;
layout(set = 0, binding = 0) uniform usampler2D ids;
layout(set = 0, binding = 1) uniform sampler2D g_map;
layout(set = 0, binding = 2) uniform sampler2D shown_map;
layout(set = 0, binding = 3, scalar) writeonly buffer Partials { vg_probe_partial partial[]; };
layout(push_constant, scalar) uniform ProbeBlock { vg_probe_push p; };

shared float s_sum[256];
shared uint s_pixels[256];

void main()
{
    ivec2 q = ivec2(gl_GlobalInvocationID.xy);
    uint i = gl_LocalInvocationIndex;
    float sum = 0.0;
    uint pixels = 0u;
    if (q.x < int(p.width) && q.y < int(p.height)) {
        uint id = texelFetch(ids, q, 0).r;
        bool hit = false;
        for (int k = 0; k < VG_PROBE_MAX_IDS; k++)
            hit = hit || (id != 0u && id == p.ids[k]);
        if (hit) {
            sum = texelFetch(shown_map, q, 0).r - texelFetch(g_map, q, 0).r;
            pixels = 1u;
        }
    }
    s_sum[i] = sum;
    s_pixels[i] = pixels;
    barrier();
    for (uint n = 128u; n > 0u; n >>= 1) {
        if (i < n) {
            s_sum[i] += s_sum[i + n];
            s_pixels[i] += s_pixels[i + n];
        }
        barrier();
    }
    if (i == 0u)
        partial[gl_WorkGroupID.y * p.groups_x + gl_WorkGroupID.x] = vg_probe_partial(s_sum[0], s_pixels[0]);
}
