#version 460
#extension GL_GOOGLE_include_directive : require
#define GBUFFER_UNLIT 1
#include "gbuffer.glsl"
