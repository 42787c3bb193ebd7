/* EXR writer: scanline, ZIP-compressed, 32-bit channels through OpenEXR's
 * core C API.
 *
 * Channels: R, G, B (float) always; "depth" (float), "prim" (uint) and
 * "normal.X/Y/Z" (float) when the image has those planes.  ZIP is lossless
 * and compact, which matters because golden images are committed. */
#include <stdlib.h>
#include <string.h>

#include "rtt/atomic_file.h"
#include "exr_stream.h"
#include "rtt/image.h"

typedef struct exr_channel_source {
    const char *name;
    exr_pixel_type_t type;
    const void *base;      /* first sample of row 0 */
    int32_t pixel_stride;  /* bytes */
    int32_t components;    /* samples per pixel in base's plane */
} exr_channel_source;

/* The image's planes as EXR channels; returns how many. */
static int channel_sources(const rtt_image *image, exr_channel_source out[8])
{
    int n = 0;
    const char *rgb[3] = { "R", "G", "B" };
    for (int k = 0; k < 3; k++)
        out[n++] = (exr_channel_source){ rgb[k], EXR_PIXEL_FLOAT, image->rgb + k, 12, 3 };
    if (image->depth)
        out[n++] = (exr_channel_source){ "depth", EXR_PIXEL_FLOAT, image->depth, 4, 1 };
    if (image->prim)
        out[n++] = (exr_channel_source){ "prim", EXR_PIXEL_UINT, image->prim, 4, 1 };
    if (image->normal) {
        const char *xyz[3] = { "normal.X", "normal.Y", "normal.Z" };
        for (int k = 0; k < 3; k++)
            out[n++] = (exr_channel_source){ xyz[k], EXR_PIXEL_FLOAT, image->normal + k, 12, 3 };
    }
    return n;
}

static const exr_channel_source *find_source(const exr_channel_source *sources, int count, const char *name)
{
    for (int i = 0; i < count; i++)
        if (strcmp(sources[i].name, name) == 0)
            return &sources[i];
    return NULL;
}

static exr_result_t define_part(exr_context_t ctxt, const rtt_image *image, const exr_channel_source *sources,
                                int count)
{
    int part = 0;
    exr_result_t rv = exr_add_part(ctxt, NULL, EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctxt, part, (int32_t)image->width, (int32_t)image->height,
                                                 EXR_COMPRESSION_ZIP);
    for (int i = 0; i < count && rv == EXR_ERR_SUCCESS; i++)
        rv = exr_add_channel(ctxt, part, sources[i].name, sources[i].type, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctxt);
    return rv;
}

/* Points the encoder's channels at the rows of the chunk starting at cinfo. */
static bool bind_channels(exr_encode_pipeline_t *encoder, const rtt_image *image,
                          const exr_channel_source *sources, int count)
{
    for (int c = 0; c < encoder->channel_count; c++) {
        exr_coding_channel_info_t *ch = &encoder->channels[c];
        const exr_channel_source *src = find_source(sources, count, ch->channel_name);
        if (!src)
            return false;
        size_t row_samples = (size_t)image->width * (size_t)src->components;
        ch->user_bytes_per_element = 4;
        ch->user_data_type = (uint16_t)src->type;
        ch->user_pixel_stride = src->pixel_stride;
        ch->user_line_stride = (int32_t)(row_samples * 4);
        ch->encode_from_ptr = (const uint8_t *)src->base + (size_t)encoder->chunk.start_y * row_samples * 4;
    }
    return true;
}

static exr_result_t write_chunks(exr_context_t ctxt, const rtt_image *image, const exr_channel_source *sources,
                                 int count)
{
    int32_t lines = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines);
    if (rv != EXR_ERR_SUCCESS)
        return rv;
    exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool started = false;
    for (int32_t y = 0; y < (int32_t)image->height && rv == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t cinfo;
        rv = exr_write_scanline_chunk_info(ctxt, 0, y, &cinfo);
        if (rv != EXR_ERR_SUCCESS)
            break;
        rv = started ? exr_encoding_update(ctxt, 0, &cinfo, &encoder)
                     : exr_encoding_initialize(ctxt, 0, &cinfo, &encoder);
        if (rv != EXR_ERR_SUCCESS)
            break;
        if (!bind_channels(&encoder, image, sources, count)) {
            rv = EXR_ERR_INVALID_ARGUMENT;
            break;
        }
        if (!started) {
            started = true;
            rv = exr_encoding_choose_default_routines(ctxt, 0, &encoder);
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_run(ctxt, 0, &encoder);
    }
    if (started) {
        exr_result_t destroyed = exr_encoding_destroy(ctxt, &encoder);
        if (rv == EXR_ERR_SUCCESS)
            rv = destroyed;
    }
    return rv;
}

bool rtt_image_write_exr(const rtt_image *image, const char *path, rtt_error *err)
{
    if (!image || !image->rgb || image->width == 0 || image->height == 0 || image->width > INT32_MAX ||
        image->height > INT32_MAX)
        return rtt_error_set(err, "%s: no image to write", path);
    rtt_atomic_file file;
    if (!rtt_atomic_file_open(&file, path, err))
        return false;
    rtt_exr_stream stream = { .fd = fileno(file.stream) };
    exr_context_initializer_t init = rtt_exr_stream_initializer(&stream);
    exr_context_t ctxt = NULL;
    exr_channel_source sources[8];
    int count = channel_sources(image, sources);

    exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv == EXR_ERR_SUCCESS)
        rv = define_part(ctxt, image, sources, count);
    if (rv == EXR_ERR_SUCCESS)
        rv = write_chunks(ctxt, image, sources, count);
    if (ctxt) {
        exr_result_t finished = exr_finish(&ctxt);   /* writes the chunk offset table */
        if (rv == EXR_ERR_SUCCESS)
            rv = finished;
    }
    if (rv != EXR_ERR_SUCCESS) {
        rtt_atomic_file_abort(&file);
        return rtt_error_set(err, "%s: cannot write EXR: %s", path, rtt_exr_stream_message(&stream, rv));
    }
    return rtt_atomic_file_commit(&file, err);
}
