#version 460
#extension GL_GOOGLE_include_directive : require
// warp.classify.levels (after warp_edge_levels): the warp, Halton search included, of the vertices
// warp_vertices listed (warp_vertices.glsl).
#define VG_VERTEX_SEARCH
#include "warp_vertices.glsl"
