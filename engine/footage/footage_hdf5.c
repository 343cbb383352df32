/* vergence — HDF5 disparity and depth through libhdf5 (footage.h): the
 * Spring benchmark's .dsp5 files hold one float dataset, "disparity".
 * Debian 12 ships HDF5 1.10: its API names, not 1.12's. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <hdf5.h>

#include "core/log.h"
#include "footage.h"

static bool has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n > e && !strcasecmp(path + n - e, ext);
}

bool footage_is_hdf5(const char *path)
{
    return has_ext(path, ".h5") || has_ext(path, ".hdf5") || footage_is_spring(path);
}

bool footage_is_spring(const char *path) { return has_ext(path, ".dsp5"); }

/* The file's datasets at its root (names into list, up to cap). */
typedef struct h5_names {
    char list[8][64];
    int count;
} h5_names;

static herr_t h5_visit(hid_t group, const char *name, const H5L_info_t *info, void *data)
{
    (void)info;
    h5_names *n = data;
    H5O_info_t oi;
    if (H5Oget_info_by_name2(group, name, &oi, H5O_INFO_BASIC, H5P_DEFAULT) >= 0 && oi.type == H5O_TYPE_DATASET) {
        if (n->count < 8)
            snprintf(n->list[n->count], sizeof n->list[0], "%s", name);
        n->count++;
    }
    return 0;
}

vg_status footage_hdf5_read(const char *path, const char *dataset, vg_imagef *out)
{
    *out = (vg_imagef){0};
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL); /* our one error line, not libhdf5's stack print */
    if (H5Fis_hdf5(path) <= 0) {
        FILE *probe = fopen(path, "rb");
        if (!probe) {
            vg_error("%s: cannot open: no such file or no permission", path);
            return VG_ERR_IO;
        }
        fclose(probe);
        vg_error("%s: not an HDF5 file", path);
        return VG_ERR_FORMAT;
    }
    hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT), set = H5I_INVALID_HID, space = H5I_INVALID_HID;
    vg_status st = VG_ERR_FORMAT;
    if (file < 0) {
        vg_error("%s: libhdf5 cannot open it (truncated or corrupt)", path);
        return VG_ERR_FORMAT;
    }
    h5_names names = {0};
    H5Literate(file, H5_INDEX_NAME, H5_ITER_NATIVE, NULL, h5_visit, &names);
    const char *want = dataset;
    static const char *const usual[] = {"disparity", "depth"};
    for (size_t u = 0; !want && u < sizeof usual / sizeof usual[0]; u++)
        for (int k = 0; k < names.count && k < 8 && !want; k++)
            if (!strcmp(names.list[k], usual[u]))
                want = usual[u];
    if (!want && names.count == 1)
        want = names.list[0];
    if (!want || H5Lexists(file, want, H5P_DEFAULT) <= 0) {
        char list[600] = "";
        for (int k = 0; k < names.count && k < 8; k++)
            snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", k ? ", " : "", names.list[k]);
        vg_error("%s: HDF5 file without %s%s (its datasets: %s)", path, dataset ? "the dataset " : "a dataset "
                 "\"disparity\" or \"depth\"", dataset ? dataset : "", names.count ? list : "none");
        goto done;
    }
    set = H5Dopen2(file, want, H5P_DEFAULT);
    space = set >= 0 ? H5Dget_space(set) : H5I_INVALID_HID;
    hsize_t dims[3] = {0, 0, 0};
    int rank = space >= 0 ? H5Sget_simple_extent_ndims(space) : -1;
    if (rank == 2 || rank == 3)
        H5Sget_simple_extent_dims(space, dims, NULL);
    hid_t type = set >= 0 ? H5Dget_type(set) : H5I_INVALID_HID;
    H5T_class_t cls = type >= 0 ? H5Tget_class(type) : H5T_NO_CLASS;
    if (type >= 0)
        H5Tclose(type);
    if (!(rank == 2 || (rank == 3 && dims[2] == 1)) || (cls != H5T_FLOAT && cls != H5T_INTEGER)) {
        vg_error("%s: HDF5 dataset %s is not a 2-D array of numbers (rank %d)", path, want, rank);
        goto done;
    }
    if (dims[0] == 0 || dims[1] == 0 || dims[0] > (1 << 16) || dims[1] > (1 << 16) ||
        dims[0] * dims[1] > (hsize_t)VG_MAX_PIXELS) {
        vg_error("%s: HDF5 dataset %s is %llux%llu: not an image vergence reads", path, want,
                 (unsigned long long)dims[1], (unsigned long long)dims[0]);
        goto done;
    }
    if ((st = vg_imagef_alloc(out, (int)dims[1], (int)dims[0], 1)) != VG_OK)
        goto done;
    if (H5Dread(set, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, out->data) < 0) {
        vg_error("%s: libhdf5 cannot read dataset %s (truncated or corrupt)", path, want);
        vg_imagef_free(out);
        st = VG_ERR_FORMAT;
        goto done;
    }
    st = VG_OK;
done:
    if (space >= 0)
        H5Sclose(space);
    if (set >= 0)
        H5Dclose(set);
    H5Fclose(file);
    return st;
}
