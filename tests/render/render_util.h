/* vergence — helpers of the render tests: a GPU + scene + frame bundle, the
 * camera maths in double precision, an Embree 3 copy of an evaluated scene
 * (the CPU ground truth, DESIGN.md "Reference truths"), and order
 * statistics for the reports. */
#pragma once
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <embree3/rtcore.h>

#include "frame/frame.h"

/* ------------------------------------------------------------------------- */
/* A rendering context                                                       */
/* ------------------------------------------------------------------------- */

typedef struct rt_ctx {
    gpu *gpu;
    scene *scene;
    frame *frame;
    uint32_t width, height;
} rt_ctx;

/* GPU (validation from VERGENCE_VALIDATE), scene, frame with readback.
 * Returns 0, or 1 after printing why not. */
int rt_open(rt_ctx *c, const char *scene_path, uint32_t width, uint32_t height);
/* Adds a second frame object on the same GPU and scene. */
int rt_open_frame(const rt_ctx *c, frame **out);
/* Destroys everything; returns the validation messages of the whole process
 * (including those raised during destruction) and prints them when > 0. */
int rt_close(rt_ctx *c);

/* ------------------------------------------------------------------------- */
/* Camera maths (column-major, Vulkan clip space: y down, depth 0..1)        */
/* ------------------------------------------------------------------------- */

void rt_mat4_to_double(const float m[16], double out[16]);
bool rt_mat4_invert(const double m[16], double out[16]);
void rt_mat4_mul_point(const double m[16], const double p[3], double out[4]); /* w = 1 in */

/* The ray through pixel (px, py) (pixel centres at +0.5): from the near
 * plane point `org` to the far plane point org + dir (parameter 0..1). */
typedef struct rt_ray {
    double org[3], dir[3];
} rt_ray;
void rt_pixel_ray(const double inv_view_proj[16], uint32_t width, uint32_t height, double px,
                  double py, rt_ray *r);

/* Pixel position of a world point (pixel = (ndc * 0.5 + 0.5) * size);
 * false behind the camera. */
bool rt_project(const float view_proj[16], const double p[3], uint32_t width, uint32_t height,
                double out[2]);

/* Linear depth of a world point: distance along the camera's forward axis. */
double rt_linear_depth(const vg_camera *cam, const double p[3]);

/* ------------------------------------------------------------------------- */
/* Embree ground truth                                                       */
/* ------------------------------------------------------------------------- */

/* One Embree geometry per scene instance (geomID = instance index), with the
 * world-space vertices of an evaluated state. */
typedef struct rt_embree {
    RTCDevice device;
    RTCScene scene;
} rt_embree;

int rt_embree_build(rt_embree *e, const scene *s, const scene_state *st);
void rt_embree_destroy(rt_embree *e);
/* Closest hit on the ray segment [0, 1]: the instance index, or -1 on a miss. */
int rt_embree_cast(const rt_embree *e, const rt_ray *r, double *t);

/* ------------------------------------------------------------------------- */
/* Statistics                                                                */
/* ------------------------------------------------------------------------- */

typedef struct rt_stats {
    size_t n;
    double median, p95, p99, max, mean;
} rt_stats;

/* Sorts v in place. */
rt_stats rt_stats_of(double *v, size_t n);
