/* Format detection, whole-file reading, and the atomic write path of every writer. */
#include "lumis/io.h"

#include "internal.h"

#include "../core/internal.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *const compression_names[] = {"zip",   "none", "rle",  "zips", "piz",
                                                "pxr24", "b44",  "b44a", "dwaa", "dwab"};

LUMIS__ENUM_NAMES(lumis_exr_compression, LUMIS_EXR_COMPRESSION_COUNT, compression_names,
                  lumis_exr_compression_name, lumis_exr_compression_from_name);

static const char *const format_names[] = {"auto", "exr", "hdr", "pfm", "png"};

LUMIS__ENUM_NAME(lumis_file_format, LUMIS_FORMAT_COUNT, format_names, lumis_format_name);

lumis_file_format lumis_format_from_path(const char *path)
{
    const char *dot = path ? strrchr(path, '.') : NULL;
    if (!dot || strchr(dot, '/')) return LUMIS_FORMAT_AUTO;
    dot++;
    if (strcasecmp(dot, "exr") == 0) return LUMIS_FORMAT_EXR;
    if (strcasecmp(dot, "hdr") == 0 || strcasecmp(dot, "pic") == 0) return LUMIS_FORMAT_HDR;
    if (strcasecmp(dot, "pfm") == 0) return LUMIS_FORMAT_PFM;
    if (strcasecmp(dot, "png") == 0) return LUMIS_FORMAT_PNG;
    return LUMIS_FORMAT_AUTO;
}

lumis_file_format lumis_format_from_magic(const void *data, size_t size)
{
    const unsigned char *b = data;
    if (size >= 4 && b[0] == 0x76 && b[1] == 0x2f && b[2] == 0x31 && b[3] == 0x01)
        return LUMIS_FORMAT_EXR;
    if (size >= 2 && b[0] == '#' && b[1] == '?') return LUMIS_FORMAT_HDR;
    if (size >= 3 && b[0] == 'P' && (b[1] == 'F' || b[1] == 'f') &&
        (b[2] == '\n' || b[2] == '\r' || b[2] == ' ' || b[2] == '\t'))
        return LUMIS_FORMAT_PFM;
    if (size >= 8 && memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0) return LUMIS_FORMAT_PNG;
    return LUMIS_FORMAT_AUTO;
}

static lumis_status finish_read(lumis_status st, lumis_image **out, lumis_read_info *info)
{
    if (st == LUMIS_OK) {
        size_t n = (size_t)(*out)->width * (size_t)(*out)->height * 3;
        lumis_sanitize_floats((*out)->pixels, n, &info->replaced);
    } else {
        lumis_image_destroy(*out);
        *out = NULL;
    }
    return st;
}

static lumis_status read_dispatch(const unsigned char *data, size_t size, lumis_file_format format,
                                  const lumis__read_ctx *ctx, lumis_image **out)
{
    if (size == 0)
        return lumis__fail(ctx->errors, LUMIS_ERR_EMPTY_FILE, "%s: file is empty", ctx->name);
    lumis_file_format detected = lumis_format_from_magic(data, size);
    if (format == LUMIS_FORMAT_AUTO) format = detected;
    ctx->info->format = format;
    switch (format) {
    case LUMIS_FORMAT_EXR:
        return lumis__exr_read(data, size, ctx, out);
    case LUMIS_FORMAT_HDR:
        return lumis__hdr_read(data, size, ctx, out);
    case LUMIS_FORMAT_PFM:
        return lumis__pfm_read(data, size, ctx, out);
    case LUMIS_FORMAT_PNG:
        return lumis__png_read(data, size, ctx, out);
    default:
        return lumis__fail(ctx->errors, LUMIS_ERR_UNKNOWN_FORMAT,
                           "%s: not an EXR, Radiance HDR, PFM or PNG image (unrecognised content)",
                           ctx->name);
    }
}

/* The reading context of one call: defaults for NULL options and info, info cleared. */
static lumis__read_ctx begin_read(const char *name, const lumis_read_options *options,
                                  lumis_read_info *info)
{
    static const lumis_read_options zero_options;
    if (!options) options = &zero_options;
    memset(info, 0, sizeof *info);
    lumis__read_ctx ctx = {name, options->max_pixels, options->threads, &options->errors, info};
    return ctx;
}

lumis_status lumis_image_read_memory(const void *data, size_t size, lumis_file_format format,
                                     const char *name, const lumis_read_options *options,
                                     lumis_image **out, lumis_read_info *info)
{
    lumis_read_info local_info;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    lumis__read_ctx ctx = begin_read(name ? name : "<memory>", options, info ? info : &local_info);
    if (!data && size) return lumis__fail(ctx.errors, LUMIS_ERR_INVALID_ARGUMENT, "no data given");
    return finish_read(read_dispatch(data, size, format, &ctx, out), out, ctx.info);
}

lumis_status lumis__read_whole(const char *path, size_t max, const char *what,
                               const lumis_error_sink *errors, char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    if (!path) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "no %s path given", what);
    /* opened without blocking: a FIFO or a device would otherwise wait for a writer
     * before fstat could refuse it */
    const int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd < 0) return lumis__fail(errors, LUMIS_ERR_OPEN, "%s: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        close(fd);
        return lumis__fail(errors, LUMIS_ERR_OPEN, "%s: not a regular file", path);
    }
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        close(fd);
        return lumis__fail(errors, LUMIS_ERR_OPEN, "%s: %s", path, strerror(errno));
    }
    if ((unsigned long long)sb.st_size > max) {
        fclose(f);
        return lumis__fail(errors, LUMIS_ERR_TOO_LARGE, "%s: %lld bytes: too large for a %s", path,
                           (long long)sb.st_size, what);
    }
    const size_t n = (size_t)sb.st_size;
    char *text = malloc(n + 1);
    if (!text) {
        fclose(f);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    const size_t got = fread(text, 1, n, f);
    const int bad = ferror(f);
    fclose(f);
    if (bad || got != n) {
        free(text);
        return lumis__fail(errors, LUMIS_ERR_READ, "%s: read error", path);
    }
    text[n] = '\0';
    *data = text;
    *size = n;
    return LUMIS_OK;
}

lumis_status lumis_image_read(const char *path, const lumis_read_options *options,
                              lumis_image **out, lumis_read_info *info)
{
    lumis_read_info local_info;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    lumis__read_ctx ctx = begin_read(path, options, info ? info : &local_info);
    info = ctx.info;
    const lumis_error_sink *err = ctx.errors;
    if (!path) return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT, "no input path given");

    FILE *f = fopen(path, "rb");
    if (!f) return lumis__fail(err, LUMIS_ERR_OPEN, "%s: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fileno(f), &sb) != 0 || !S_ISREG(sb.st_mode)) {
        fclose(f);
        return lumis__fail(err, LUMIS_ERR_OPEN, "%s: not a regular file", path);
    }
    unsigned char magic[8];
    size_t got = fread(magic, 1, sizeof magic, f);
    lumis_status st;
    if (got >= 4 && lumis_format_from_magic(magic, got) == LUMIS_FORMAT_EXR) {
        /* OpenEXR streams the file itself (and can use its own threads to decode). */
        fclose(f);
        info->format = LUMIS_FORMAT_EXR;
        st = lumis__exr_read(NULL, (size_t)sb.st_size, &ctx, out);
        return finish_read(st, out, info);
    }
    size_t size = (size_t)sb.st_size;
    unsigned char *data = malloc(size ? size : 1);
    if (!data) {
        fclose(f);
        return lumis__fail(err, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory reading %zu bytes",
                           path, size);
    }
    memcpy(data, magic, got < size ? got : size);
    size_t rest = size > got ? fread(data + got, 1, size - got, f) : 0;
    int bad = ferror(f);
    fclose(f);
    if (bad || got + rest < size) {
        free(data);
        return lumis__fail(err, LUMIS_ERR_READ, "%s: read error", path);
    }
    st = read_dispatch(data, size, LUMIS_FORMAT_AUTO, &ctx, out);
    free(data);
    return finish_read(st, out, info);
}

lumis_status lumis_image_write(const char *path, const lumis_image *image,
                               const lumis_write_options *options)
{
    static const lumis_write_options zero_options;
    if (!options) options = &zero_options;
    const lumis_error_sink *err = &options->errors;
    if (!path || !image || !image->pixels)
        return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT, "write: no path or image given");
    if (lumis_image_check_size(image->width, image->height, UINT64_MAX) != LUMIS_OK)
        return lumis__fail(err, LUMIS_ERR_BAD_DIMENSIONS, "%s: image has bad dimensions", path);
    lumis_file_format format =
        options->format != LUMIS_FORMAT_AUTO ? options->format : lumis_format_from_path(path);
    if (format <= LUMIS_FORMAT_AUTO || format >= LUMIS_FORMAT_COUNT)
        return lumis__fail(err, LUMIS_ERR_UNKNOWN_FORMAT,
                           "%s: unknown output format (use .exr, .hdr, .pfm or .png)", path);
    if (!isfinite(options->exposure_ev) || (unsigned)options->tonemap >= LUMIS_TONEMAP_COUNT ||
        (unsigned)options->exr_compression >= LUMIS_EXR_COMPRESSION_COUNT ||
        options->exr_tile_size < 0)
        return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT, "%s: bad exposure or tone map", path);

    lumis__atomic_file af;
    lumis_status st = lumis__atomic_begin(&af, path, err);
    if (st != LUMIS_OK) return st;
    switch (format) {
    case LUMIS_FORMAT_EXR:
        st = lumis__exr_write(af.f, path, image, options);
        break;
    case LUMIS_FORMAT_HDR:
        st = lumis__hdr_write(af.f, image);
        break;
    case LUMIS_FORMAT_PFM:
        st = lumis__pfm_write(af.f, image, options->pfm_big_endian);
        break;
    default:
        st = lumis__png_write(af.f, image, options->exposure_ev, options->tonemap);
        break;
    }
    if (st != LUMIS_OK && st != LUMIS_ERR_WRITE && format != LUMIS_FORMAT_EXR)
        lumis__fail(err, st, "%s: %s", path, lumis_status_string(st));
    else if (st == LUMIS_ERR_WRITE && format != LUMIS_FORMAT_EXR)
        lumis__fail(err, st, "%s: write failed: %s", path, strerror(errno));
    return lumis__atomic_end(&af, st, err);
}
