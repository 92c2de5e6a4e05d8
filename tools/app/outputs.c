/* Checks of a command's output paths, made before any work: the format an extension names,
 * a directory that exists and can be written, and no output that is also an input (or
 * another output).  A mistake here is a usage error (exit 2) that names the paths, found
 * in milliseconds rather than after a render. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "errors.h"
#include "files.h"
#include "lights.h"
#include "pipeline.h"

#include <cJSON.h>

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *kind_formats(tool_output_kind kind)
{
    switch (kind) {
    case TOOL_OUT_IMAGE:
        return ".exr, .hdr, .pfm or .png";
    case TOOL_OUT_LINEAR:
        return ".exr, .hdr or .pfm";
    case TOOL_OUT_PNG:
        return ".png";
    case TOOL_OUT_GLTF:
        return ".gltf for text, .glb for binary";
    default:
        return "";
    }
}

static int kind_accepts(tool_output_kind kind, const char *path)
{
    lumis_file_format f = lumis_format_from_path(path);
    switch (kind) {
    case TOOL_OUT_IMAGE:
        return f != LUMIS_FORMAT_AUTO;
    case TOOL_OUT_LINEAR:
        return f != LUMIS_FORMAT_AUTO && f != LUMIS_FORMAT_PNG;
    case TOOL_OUT_PNG:
        return f == LUMIS_FORMAT_PNG;
    case TOOL_OUT_GLTF: {
        const char *dot = strrchr(path, '.');
        return dot && !strchr(dot, '/') &&
               (strcasecmp(dot, ".gltf") == 0 || strcasecmp(dot, ".glb") == 0);
    }
    default:
        return 1;
    }
}

/* The directory part of path ("." when it has none), in buf. */
static void dir_of(const char *path, char *buf, size_t cap)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(buf, cap, ".");
    else if (slash == path)
        snprintf(buf, cap, "/");
    else
        snprintf(buf, cap, "%.*s", (int)(slash - path), path);
}

/* path with its directory resolved (symbolic links, "..", "."), or a copy of path when the
 * directory does not exist. */
static void canonical(const char *path, char *buf, size_t cap)
{
    char dir[PATH_MAX], real[PATH_MAX];
    dir_of(path, dir, sizeof dir);
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    if (realpath(dir, real))
        snprintf(buf, cap, "%s/%s", strcmp(real, "/") == 0 ? "" : real, base);
    else
        snprintf(buf, cap, "%s", path);
}

int tool_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    int ea = stat(a, &sa) == 0, eb = stat(b, &sb) == 0;
    /* two outputs to /dev/null (a character device) are not one file's two versions */
    if (ea && eb) return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino && !S_ISCHR(sa.st_mode);
    if (ea != eb) return 0; /* one exists, the other does not: not yet the same file */
    /* where each write lands (a dangling link's target), as the library writes it */
    char fa[PATH_MAX + 256], fb[PATH_MAX + 256], ca[PATH_MAX + 512], cb[PATH_MAX + 512];
    if (lumis_output_target(a, fa, sizeof fa) != LUMIS_OK) snprintf(fa, sizeof fa, "%s", a);
    if (lumis_output_target(b, fb, sizeof fb) != LUMIS_OK) snprintf(fb, sizeof fb, "%s", b);
    canonical(fa, ca, sizeof ca);
    canonical(fb, cb, sizeof cb);
    return strcmp(ca, cb) == 0;
}

void tool_files_input(tool_files *f, const char *what, const char *path)
{
    if (!path || !*path || f->n_in >= TOOL_FILES_MAX) return;
    f->in[f->n_in].what = what;
    f->in[f->n_in].path = path;
    f->n_in++;
}

void tool_files_input_list(tool_files *f, const char *what, const char *const *paths, int count)
{
    if (!paths || count <= 0 || f->n_lists >= TOOL_FILES_MAX) return;
    f->lists[f->n_lists].what = what;
    f->lists[f->n_lists].paths = paths;
    f->lists[f->n_lists].count = count;
    f->n_lists++;
}

void tool_files_output(tool_files *f, const char *what, const char *path, tool_output_kind kind)
{
    if (!path || !*path || f->n_out >= TOOL_FILES_MAX) return;
    f->out[f->n_out].what = what;
    f->out[f->n_out].path = path;
    f->out[f->n_out].kind = kind;
    f->out[f->n_out].hint = NULL;
    f->n_out++;
}

void tool_files_sidecar(tool_files *f, const char *path, const char *hint)
{
    const int n = f->n_out;
    tool_files_output(f, "sidecar", path, TOOL_OUT_SIDECAR);
    if (f->n_out > n) f->out[n].hint = hint;
}

int tool_is_sidecar(const char *path)
{
    /* what tool_write_sidecar writes, and lumis merge's copy of it; no sidecar is this big */
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size > (16 << 20)) return 0;
    size_t n = 0;
    int oom = 0;
    unsigned char *text = tool_read_file(path, &n, &oom);
    if (!text) return 0;
    cJSON *j = cJSON_ParseWithLength((const char *)text, n);
    free(text);
    const int yes = cJSON_IsObject(j) &&
                    cJSON_IsString(cJSON_GetObjectItemCaseSensitive(j, "lumis_version")) &&
                    cJSON_IsString(cJSON_GetObjectItemCaseSensitive(j, "command")) &&
                    cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(j, "outputs"));
    cJSON_Delete(j);
    return yes;
}

/* A sidecar replaces an earlier one, or an empty file (nothing to lose); a device (/dev/null)
 * is written through; anything else is someone's file (lumis lights --json, a scene). */
static int check_sidecar(const char *cmd, const char *path, const char *hint)
{
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size == 0 || tool_is_sidecar(path))
        return EXIT_OK;
    return tool_usage_error(cmd,
                            "the sidecar %s would replace a file that is not a lumis sidecar; "
                            "choose another sidecar path%s%s",
                            path, hint ? " with " : "", hint ? hint : "");
}

static int check_one(const char *cmd, const char *what, const char *path, tool_output_kind kind)
{
    struct stat st;
    if (kind == TOOL_OUT_DIR) {
        if (stat(path, &st) == 0) {
            if (!S_ISDIR(st.st_mode))
                return tool_usage_error(cmd, "%s %s exists and is not a directory", what, path);
            if (access(path, W_OK | X_OK) != 0)
                return tool_usage_error(cmd, "%s %s: cannot write there: %s", what, path,
                                        strerror(errno));
            return EXIT_OK;
        }
    } else if (!kind_accepts(kind, path)) {
        return tool_usage_error(cmd, "%s %s: unknown extension (use %s)", what, path,
                                kind_formats(kind));
    }
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
        return tool_usage_error(cmd, "%s %s is a directory", what, path);
    char dir[PATH_MAX];
    dir_of(path, dir, sizeof dir);
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        return tool_usage_error(cmd, "%s %s: the directory %s does not exist", what, path, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return tool_usage_error(cmd, "%s %s: cannot write in %s: %s", what, path, dir,
                                strerror(errno));
    return EXIT_OK;
}

int tool_files_check(const char *cmd, const tool_files *f)
{
    for (int o = 0; o < f->n_out; o++) {
        int rc = check_one(cmd, f->out[o].what, f->out[o].path, f->out[o].kind);
        if (rc != EXIT_OK) return rc;
        for (int i = 0; i < f->n_in; i++)
            if (tool_same_file(f->out[o].path, f->in[i].path))
                return tool_usage_error(cmd, "%s %s would replace the %s %s; choose another name",
                                        f->out[o].what, f->out[o].path, f->in[i].what,
                                        f->in[i].path);
        for (int l = 0; l < f->n_lists; l++)
            for (int i = 0; i < f->lists[l].count; i++)
                if (tool_same_file(f->out[o].path, f->lists[l].paths[i]))
                    return tool_usage_error(
                        cmd, "%s %s would replace the %s %s; choose another name", f->out[o].what,
                        f->out[o].path, f->lists[l].what, f->lists[l].paths[i]);
        for (int p = 0; p < o; p++)
            if (tool_same_file(f->out[o].path, f->out[p].path))
                return tool_usage_error(cmd, "%s and %s are the same file (%s)", f->out[p].what,
                                        f->out[o].what, f->out[o].path);
        if (f->out[o].kind == TOOL_OUT_SIDECAR) {
            rc = check_sidecar(cmd, f->out[o].path, f->out[o].hint);
            if (rc != EXIT_OK) return rc;
        }
    }
    return EXIT_OK;
}
