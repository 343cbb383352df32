/* vergence — the one prelude of every header that C and GLSL both compile
 * (vergence/warp_shared.h, vergence/curve.h; in the engine shaders/shared.h
 * and disparity/mid_shared.h). Such a header is written in the subset of
 * C17 and GLSL 4.50 that both accept:
 *   - structs declared with VGX_STRUCT(name) { ... }; (both then name the
 *     type bare), of 4-byte scalars, VGX_VEC2 / VGX_VEC4 / VGX_MAT4 and
 *     arrays of them, laid out alike by C and by scalar blocks (no vec3, no
 *     bool; std430 agrees too where every vector sits at a multiple of its
 *     size);
 *   - float literals with an f suffix, uint literals with a u suffix
 *     (unsuffixed literals are double in C, float in GLSL);
 *   - functions marked VGX_FN that take and return values (no pointers, no
 *     out parameters); casts through VGX_INT(), VGX_UINT(), VGX_FLOAT();
 *   - float maths through vgx_abs .. vgx_mix: C's float functions, GLSL's
 *     built-ins (vgx_mix is GLSL's mix as the GLSL specification defines it).
 * GLSL includes these headers with GL_GOOGLE_include_directive. */
#ifndef VERGENCE_LANG_H
#define VERGENCE_LANG_H

#ifdef GL_core_profile
#define VGX_FN
#define VGX_STRUCT(name) struct name
#define VGX_VEC2 vec2
#define VGX_VEC4 vec4
#define VGX_MAT4 mat4
#define VGX_INT(x) int(x)
#define VGX_UINT(x) uint(x)
#define VGX_FLOAT(x) float(x)
#define vgx_abs abs
#define vgx_floor floor
#define vgx_sqrt sqrt
#define vgx_pow pow
#define vgx_log log
#define vgx_exp exp
#define vgx_mix mix
#else
#include <math.h>
#include <stdint.h>
typedef unsigned int uint;
#define VGX_FN static inline
#define VGX_STRUCT(name) typedef struct name name; struct name
typedef struct vgx_vec2 { float v[2]; } vgx_vec2;
typedef struct vgx_vec4 { float v[4]; } vgx_vec4;
typedef struct vgx_mat4 { float m[16]; } vgx_mat4; /* column-major, as GLSL */
#define VGX_VEC2 vgx_vec2
#define VGX_VEC4 vgx_vec4
#define VGX_MAT4 vgx_mat4
#define VGX_INT(x) ((int)(x))
#define VGX_UINT(x) ((uint)(x))
#define VGX_FLOAT(x) ((float)(x))
#define vgx_abs fabsf
#define vgx_floor floorf
#define vgx_sqrt sqrtf
#define vgx_pow powf
#define vgx_log logf
#define vgx_exp expf
static inline float vgx_mix(float x, float y, float a) { return x * (1.0f - a) + y * a; }
#endif

#endif /* VERGENCE_LANG_H */
