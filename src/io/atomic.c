/* Crash-safe outputs: write "DIR/.NAME.XXXXXX", then rename(2) it over "DIR/NAME".  A
 * rename within one file system is atomic, so readers see the old file or the new one,
 * never half of either. */
/* realpath(3) is XSI */
#define _XOPEN_SOURCE 700
#include "internal.h"

#include "../core/internal.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
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

/* Staging folders of luminaire images (luminaire_file.c): the folder and its grid, so that
 * the handler can name every image it may hold (aNNN_bNNN.EXT) without reading the folder
 * (opendir is not async-signal-safe). */
enum { STAGE_SLOTS = 4 };
static _Atomic int stage_state[STAGE_SLOTS];
static char stage_path[STAGE_SLOTS][TRACK_PATH];
static int stage_grid[STAGE_SLOTS][2];
static char stage_ext[STAGE_SLOTS][8];

void lumis__atomic_track_stage(const char *dir, int gw, int gh, const char *ext)
{
    if (strlen(dir) + 20 >= TRACK_PATH || strlen(ext) >= sizeof stage_ext[0]) return;
    for (int k = 0; k < STAGE_SLOTS; k++) {
        int expected = 0;
        if (atomic_compare_exchange_strong(&stage_state[k], &expected, 1)) {
            memcpy(stage_path[k], dir, strlen(dir) + 1);
            stage_grid[k][0] = gw;
            stage_grid[k][1] = gh;
            memcpy(stage_ext[k], ext, strlen(ext) + 1);
            atomic_store(&stage_state[k], 2);
            return;
        }
    }
}

void lumis__atomic_untrack_stage(const char *dir)
{
    for (int k = 0; k < STAGE_SLOTS; k++)
        if (atomic_load(&stage_state[k]) == 2 && strcmp(stage_path[k], dir) == 0) {
            atomic_store(&stage_state[k], 0);
            return;
        }
}

/* "/a%03d_b%03d." without snprintf (not async-signal-safe). */
static char *put3(char *p, int v)
{
    p[0] = (char)('0' + v / 100 % 10);
    p[1] = (char)('0' + v / 10 % 10);
    p[2] = (char)('0' + v % 10);
    return p + 3;
}

void lumis_io_remove_partial_outputs(void)
{
    for (int k = 0; k < TRACK_SLOTS; k++)
        if (atomic_load(&track_state[k]) == 2) unlink(track_path[k]);
    for (int k = 0; k < STAGE_SLOTS; k++) {
        if (atomic_load(&stage_state[k]) != 2) continue;
        char name[TRACK_PATH + 32];
        const size_t n = strlen(stage_path[k]);
        memcpy(name, stage_path[k], n);
        for (int b = 0; b < stage_grid[k][1] && b < 1000; b++)
            for (int a = 0; a < stage_grid[k][0] && a < 1000; a++) {
                char *p = name + n;
                *p++ = '/';
                *p++ = 'a';
                p = put3(p, a);
                *p++ = '_';
                *p++ = 'b';
                p = put3(p, b);
                *p++ = '.';
                const size_t e = strlen(stage_ext[k]);
                memcpy(p, stage_ext[k], e + 1);
                unlink(name);
            }
        rmdir(stage_path[k]);
    }
}

void lumis__signals_block(sigset_t *was)
{
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGHUP);
    sigaddset(&set, SIGQUIT);
    pthread_sigmask(SIG_BLOCK, &set, was);
}

void lumis__signals_restore(const sigset_t *was)
{
    pthread_sigmask(SIG_SETMASK, was, NULL);
}

/* A descriptor named as a path: /dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N; else
 * -1.  Opening such a path anew would truncate what the descriptor writes to (a log that
 * `>>` appends to), and renaming over it would replace that file. */
static int fd_of_path(const char *p)
{
    if (strcmp(p, "/dev/stdout") == 0) return STDOUT_FILENO;
    if (strcmp(p, "/dev/stderr") == 0) return STDERR_FILENO;
    const char *n = strncmp(p, "/dev/fd/", 8) == 0          ? p + 8
                    : strncmp(p, "/proc/self/fd/", 14) == 0 ? p + 14
                                                            : NULL;
    if (!n || !*n) return -1;
    char *end = NULL;
    const long fd = strtol(n, &end, 10);
    return *end == '\0' && fd >= 0 && fd < INT_MAX ? (int)fd : -1;
}

/* Follows path's chain of symbolic links by their text (a dangling link included: its
 * target is where the output goes), at most 40 links.  Returns the last path of the chain
 * (malloc'ed; NULL when out of memory) and in *fd a descriptor the chain names, or -1. */
char *lumis__follow_links(const char *path, int *fd)
{
    char *cur = malloc(strlen(path) + 1);
    if (!cur) return NULL;
    strcpy(cur, path);
    *fd = fd_of_path(cur);
    for (int hop = 0; hop < 40 && *fd < 0; hop++) {
        struct stat lb;
        if (lstat(cur, &lb) != 0 || !S_ISLNK(lb.st_mode)) break;
        char link[PATH_MAX];
        const ssize_t n = readlink(cur, link, sizeof link - 1);
        if (n <= 0) break;
        link[n] = '\0';
        const char *slash = strrchr(cur, '/');
        const size_t dir = link[0] == '/' || !slash ? 0 : (size_t)(slash - cur) + 1;
        char *next = malloc(dir + (size_t)n + 1);
        if (!next) {
            free(cur);
            return NULL;
        }
        memcpy(next, cur, dir);
        memcpy(next + dir, link, (size_t)n + 1);
        free(cur);
        cur = next;
        *fd = fd_of_path(cur);
    }
    return cur;
}

lumis_status lumis_output_target(const char *path, char *buf, size_t cap)
{
    if (!path || !buf || cap == 0) return LUMIS_ERR_INVALID_ARGUMENT;
    int fd = -1;
    char *end = lumis__follow_links(path, &fd);
    if (!end) return LUMIS_ERR_OUT_OF_MEMORY;
    const char *target = fd >= 0 ? path : end;
    const size_t n = strlen(target);
    const lumis_status st = n < cap ? LUMIS_OK : LUMIS_ERR_INVALID_ARGUMENT;
    if (st == LUMIS_OK) memcpy(buf, target, n + 1);
    free(end);
    return st;
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
    int fd = -1;
    af->target = lumis__follow_links(path, &fd);
    if (!af->target) return LUMIS_ERR_OUT_OF_MEMORY;
    if (fd >= 0) { /* a descriptor by name: written where it stands, not reopened */
        const int dup_fd = dup(fd);
        af->f = dup_fd >= 0 ? fdopen(dup_fd, "wb") : NULL;
        if (!af->f) {
            const int e = errno;
            if (dup_fd >= 0) close(dup_fd);
            free(af->target);
            af->target = NULL;
            return lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot write: %s", path, strerror(e));
        }
        af->tmp_path = af->target; /* owned by tmp_path from here */
        af->target = NULL;
        af->in_place = 1;
        return LUMIS_OK;
    }
    if (strcmp(af->target, path) == 0) { /* not a link */
        free(af->target);
        af->target = NULL;
    }
    struct stat sb;
    const int exists = stat(path, &sb) == 0;
    if (exists && S_ISDIR(sb.st_mode)) {
        free(af->target);
        af->target = NULL;
        return lumis__fail(errors, LUMIS_ERR_WRITE, "%s: is a directory", path);
    }
    if (exists && !S_ISREG(sb.st_mode)) {
        /* A device or a FIFO: written where it is, never renamed over (as root, rename
         * would replace /dev/null with a regular file). */
        free(af->target);
        af->target = NULL;
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
    /* A link (to a file, or dangling): its target is written, beside itself; renaming over
     * the link would turn the link into a file and leave its target unchanged. */
    if (af->target) path = af->target;
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
    /* The name is registered before the file exists, so a signal's handler finds it
     * whichever thread it runs in: blocking signals covers this thread only, and a
     * render's worker threads take them too (a SIGTERM handled by one of them between
     * mkstemp and the registration left the file, 1 run in 4 of the output sweep's timed
     * case on a loaded machine).  The handler may then unlink a name not yet made:
     * harmless. */
    char *suffix = af->tmp_path + len + 2;
    static _Atomic unsigned long long names_made;
    for (unsigned attempt = 0;; attempt++) {
        static const char chars[] =
            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
        struct timespec ts;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        unsigned long long h = ((unsigned long long)getpid() << 32) ^
                               (unsigned long long)ts.tv_nsec ^
                               (atomic_fetch_add(&names_made, 1) * 0x9e3779b97f4a7c15ull);
        for (int c = 0; c < 6; c++) {
            h = lumis__mix64(h);
            suffix[c] = chars[(h >> 40) % 62];
        }
        sigset_t was;
        lumis__signals_block(&was);
        lumis__atomic_track(af->tmp_path);
        lumis__signals_restore(&was);
        fd = open(af->tmp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
        if (fd >= 0) break;
        const int e = errno;
        lumis__atomic_untrack(af->tmp_path);
        errno = e;
        if (e != EEXIST || attempt >= 100) break;
    }
    if (fd < 0) {
        int e = errno;
        free(af->tmp_path);
        af->tmp_path = NULL;
        free(af->target);
        af->target = NULL;
        return lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot create a file there: %s", af->path,
                           strerror(e));
    }
    /* made private (0600), whatever the umask; an image is an ordinary output */
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

int lumis__durable(void)
{
    const char *e = getenv("LUMIS_NO_FSYNC");
    return !(e && *e && strcmp(e, "0") != 0);
}

/* The rename on the disk: the folder that holds dest synced (a rename is a change of the
 * folder; until it is written, a power loss may bring back the old file or none).  A file
 * system that cannot sync a folder (EINVAL: some network and FUSE ones) is let be. */
static lumis_status sync_folder(const char *dest, const char *shown, const lumis_error_sink *errors)
{
    /* no allocation: the file is in place by now, and an out-of-memory failure here would
     * report a finished write as failed */
    char dir[PATH_MAX];
    const char *slash = strrchr(dest, '/');
    const size_t n = !slash ? 1 : slash == dest ? 1 : (size_t)(slash - dest);
    if (n >= sizeof dir) return LUMIS_OK; /* a folder no open(2) would take */
    memcpy(dir, !slash ? "." : slash == dest ? "/" : dest, n);
    dir[n] = '\0';
    lumis_status st = LUMIS_OK;
    const int fd = open(dir, O_RDONLY | O_CLOEXEC);
    if (fd < 0 || (fsync(fd) != 0 && errno != EINVAL && errno != EROFS))
        st = lumis__fail(errors, LUMIS_ERR_WRITE,
                         "%s: written, but its folder %s cannot be synced (a power loss may "
                         "undo it): %s",
                         shown, dir, strerror(errno));
    if (fd >= 0) close(fd);
    return st;
}

lumis_status lumis__atomic_end(lumis__atomic_file *af, lumis_status status,
                               const lumis_error_sink *errors)
{
    if (!af->tmp_path) return status;
    const int durable = lumis__durable();
    if (af->f) {
        int bad = ferror(af->f);
        /* the data on the disk before the name: else a power loss after the rename can
         * leave the new name on an empty file (ext4's delayed allocation, XFS) */
        if (!bad && !af->in_place && durable && status == LUMIS_OK &&
            (fflush(af->f) != 0 || fsync(fileno(af->f)) != 0))
            status = lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot sync the file: %s", af->path,
                                 strerror(errno));
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
        if (status == LUMIS_OK && durable) status = sync_folder(dest, af->path, errors);
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
