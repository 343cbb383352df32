// vergence — warp.classify / warp.compact (shared declarations). Triangles
// go in chunks of 256 of one instance: classify culls them (warp_cull),
// warps each vertex they use once for both eyes (warp_vertices),
// levels each edge they use once (warp_edges, then warp_edge_levels over the
// edges that need sampling, by their number of samples), then decides each
// triangle's kind (0 culled, 1 flat, 2 tessellated) in parallel over all chunks;
// compact writes each instance's flat and tessellated index lists in the
// original triangle order (prefix sums, no atomics) and its draw commands.
layout(set = 0, binding = VG_BINDING_VERTICES, scalar) readonly buffer VertexBlock { float vertices[]; };
layout(set = 0, binding = VG_BINDING_INDICES, scalar) readonly buffer IndexBlock { uint indices[]; };
layout(set = 0, binding = VG_BINDING_INSTANCES, scalar) readonly buffer InstanceBlock { vg_warp_instance instances[]; };
layout(set = 0, binding = VG_BINDING_FLAT, scalar) writeonly buffer FlatBlock { uint flat_indices[]; };
layout(set = 0, binding = VG_BINDING_TESS, scalar) writeonly buffer TessBlock { uint tess_indices[]; };
layout(set = 0, binding = VG_BINDING_ARGS, scalar) writeonly buffer ArgsBlock { uint args[]; };
layout(set = 0, binding = VG_BINDING_CHUNKS, scalar) readonly buffer ChunkBlock { vg_warp_chunk chunks[]; };
layout(set = 0, binding = VG_BINDING_KINDS, scalar) buffer KindBlock { uint kinds[]; };
layout(set = 0, binding = VG_BINDING_COUNTS, scalar) buffer CountBlock { uvec2 counts[]; };
layout(set = 0, binding = VG_BINDING_TESS_LEVELS, scalar) writeonly buffer TessLevelBlock { uint tess_levels[]; };
layout(set = 0, binding = VG_BINDING_TRI_EDGES, scalar) readonly buffer TriEdgeBlock { uint tri_edges[]; };
layout(set = 0, binding = VG_BINDING_EDGES, scalar) readonly buffer EdgeBlock { vg_warp_edge edges[]; };
layout(set = 0, binding = VG_BINDING_EDGE_LEVELS, scalar) buffer EdgeLevelBlock { uint edge_levels[]; };
layout(set = 0, binding = VG_BINDING_VERTEX_WARP, scalar) writeonly buffer VertexWarpBlock { vec2 vertex_warp[]; };
layout(set = 0, binding = VG_BINDING_VERTEX_SEEN, scalar) buffer VertexSeenBlock { uint vertex_seen[]; };
layout(set = 0, binding = VG_BINDING_CLASSIFY_WORK, scalar) buffer EdgeWorkBlock {
    uvec4 work_lists[VG_CLASSIFY_LISTS];
    uint work_items[];
};
layout(push_constant, scalar) uniform ClassifyBlock { vg_classify_push pc; };

// A scene vertex's position (VertexBlock: 6 floats per vertex).
vec3 position(uint v)
{
    return vec3(vertices[6u * v], vertices[6u * v + 1u], vertices[6u * v + 2u]);
}

const uint KIND_CULLED = 0u, KIND_FLAT = 1u, KIND_TESSELLATED = 2u;
