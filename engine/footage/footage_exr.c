/* vergence — OpenEXR depth and disparity through OpenEXRCore (footage.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <openexr.h>

#include "core/log.h"
#include "footage.h"

static bool has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    return n > e && !strcasecmp(path + n - e, ext);
}

bool footage_is_exr(const char *path) { return has_ext(path, ".exr"); }

/* OpenEXRCore's messages go to the reader's buffer, not to stderr. */
typedef struct exr_job {
    char why[256];
} exr_job;

static void exr_on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    if (exr_get_user_data(ctxt, &ud) == EXR_ERR_SUCCESS && ud)
        snprintf(((exr_job *)ud)->why, sizeof ((exr_job *)ud)->why, "%s", msg ? msg : exr_get_default_error_message(code));
}

static const char *reason(const exr_job *job, exr_result_t rv)
{
    return job->why[0] ? job->why : exr_get_default_error_message(rv);
}

vg_status footage_exr_read(const char *path, const char *channel, vg_imagef *out)
{
    *out = (vg_imagef){0};
    exr_job job = {{0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_on_error;
    init.user_data = &job;
    init.max_image_width = 1 << 16;
    init.max_image_height = 1 << 16;
    exr_context_t f = NULL;
    exr_result_t rv = exr_start_read(&f, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        vg_error("%s: cannot read OpenEXR: %s", path, reason(&job, rv));
        exr_finish(&f);
        return rv == EXR_ERR_FILE_ACCESS ? VG_ERR_IO : VG_ERR_FORMAT;
    }
    vg_status st = VG_ERR_FORMAT;
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *chans = NULL;
    int32_t lines = 0;
    if (exr_get_storage(f, 0, &storage) != EXR_ERR_SUCCESS || exr_get_data_window(f, 0, &dw) != EXR_ERR_SUCCESS ||
        exr_get_channels(f, 0, &chans) != EXR_ERR_SUCCESS || !chans ||
        exr_get_scanlines_per_chunk(f, 0, &lines) != EXR_ERR_SUCCESS) {
        vg_error("%s: cannot read OpenEXR: %s", path, job.why[0] ? job.why : "its header is incomplete");
        goto done;
    }
    if (storage != EXR_STORAGE_SCANLINE) {
        vg_error("%s: a %s OpenEXR file: vergence reads scan-line files (write it with scan lines)", path,
                 storage == EXR_STORAGE_TILED ? "tiled" : "deep");
        goto done;
    }
    /* The channel: named, else the usual names, else the only one. */
    const char *want = NULL;
    static const char *const usual[] = {"Z", "depth", "disparity", "Y", "R"};
    for (int c = 0; c < chans->num_channels && !want; c++)
        if (channel ? !strcmp(chans->entries[c].name.str, channel) : false)
            want = chans->entries[c].name.str;
    for (size_t u = 0; !channel && !want && u < sizeof usual / sizeof usual[0]; u++)
        for (int c = 0; c < chans->num_channels && !want; c++)
            if (!strcmp(chans->entries[c].name.str, usual[u]))
                want = chans->entries[c].name.str;
    if (!channel && !want && chans->num_channels == 1)
        want = chans->entries[0].name.str;
    if (!want) {
        char names[512] = "";
        for (int c = 0; c < chans->num_channels; c++)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", c ? ", " : "",
                     chans->entries[c].name.str);
        if (channel)
            vg_error("%s: OpenEXR file without the channel %s (its channels: %s)", path, channel, names);
        else
            vg_error("%s: OpenEXR file with several channels and none named Z, depth, disparity, Y or R (its "
                     "channels: %s)", path, names);
        goto done;
    }
    for (int c = 0; c < chans->num_channels; c++)
        if (!strcmp(chans->entries[c].name.str, want) &&
            (chans->entries[c].x_sampling != 1 || chans->entries[c].y_sampling != 1)) {
            vg_error("%s: OpenEXR channel %s is subsampled (%dx%d): vergence reads full-resolution channels", path,
                     want, chans->entries[c].x_sampling, chans->entries[c].y_sampling);
            goto done;
        }
    long w = (long)dw.max.x - dw.min.x + 1, h = (long)dw.max.y - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w * h > VG_MAX_PIXELS || lines <= 0) {
        vg_error("%s: OpenEXR data window %ldx%ld is not an image vergence reads", path, w, h);
        goto done;
    }
    if ((st = vg_imagef_alloc(out, (int)w, (int)h, 1)) != VG_OK)
        goto done;
    for (int32_t y = dw.min.y; y <= dw.max.y; y += lines) {
        exr_chunk_info_t cinfo;
        exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
        rv = exr_read_scanline_chunk_info(f, 0, y, &cinfo);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_decoding_initialize(f, 0, &cinfo, &dec);
        for (int c = 0; rv == EXR_ERR_SUCCESS && c < dec.channel_count; c++) {
            exr_coding_channel_info_t *ch = &dec.channels[c];
            if (strcmp(ch->channel_name, want)) {
                ch->decode_to_ptr = NULL;
                continue;
            }
            ch->decode_to_ptr = (uint8_t *)(out->data + (size_t)(cinfo.start_y - dw.min.y) * (size_t)w);
            ch->user_pixel_stride = 4;
            ch->user_line_stride = (int32_t)(4 * w);
            ch->user_bytes_per_element = 4;
            ch->user_data_type = EXR_PIXEL_FLOAT;
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_decoding_choose_default_routines(f, 0, &dec);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_decoding_run(f, 0, &dec);
        exr_decoding_destroy(f, &dec);
        if (rv != EXR_ERR_SUCCESS) {
            vg_error("%s: cannot decode OpenEXR scan lines from %d: %s", path, (int)y, reason(&job, rv));
            vg_imagef_free(out);
            st = VG_ERR_FORMAT;
            goto done;
        }
    }
    st = VG_OK;
done:
    exr_finish(&f);
    return st;
}

vg_status footage_exr_write(const char *path, const char *channel, const vg_imagef *img)
{
    exr_job job = {{0}};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_on_error;
    init.user_data = &job;
    exr_context_t f = NULL;
    int part = 0;
    int32_t lines = 0;
    /* A temporary file renamed on success, as core/io writes. */
    exr_result_t rv = img->channels == 1 ? exr_start_write(&f, path, EXR_INTERMEDIATE_TEMP_FILE, &init)
                                         : EXR_ERR_INVALID_ARGUMENT;
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_add_part(f, "depth", EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(f, part, img->width, img->height, EXR_COMPRESSION_ZIP);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_add_channel(f, part, channel, EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_set_version(f, part, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(f);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_get_scanlines_per_chunk(f, part, &lines);
    for (int32_t y = 0; rv == EXR_ERR_SUCCESS && y < img->height; y += lines) {
        exr_chunk_info_t cinfo;
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        rv = exr_write_scanline_chunk_info(f, part, y, &cinfo);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_initialize(f, part, &cinfo, &enc);
        if (rv == EXR_ERR_SUCCESS) {
            enc.channels[0].encode_from_ptr = (const uint8_t *)(img->data + (size_t)y * (size_t)img->width);
            enc.channels[0].user_pixel_stride = 4;
            enc.channels[0].user_line_stride = 4 * img->width;
            enc.channels[0].user_bytes_per_element = 4;
            enc.channels[0].user_data_type = EXR_PIXEL_FLOAT;
            rv = exr_encoding_choose_default_routines(f, part, &enc);
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_run(f, part, &enc);
        exr_encoding_destroy(f, &enc);
    }
    exr_result_t done = exr_finish(&f);
    if (rv == EXR_ERR_SUCCESS)
        rv = done;
    if (rv != EXR_ERR_SUCCESS) {
        vg_error("%s: cannot write OpenEXR: %s", path, reason(&job, rv));
        return VG_ERR_IO;
    }
    return VG_OK;
}
