#version 460
#extension GL_GOOGLE_include_directive : require
#define EYE_MEASURE 1
#include "eye.glsl"
