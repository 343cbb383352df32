/* vergence — the perceptual constants the C and GLSL sides share, written
 * in the subset of C17 and GLSL that both accept (float literals with an f
 * suffix), so each has one definition: stereo_perception.c and the CPU
 * reference include it through stereo_perception.h, the compute passes
 * through disparity/mid_shared.h. tests/arch (case constants) rejects a
 * second definition of these values anywhere else. */
#ifndef VG_STEREO_SHARED_H
#define VG_STEREO_SHARED_H

/* Weber fraction of disparity-velocity discrimination (paper Sec. 4.2, after
 * Portfors-Yeomans and Regan 1996, 1997), and its inverse (exact in float:
 * the kernels multiply instead of divide). */
#define STEREO_WEBER_K 0.08f
#define STEREO_INV_WEBER_K 12.5f

/* Arcminutes per radian (the SDK's include/vergence/display.glsl spells it
 * again for hosts; tests/arch compares the two). Double in C. */
#define STEREO_ARCMIN_PER_RAD (60.0 * 180.0 / 3.14159265358979323846)

#endif /* VG_STEREO_SHARED_H */
