/* vergence — glTF accessor decoding with full bounds checks.
 *
 * gltf.cpp locates the bytes of an accessor's bufferView (and checks that
 * the view lies inside its buffer); here everything relative to the view is
 * checked before a single byte is read: element size against byteStride,
 * the last element against the view's end, sparse indices and values against
 * their views and every sparse index against the element count
 * (glTF 2.0 spec 3.6.2 "Accessors"). Reads go through memcpy, so unaligned
 * data is fine; the host is assumed little-endian like glTF itself. */
#include <stdio.h>
#include <string.h>

#include "scene_internal.h"

/* ------------------------------------------------------------------------- */
/* Component types                                                           */
/* ------------------------------------------------------------------------- */

enum {
    CT_BYTE = 5120,
    CT_UBYTE = 5121,
    CT_SHORT = 5122,
    CT_USHORT = 5123,
    CT_UINT = 5125,
    CT_FLOAT = 5126,
};

static size_t component_size(int type)
{
    switch (type) {
    case CT_BYTE: case CT_UBYTE: return 1;
    case CT_SHORT: case CT_USHORT: return 2;
    case CT_UINT: case CT_FLOAT: return 4;
    default: return 0; /* 5124 (INT) and 5130 (DOUBLE) are not glTF 2.0 accessor types */
    }
}

/* One component as float. Normalised integers follow spec 3.11
 * ("Animations", table of normalisation): unsigned c / max, signed
 * max(c / max, -1). */
static float read_component(const uint8_t *p, int type, bool normalized)
{
    switch (type) {
    case CT_BYTE: {
        int8_t v;
        memcpy(&v, p, 1);
        if (!normalized)
            return (float)v;
        float f = (float)v / 127.0f;
        return f < -1.0f ? -1.0f : f;
    }
    case CT_UBYTE: return normalized ? (float)p[0] / 255.0f : (float)p[0];
    case CT_SHORT: {
        int16_t v;
        memcpy(&v, p, 2);
        if (!normalized)
            return (float)v;
        float f = (float)v / 32767.0f;
        return f < -1.0f ? -1.0f : f;
    }
    case CT_USHORT: {
        uint16_t v;
        memcpy(&v, p, 2);
        return normalized ? (float)v / 65535.0f : (float)v;
    }
    case CT_UINT: {
        uint32_t v;
        memcpy(&v, p, 4);
        return normalized ? (float)((double)v / 4294967295.0) : (float)v;
    }
    default: {
        float v;
        memcpy(&v, p, 4);
        return v;
    }
    }
}

static uint32_t read_uint(const uint8_t *p, int type)
{
    if (type == CT_UBYTE)
        return p[0];
    if (type == CT_USHORT) {
        uint16_t v;
        memcpy(&v, p, 2);
        return v;
    }
    uint32_t v;
    memcpy(&v, p, 4);
    return v;
}

/* ------------------------------------------------------------------------- */
/* Range checks                                                              */
/* ------------------------------------------------------------------------- */

/* Does `count` elements of `elem` bytes, `stride` apart, starting at
 * `offset`, fit in `size` bytes? Written so that nothing can overflow. */
static bool fits(size_t offset, size_t stride, size_t elem, size_t count, size_t size)
{
    if (count == 0)
        return offset <= size;
    if (offset > size || elem > size - offset)
        return false;
    size_t room = size - offset - elem;
    return stride == 0 ? true : (count - 1) <= room / stride;
}

/* Checks the layout shared by both decoders; returns the element size. */
static bool check_layout(const scene_accessor_desc *d, size_t *elem_out, size_t *stride_out,
                         char *why, size_t cap)
{
    size_t cs = component_size(d->component_type);
    if (cs == 0) {
        snprintf(why, cap, "componentType %d is not a glTF 2.0 accessor type", d->component_type);
        return false;
    }
    if (d->components < 1 || d->components > 16) {
        snprintf(why, cap, "bad element type (%d components)", d->components);
        return false;
    }
    /* MAT2/MAT3 of 1- and 2-byte components have padded columns; only float
     * matrices (inverse bind matrices) are decoded here. */
    if (d->components > 4 && d->component_type != CT_FLOAT) {
        snprintf(why, cap, "matrix accessors must be float");
        return false;
    }
    size_t elem = cs * (size_t)d->components;
    size_t stride = d->stride ? d->stride : elem;
    if (d->has_view && d->stride && d->stride < elem) {
        snprintf(why, cap, "byteStride %zu is smaller than the element size %zu", d->stride, elem);
        return false;
    }
    if (d->has_view && !fits(d->offset, stride, elem, d->count, d->view_size)) {
        snprintf(why, cap,
                 "byteOffset %zu + %zu elements of %zu bytes (stride %zu) run past the end of "
                 "its bufferView (%zu bytes)",
                 d->offset, d->count, elem, stride, d->view_size);
        return false;
    }
    if (d->sparse_count) {
        size_t is = component_size(d->sparse_index_type);
        if (d->sparse_index_type != CT_UBYTE && d->sparse_index_type != CT_USHORT &&
            d->sparse_index_type != CT_UINT) {
            snprintf(why, cap, "sparse indices componentType %d is not unsigned", d->sparse_index_type);
            return false;
        }
        if (d->sparse_count > d->count) {
            snprintf(why, cap, "sparse count %zu exceeds the accessor count %zu", d->sparse_count, d->count);
            return false;
        }
        if (!fits(0, is, is, d->sparse_count, d->sparse_indices_size)) {
            snprintf(why, cap, "%zu sparse indices run past the end of their bufferView", d->sparse_count);
            return false;
        }
        if (!fits(0, elem, elem, d->sparse_count, d->sparse_values_size)) {
            snprintf(why, cap, "%zu sparse values run past the end of their bufferView", d->sparse_count);
            return false;
        }
        for (size_t i = 0; i < d->sparse_count; i++) {
            uint32_t k = read_uint(d->sparse_indices + i * is, d->sparse_index_type);
            if (k >= d->count) {
                snprintf(why, cap, "sparse index %u is not below the count %zu", k, d->count);
                return false;
            }
        }
    }
    *elem_out = elem;
    *stride_out = stride;
    return true;
}

/* ------------------------------------------------------------------------- */
/* Decoders                                                                  */
/* ------------------------------------------------------------------------- */

bool scene_accessor_check(const scene_accessor_desc *d, char *why, size_t cap)
{
    size_t elem, stride;
    return check_layout(d, &elem, &stride, why, cap);
}

/* One element's components at p to out's element k: floats (normalised as
 * the accessor says) or unsigned integers. */
static void put(const scene_accessor_desc *d, bool floats, const uint8_t *p, size_t cs, void *out, size_t k)
{
    size_t n = (size_t)d->components;
    for (size_t c = 0; c < n; c++) {
        if (floats)
            ((float *)out)[k * n + c] = read_component(p + c * cs, d->component_type, d->normalized);
        else
            ((uint32_t *)out)[k * n + c] = read_uint(p + c * cs, d->component_type);
    }
}

/* Decodes every element (zeros without a bufferView), then the sparse
 * values, which replace whole elements (spec 3.6.2.3). */
static bool decode(const scene_accessor_desc *d, bool floats, void *out, char *why, size_t cap)
{
    size_t elem, stride;
    if (!check_layout(d, &elem, &stride, why, cap))
        return false;
    size_t n = (size_t)d->components, cs = elem / n;
    if (!d->has_view)
        memset(out, 0, d->count * n * (floats ? sizeof(float) : sizeof(uint32_t)));
    else
        for (size_t i = 0; i < d->count; i++)
            put(d, floats, d->view + d->offset + i * stride, cs, out, i);
    size_t is = component_size(d->sparse_index_type);
    for (size_t i = 0; i < d->sparse_count; i++)
        put(d, floats, d->sparse_values + i * elem, cs, out,
            read_uint(d->sparse_indices + i * is, d->sparse_index_type));
    return true;
}

bool scene_accessor_floats(const scene_accessor_desc *d, float *out, char *why, size_t cap)
{
    return decode(d, true, out, why, cap);
}

bool scene_accessor_uints(const scene_accessor_desc *d, uint32_t *out, char *why, size_t cap)
{
    if (d->component_type != CT_UBYTE && d->component_type != CT_USHORT &&
        d->component_type != CT_UINT) {
        snprintf(why, cap, "componentType %d is not an unsigned integer type", d->component_type);
        return false;
    }
    return decode(d, false, out, why, cap);
}
