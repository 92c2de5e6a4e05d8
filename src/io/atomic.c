/* Crash-safe outputs: write "DIR/.NAME.XXXXXX", then rename(2) it over "DIR/NAME".  A
 * rename within one file system is atomic, so readers see the old file or the new one,
 * never half of either. */
#include "internal.h"

#include "../core/internal.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

lumis_status lumis__atomic_begin(lumis__atomic_file *af, const char *path,
                                 const lumis_error_sink *errors)
{
    af->tmp_path = NULL;
    af->path = path;
    af->f = NULL;
    if (!path || !*path)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "no output path given");
    const char *slash = strrchr(path, '/');
    size_t dir_len = slash ? (size_t)(slash - path) + 1 : 0;
    size_t len = strlen(path);
    af->tmp_path = malloc(len + 16);
    if (!af->tmp_path) return LUMIS_ERR_OUT_OF_MEMORY;
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
        return lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot create a file there: %s", path,
                           strerror(e));
    }
    /* mkstemp makes the file private (0600); an image is an ordinary output. */
    (void)fchmod(fd, 0644);
    af->f = fdopen(fd, "wb");
    if (!af->f) {
        int e = errno;
        close(fd);
        unlink(af->tmp_path);
        free(af->tmp_path);
        af->tmp_path = NULL;
        return lumis__fail(errors, LUMIS_ERR_WRITE, "%s: %s", path, strerror(e));
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
    if (status == LUMIS_OK && rename(af->tmp_path, af->path) != 0)
        status = lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot rename the finished file: %s",
                             af->path, strerror(errno));
    if (status != LUMIS_OK) unlink(af->tmp_path);
    free(af->tmp_path);
    af->tmp_path = NULL;
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
