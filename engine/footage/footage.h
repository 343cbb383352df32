/* vergence — the files real footage's depth and disparity come in, read
 * through their own libraries (issue 43): OpenEXR (a renderer's depth or
 * disparity pass; Debian's libopenexr, its C API OpenEXRCore) and HDF5 (the
 * Spring benchmark's disparity; Debian's libhdf5). Each reader gives one
 * float channel and logs one error line naming the file and the problem.
 * `vergence optimize` reads --g and --depth through them by extension. */
#pragma once
#include <stdbool.h>

#include "core/io.h"

/* .exr */
bool footage_is_exr(const char *path);
/* .h5, .hdf5 and Spring's .dsp5 */
bool footage_is_hdf5(const char *path);
/* Spring's disparity files (.dsp5): pixels, x_left - x_right, NaN unknown. */
bool footage_is_spring(const char *path);

/* One channel of a scan-line OpenEXR file's first part (its data window),
 * as floats (half and uint channels converted): `channel` by name, or NULL
 * for the first of Z, depth, disparity, Y, R, or the file's only channel.
 * Non-finite values are kept (the caller decides what they mean). */
vg_status footage_exr_read(const char *path, const char *channel, vg_imagef *out);

/* One float channel named `channel` (ZIP-compressed scan lines), written to
 * a temporary file and renamed into place. */
vg_status footage_exr_write(const char *path, const char *channel, const vg_imagef *img);

/* A two-dimensional numeric dataset of an HDF5 file as floats: `dataset` by
 * name, or NULL for "disparity" (Spring's), "depth", or the file's only
 * dataset. */
vg_status footage_hdf5_read(const char *path, const char *dataset, vg_imagef *out);
