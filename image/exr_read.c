/* EXR reader: R, G, B and our AOV channels from any single-part scanline
 * EXR that OpenEXR decodes (half, float or uint samples, any compression).
 *
 * Half and float channels are converted to float by OpenEXR's unpacker; the
 * "prim" AOV must be uint.  Tiled, deep, multi-part and subsampled files are
 * refused with one line naming the file. */
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <unistd.h>

#include "exr_stream.h"
#include "rtt/files.h"
#include "rtt/image.h"
#include "rtt/render.h"

typedef struct exr_channel_target {
    const char *name;
    uint8_t *base;       /* first sample of row 0 in our plane (NULL: skip) */
    int32_t pixel_stride;
    int32_t components;
    exr_pixel_type_t type;
} exr_channel_target;

typedef struct exr_layout {
    int32_t width, height, min_y;
    uint32_t aovs;
} exr_layout;

static const exr_attr_chlist_entry_t *find_channel(const exr_attr_chlist_t *channels, const char *name)
{
    for (int i = 0; i < channels->num_channels; i++)
        if (strcmp(channels->entries[i].name.str, name) == 0)
            return &channels->entries[i];
    return NULL;
}

static bool is_real(const exr_attr_chlist_entry_t *ch)
{
    return ch && (ch->pixel_type == EXR_PIXEL_HALF || ch->pixel_type == EXR_PIXEL_FLOAT);
}

/* Checks what we need of the header; fills layout. */
static bool read_layout(exr_const_context_t ctxt, const char *path, exr_layout *layout, rtt_error *err)
{
    int parts = 0;
    exr_storage_t storage;
    exr_attr_box2i_t window;
    const exr_attr_chlist_t *channels = NULL;
    if (exr_get_count(ctxt, &parts) != EXR_ERR_SUCCESS || parts != 1)
        return rtt_error_set(err, "%s: multi-part EXR files are not supported", path);
    if (exr_get_storage(ctxt, 0, &storage) != EXR_ERR_SUCCESS || storage != EXR_STORAGE_SCANLINE)
        return rtt_error_set(err, "%s: only scanline EXR images are supported (not tiled or deep)", path);
    if (exr_get_data_window(ctxt, 0, &window) != EXR_ERR_SUCCESS || exr_get_channels(ctxt, 0, &channels) != 0)
        return rtt_error_set(err, "%s: EXR header lacks a data window or channels", path);
    int64_t width = (int64_t)window.max.x - window.min.x + 1;
    int64_t height = (int64_t)window.max.y - window.min.y + 1;
    if (width < 1 || height < 1 || width > INT32_MAX || height > INT32_MAX)
        return rtt_error_set(err, "%s: EXR data window is empty", path);
    for (int i = 0; i < channels->num_channels; i++)
        if (channels->entries[i].x_sampling != 1 || channels->entries[i].y_sampling != 1)
            return rtt_error_set(err, "%s: subsampled channel \"%s\" is not supported", path,
                                 channels->entries[i].name.str);
    const char *rgb[3] = { "R", "G", "B" };
    for (int k = 0; k < 3; k++)
        if (!is_real(find_channel(channels, rgb[k])))
            return rtt_error_set(err, "%s: EXR has no half or float channel \"%s\"", path, rgb[k]);
    *layout = (exr_layout){ (int32_t)width, (int32_t)height, window.min.y, 0 };
    if (is_real(find_channel(channels, "depth")))
        layout->aovs |= RTT_AOV_DEPTH;
    const exr_attr_chlist_entry_t *prim = find_channel(channels, "prim");
    if (prim && prim->pixel_type == EXR_PIXEL_UINT)
        layout->aovs |= RTT_AOV_PRIM;
    if (is_real(find_channel(channels, "normal.X")) && is_real(find_channel(channels, "normal.Y")) &&
        is_real(find_channel(channels, "normal.Z")))
        layout->aovs |= RTT_AOV_NORMAL;
    return true;
}

/* A file's chunks can expand only so far: deflate tops out near 1032:1, so
 * a header that promises more than MAX_EXPANSION times the file's size in
 * pixels is a lie (or a bomb) and is refused before any allocation. */
#define MAX_EXPANSION 4096u

static bool plausible_size(exr_const_context_t ctxt, const char *path, const exr_layout *layout, int64_t file_size,
                           rtt_error *err)
{
    int32_t lines = 0;
    if (file_size < 0)
        return rtt_error_set(err, "%s: cannot tell the file's size", path);
    if (exr_get_scanlines_per_chunk(ctxt, 0, &lines) != EXR_ERR_SUCCESS || lines < 1)
        return rtt_error_set(err, "%s: EXR has no scanline chunk size", path);
    uint64_t unpacked = 0;
    int64_t end = (int64_t)layout->min_y + layout->height;
    for (int64_t y = layout->min_y; y < end; y += lines) {
        exr_chunk_info_t cinfo;
        exr_result_t rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &cinfo);
        if (rv != EXR_ERR_SUCCESS)
            return rtt_error_set(err, "%s: bad EXR chunk at line %lld: %s", path, (long long)y,
                                 exr_get_default_error_message(rv));
        unpacked += cinfo.unpacked_size;
        if (unpacked / MAX_EXPANSION > (uint64_t)file_size)
            return rtt_error_set(err, "%s: EXR promises %dx%d pixels, more than a %lld-byte file can hold", path,
                                 layout->width, layout->height, (long long)file_size);
    }
    return true;
}

static int channel_targets(rtt_image *image, exr_channel_target out[8])
{
    int n = 0;
    const char *rgb[3] = { "R", "G", "B" };
    for (int k = 0; k < 3; k++)
        out[n++] = (exr_channel_target){ rgb[k], (uint8_t *)(image->rgb + k), 12, 3, EXR_PIXEL_FLOAT };
    if (image->depth)
        out[n++] = (exr_channel_target){ "depth", (uint8_t *)image->depth, 4, 1, EXR_PIXEL_FLOAT };
    if (image->prim)
        out[n++] = (exr_channel_target){ "prim", (uint8_t *)image->prim, 4, 1, EXR_PIXEL_UINT };
    if (image->normal) {
        const char *xyz[3] = { "normal.X", "normal.Y", "normal.Z" };
        for (int k = 0; k < 3; k++)
            out[n++] = (exr_channel_target){ xyz[k], (uint8_t *)(image->normal + k), 12, 3, EXR_PIXEL_FLOAT };
    }
    return n;
}

/* Points each decoder channel we want at its rows; others are skipped. */
static void bind_channels(exr_decode_pipeline_t *decoder, const rtt_image *image, int32_t min_y,
                          const exr_channel_target *targets, int count)
{
    size_t row = (size_t)(decoder->chunk.start_y - min_y);
    for (int c = 0; c < decoder->channel_count; c++) {
        exr_coding_channel_info_t *ch = &decoder->channels[c];
        ch->decode_to_ptr = NULL;
        for (int i = 0; i < count; i++) {
            if (strcmp(targets[i].name, ch->channel_name) != 0)
                continue;
            size_t row_bytes = (size_t)image->width * (size_t)targets[i].components * 4;
            ch->user_bytes_per_element = 4;
            ch->user_data_type = (uint16_t)targets[i].type;
            ch->user_pixel_stride = targets[i].pixel_stride;
            ch->user_line_stride = (int32_t)row_bytes;
            ch->decode_to_ptr = targets[i].base + row * row_bytes;
        }
    }
}

static exr_result_t read_chunks(exr_const_context_t ctxt, rtt_image *image, const exr_layout *layout)
{
    exr_channel_target targets[8];
    int count = channel_targets(image, targets);
    int32_t lines = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines);
    if (rv == EXR_ERR_SUCCESS && lines < 1)
        rv = EXR_ERR_BAD_CHUNK_LEADER;
    exr_decode_pipeline_t decoder = EXR_DECODE_PIPELINE_INITIALIZER;
    bool started = false;
    int64_t end = (int64_t)layout->min_y + layout->height;
    for (int64_t y = layout->min_y; y < end && rv == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t cinfo;
        rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &cinfo);
        if (rv != EXR_ERR_SUCCESS)
            break;
        if (cinfo.start_y < layout->min_y || (int64_t)cinfo.start_y + cinfo.height > end) {
            rv = EXR_ERR_BAD_CHUNK_LEADER;
            break;
        }
        rv = started ? exr_decoding_update(ctxt, 0, &cinfo, &decoder)
                     : exr_decoding_initialize(ctxt, 0, &cinfo, &decoder);
        if (rv != EXR_ERR_SUCCESS)
            break;
        bind_channels(&decoder, image, layout->min_y, targets, count);
        if (!started) {
            started = true;
            rv = exr_decoding_choose_default_routines(ctxt, 0, &decoder);
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_decoding_run(ctxt, 0, &decoder);
    }
    if (started)
        exr_decoding_destroy(ctxt, &decoder);
    return rv;
}

rtt_image *rtt_image_read_exr(const char *path, rtt_error *err)
{
    FILE *file = rtt_file_open_regular(path, err); /* a FIFO or a device is refused, not read */
    if (!file) return NULL;
    rtt_exr_stream stream = { .fd = dup(fileno(file)) };
    fclose(file);
    if (stream.fd < 0) {
        rtt_error_set(err, "%s: cannot open: %s", path, strerror(errno));
        return NULL;
    }
    exr_context_initializer_t init = rtt_exr_stream_initializer(&stream);
    exr_context_t ctxt = NULL;
    rtt_image *image = NULL;
    exr_layout layout = { 0 };
    exr_result_t rv = exr_start_read(&ctxt, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        rtt_error_set(err, "%s: not a readable EXR: %s", path, rtt_exr_stream_message(&stream, rv));
    } else if (read_layout(ctxt, path, &layout, err) &&
               plausible_size(ctxt, path, &layout, lseek(stream.fd, 0, SEEK_END), err)) {
        image = rtt_image_create((uint32_t)layout.width, (uint32_t)layout.height, layout.aovs, err);
        if (image) {
            rv = read_chunks(ctxt, image, &layout);
            if (rv != EXR_ERR_SUCCESS) {
                rtt_error_set(err, "%s: cannot decode EXR: %s", path, rtt_exr_stream_message(&stream, rv));
                rtt_image_free(image);
                image = NULL;
            }
        } else {
            rtt_error_set(err, "%s: EXR of %dx%d pixels is too large", path, layout.width, layout.height);
        }
    }
    if (ctxt)
        exr_finish(&ctxt);
    close(stream.fd);
    return image;
}
