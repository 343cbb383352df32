#version 460
#extension GL_GOOGLE_include_directive : require
// warp.classify.vertices (with warp_edges): every visible vertex's warp without the Halton
// search; the unresolved ones go to a list (warp_vertices.glsl).
#include "warp_vertices.glsl"
