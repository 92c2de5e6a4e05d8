/* Shared internals of lumis-io: one reader and writer per format, atomic output files. */
#ifndef LUMIS_IO_INTERNAL_H
#define LUMIS_IO_INTERNAL_H

#include "lumis/image.h"
#include "lumis/io.h"
#include "lumis/status.h"

#include <stddef.h>
#include <stdint.h>
#include <signal.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What every reader needs besides its bytes. */
typedef struct lumis__read_ctx {
    const char *name; /* file name for messages */
    uint64_t max_pixels;
    int threads; /* as lumis_read_options.threads */
    const lumis_error_sink *errors;
    lumis_read_info *info; /* never NULL inside the readers */
} lumis__read_ctx;

lumis_status lumis__hdr_read(const unsigned char *data, size_t size, const lumis__read_ctx *ctx,
                             lumis_image **out);
lumis_status lumis__pfm_read(const unsigned char *data, size_t size, const lumis__read_ctx *ctx,
                             lumis_image **out);
/* PNG (8 or 16 bits, grey or colour, alpha ignored), decoded from sRGB to linear. */
lumis_status lumis__png_read(const unsigned char *data, size_t size, const lumis__read_ctx *ctx,
                             lumis_image **out);
/* EXR from memory, or from a file when data is NULL (then ctx->name is the path). */
lumis_status lumis__exr_read(const unsigned char *data, size_t size, const lumis__read_ctx *ctx,
                             lumis_image **out);

/* A regular file of at most max bytes, read whole into *data (NUL-terminated, the caller
 * frees it); what names the kind of file in messages ("luminaire manifest"). */
lumis_status lumis__read_whole(const char *path, size_t max, const char *what,
                               const lumis_error_sink *errors, char **data, size_t *size);

lumis_status lumis__hdr_write(FILE *f, const lumis_image *image);
lumis_status lumis__pfm_write(FILE *f, const lumis_image *image, int big_endian);
lumis_status lumis__png_write(FILE *f, const lumis_image *image, float exposure_ev,
                              lumis_tonemap tonemap);
/* Writes an EXR file to out from its position (half: channels as half, values clamped to
 * 65504) with the options' compression and tiling; messages name display_name.  Errors of
 * the last flush show at the caller's fclose. */
lumis_status lumis__exr_write(FILE *out, const char *display_name, const lumis_image *image,
                              const lumis_write_options *options);

/* An output written under a temporary name in the destination's folder and renamed over
 * the destination only when complete.  A destination that exists and is not a regular
 * file (a character device such as /dev/null or /dev/stdout's terminal, a FIFO, a socket)
 * is written in place instead: renaming over it would replace the device node.  A
 * symbolic link is followed: its target is replaced, the link stays. */
typedef struct lumis__atomic_file {
    char *tmp_path; /* where to write: the temporary file, or (in place) the destination */
    const char *path;
    FILE *f; /* open for writing (binary) */
    int in_place;
    char *target; /* the link's target when path is a symbolic link, else NULL */
} lumis__atomic_file;

lumis_status lumis__atomic_begin(lumis__atomic_file *af, const char *path,
                                 const lumis_error_sink *errors);
/* The end of path's chain of symbolic links, by their text (a dangling link's target is
 * where a write through it goes); *fd a descriptor the chain names (/dev/stdout,
 * /proc/self/fd/N ...) or -1.  malloc'ed; NULL when out of memory. */
char *lumis__follow_links(const char *path, int *fd);
/* Registers / forgets a staging folder of luminaire images (gw x gh images aNNN_bNNN.ext)
 * for lumis_io_remove_partial_outputs. */
void lumis__atomic_track_stage(const char *dir, int gw, int gh, const char *ext);
void lumis__atomic_untrack_stage(const char *dir);
/* Holds back SIGINT, SIGTERM, SIGHUP and SIGQUIT (in this thread) over a few renames that
 * must all happen or none; restore delivers what arrived. */
void lumis__signals_block(sigset_t *was);
void lumis__signals_restore(const sigset_t *was);
/* Registers / forgets a temporary file for lumis_io_remove_partial_outputs. */
void lumis__atomic_track(const char *tmp);
void lumis__atomic_untrack(const char *tmp);
/* Whether outputs are made durable (fsync of the file before its rename, of its folder
 * after): yes unless the environment says LUMIS_NO_FSYNC=1 (scratch space, benchmarks). */
int lumis__durable(void);
/* Closes the stream if open (synced first when durable), renames on success, then syncs
 * the folder; removes the temporary file otherwise. */
lumis_status lumis__atomic_end(lumis__atomic_file *af, lumis_status status,
                               const lumis_error_sink *errors);

/* The rotation of a glTF light node for a light shining from dir (lights_export.c). */
void lumis__light_quaternion(lumis_vec3 dir, double q[4]);

#ifdef __cplusplus
}
#endif
#endif
