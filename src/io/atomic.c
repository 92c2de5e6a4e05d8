/* Crash-safe outputs: write "DIR/.NAME.XXXXXX", then rename(2) it over "DIR/NAME".  A
 * rename within one file system is atomic, so readers see the old file or the new one,
 * never half of either. */
/* realpath(3) is XSI */
#define _XOPEN_SOURCE 700
#include "internal.h"

#include "../core/internal.h"

#include <errno.h>
#include <limits.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The temporary files being written, so that an interrupted program can remove them
 * (lumis_io_remove_partial_outputs, from a signal handler): fixed slots, each a state
 * (0 free, 1 being filled, 2 a path) and a copy of the path, so the handler reads no
 * memory that another thread may free. */
enum { TRACK_SLOTS = 64, TRACK_PATH = 4096 };
static _Atomic int track_state[TRACK_SLOTS];
static char track_path[TRACK_SLOTS][TRACK_PATH];

void lumis__atomic_track(const char *tmp)
{
    if (strlen(tmp) >= TRACK_PATH) return; /* not removable on a signal; still correct */
    for (int k = 0; k < TRACK_SLOTS; k++) {
        int expected = 0;
        if (atomic_compare_exchange_strong(&track_state[k], &expected, 1)) {
            memcpy(track_path[k], tmp, strlen(tmp) + 1);
            atomic_store(&track_state[k], 2);
            return;
        }
    }
}

void lumis__atomic_untrack(const char *tmp)
{
    for (int k = 0; k < TRACK_SLOTS; k++)
        if (atomic_load(&track_state[k]) == 2 && strcmp(track_path[k], tmp) == 0) {
            atomic_store(&track_state[k], 0);
            return;
        }
}

void lumis_io_remove_partial_outputs(void)
{
    for (int k = 0; k < TRACK_SLOTS; k++)
        if (atomic_load(&track_state[k]) == 2) unlink(track_path[k]);
}

lumis_status lumis__atomic_begin(lumis__atomic_file *af, const char *path,
                                 const lumis_error_sink *errors)
{
    af->tmp_path = NULL;
    af->path = path;
    af->f = NULL;
    af->in_place = 0;
    af->target = NULL;
    if (!path || !*path)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "no output path given");
    struct stat sb;
    const int exists = stat(path, &sb) == 0;
    if (exists && S_ISDIR(sb.st_mode))
        return lumis__fail(errors, LUMIS_ERR_WRITE, "%s: is a directory", path);
    if (exists && !S_ISREG(sb.st_mode)) {
        /* A device or a FIFO: written where it is, never renamed over (as root, rename
         * would replace /dev/null with a regular file). */
        af->tmp_path = malloc(strlen(path) + 1);
        if (!af->tmp_path) return LUMIS_ERR_OUT_OF_MEMORY;
        strcpy(af->tmp_path, path);
        af->in_place = 1;
        af->f = fopen(path, "wb");
        if (!af->f) {
            const int e = errno;
            free(af->tmp_path);
            af->tmp_path = NULL;
            return lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot write: %s", path, strerror(e));
        }
        return LUMIS_OK;
    }
    struct stat lb;
    if (lstat(path, &lb) == 0 && S_ISLNK(lb.st_mode)) {
        /* A link to a regular file: the file is replaced beside itself; renaming over the
         * link would turn the link into a file and leave its target unchanged. */
        af->target = realpath(path, NULL);
        if (af->target) path = af->target;
    }
    const char *slash = strrchr(path, '/');
    size_t dir_len = slash ? (size_t)(slash - path) + 1 : 0;
    size_t len = strlen(path);
    af->tmp_path = malloc(len + 16);
    if (!af->tmp_path) {
        free(af->target);
        af->target = NULL;
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    /* Hidden, beside the destination, so the final rename never crosses file systems. */
    memcpy(af->tmp_path, path, dir_len);
    af->tmp_path[dir_len] = '.';
    memcpy(af->tmp_path + dir_len + 1, path + dir_len, len - dir_len);
    memcpy(af->tmp_path + len + 1, ".XXXXXX", 8);
    int fd = mkstemp(af->tmp_path);
    if (fd < 0) {
        int e = errno;
        free(af->tmp_path);
        af->tmp_path = NULL;
        free(af->target);
        af->target = NULL;
        return lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot create a file there: %s", af->path,
                           strerror(e));
    }
    lumis__atomic_track(af->tmp_path);
    /* mkstemp makes the file private (0600); an image is an ordinary output. */
    (void)fchmod(fd, 0644);
    af->f = fdopen(fd, "wb");
    if (!af->f) {
        int e = errno;
        close(fd);
        unlink(af->tmp_path);
        lumis__atomic_untrack(af->tmp_path);
        free(af->tmp_path);
        af->tmp_path = NULL;
        free(af->target);
        af->target = NULL;
        return lumis__fail(errors, LUMIS_ERR_WRITE, "%s: %s", af->path, strerror(e));
    }
    return LUMIS_OK;
}

lumis_status lumis__atomic_end(lumis__atomic_file *af, lumis_status status,
                               const lumis_error_sink *errors)
{
    if (!af->tmp_path) return status;
    if (af->f) {
        int bad = ferror(af->f);
        if (fclose(af->f) != 0 || bad) {
            if (status == LUMIS_OK)
                status = lumis__fail(errors, LUMIS_ERR_WRITE, "%s: write failed: %s", af->path,
                                     strerror(errno));
        }
        af->f = NULL;
    }
    if (!af->in_place) {
        const char *dest = af->target ? af->target : af->path;
        if (status == LUMIS_OK && rename(af->tmp_path, dest) != 0)
            status = lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot rename the finished file: %s",
                                 af->path, strerror(errno));
        if (status != LUMIS_OK) unlink(af->tmp_path);
        lumis__atomic_untrack(af->tmp_path);
    }
    free(af->tmp_path);
    af->tmp_path = NULL;
    free(af->target);
    af->target = NULL;
    return status;
}

lumis_status lumis_write_text(const char *path, const char *text, size_t len,
                              const lumis_error_sink *errors)
{
    if (!text && len) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "no text to write");
    lumis__atomic_file af;
    lumis_status st = lumis__atomic_begin(&af, path, errors);
    if (st != LUMIS_OK) return st;
    if (len && fwrite(text, 1, len, af.f) != len)
        st = lumis__fail(errors, LUMIS_ERR_WRITE, "%s: write failed: %s", path, strerror(errno));
    return lumis__atomic_end(&af, st, errors);
}
