/* vergence — scene unit tests: checks, files and an independent reference.
 *
 * The reference functions here (unit_hermite, unit_slerp, unit_mat_*) are
 * written apart from the engine's (double precision, different structure)
 * so a test compares two implementations of the glTF spec, not one with
 * itself. Expected values come from the raw bytes of the sample files. */
#pragma once
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "scene/scene.h"

#include "../test.h"

/* Files */
const char *unit_asset(const char *rel);          /* ../shared/assets/gltf/<rel> */
scene *unit_load(const char *path);               /* NULL (and a failure) when it does not load */
uint8_t *unit_read(const char *path, size_t *size);
float unit_f32(const uint8_t *b, size_t off);
uint16_t unit_u16(const uint8_t *b, size_t off);
uint8_t *unit_base64(const char *text, size_t *size); /* decodes the part after "base64," */
/* Writes a .gltf into a fresh temporary folder; every "@BUF@" in json is
 * replaced by a base64 data URI of data. Returns the path (static storage). */
const char *unit_write_gltf(const char *name, const char *json, const void *data, size_t size);

/* Reference math (column-major double[16]) */
void unit_mat_identity(double m[16]);
void unit_mat_mul(double out[16], const double a[16], const double b[16]);
void unit_mat_trs(double m[16], const double t[3], const double q[4], const double s[3]);
void unit_mat_from_f(double m[16], const float f[16]);
void unit_mat_point(const double m[16], const double p[3], double out[3]);
/* Key interval search, LINEAR, STEP and CUBICSPLINE per the spec. */
void unit_sample(const float *times, int keys, const float *values, int comps, int mode, bool rotation,
                 double t, double *out);
enum { UNIT_LINEAR, UNIT_STEP, UNIT_CUBIC };

/* Tests */
void test_interpolation(void);
void test_cubic_tangents(void);
void test_morph(void);
void test_morph_override(void);
void test_skin(void);
void test_skin_bind_pose(void);
void test_skin_reference(void);
void test_hierarchy(void);
void test_predict(void);
void test_placement_cache(void);
void test_sparse(void);
void test_interleaved(void);
void test_no_indices(void);
void test_topology(void);
void test_normals(void);
void test_colors(void);
void test_magic(void);
void test_saliency(void);
void test_textures(void);
void test_cameras(void);
void test_camera_resolve(void);
void test_camera_infinite(void);
