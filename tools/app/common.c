#include "errors.h"
#include "files.h"
#include "lights.h"
#include "pipeline.h"

#include <stdint.h>

#include <sys/stat.h>

#include <errno.h>

#include <math.h>

#include <cJSON.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

static void print_error(void *user, lumis_status status, const char *message)
{
    (void)user;
    /* the library reports warnings with status ok: said as warnings */
    fprintf(stderr, "lumis: %s%s\n", status == LUMIS_OK ? "warning: " : "", message);
}

const lumis_error_sink tool_errors = {print_error, NULL};

int tool_usage_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lumis %s: ", cmd);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n(see 'lumis %s --help')\n", cmd);
    va_end(ap);
    return EXIT_USAGE;
}

int tool_bad_value(const char *cmd, const char *option, const char *value, const char *expected)
{
    if (!value) return tool_usage_error(cmd, "%s %s (no value given)", option, expected);
    return tool_usage_error(cmd, "%s %s, not '%s'", option, expected, value);
}

int tool_runtime_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lumis: ");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n");
    va_end(ap);
    return EXIT_RUNTIME;
}

lumis_status tool_write_image(const char *path, const lumis_image *image,
                              const lumis_write_options *options)
{
    lumis_write_options opt = {0};
    if (options) opt = *options;
    opt.errors = tool_errors;
    return lumis_image_write(path, image, &opt);
}

int tool_write_json(const char *path, const struct cJSON *json)
{
    char *text = cJSON_Print(json);
    if (!text) return tool_runtime_error("%s: out of memory", path);
    size_t n = strlen(text);
    char *line = malloc(n + 2);
    if (line) {
        memcpy(line, text, n);
        line[n++] = '\n';
        line[n] = '\0';
    }
    cJSON_free(text);
    if (!line) return tool_runtime_error("%s: out of memory", path);
    lumis_status st = lumis_write_text(path, line, n, &tool_errors);
    free(line);
    return st == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
}

uint64_t tool_fnv(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t k = 0; k < n; k++) h = (h ^ p[k]) * 0x100000001b3ull;
    return h;
}

int tool_make_dir(const char *path)
{
    char buf[8800];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf)
        return tool_runtime_error("%s: folder name too long", path);
    for (char *p = buf + 1; *p; p++)
        if (*p == '/') {
            *p = '\0';
            if (mkdir(buf, 0755) != 0 && errno != EEXIST)
                return tool_runtime_error("%s: cannot create folder: %s", buf, strerror(errno));
            *p = '/';
        }
    if (mkdir(buf, 0755) == 0 || errno == EEXIST) return EXIT_OK;
    return tool_runtime_error("%s: cannot create folder: %s", path, strerror(errno));
}

unsigned char *tool_read_file(const char *path, size_t *n, int *oom)
{
    *n = 0;
    *oom = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16;
    unsigned char *buf = malloc(cap);
    for (size_t got; buf && (got = fread(buf + *n, 1, cap - *n, f)) > 0;) {
        *n += got;
        if (*n == cap) {
            unsigned char *grown = realloc(buf, cap *= 2);
            if (!grown) free(buf);
            buf = grown;
        }
    }
    fclose(f);
    *oom = buf == NULL;
    return buf;
}

/* The samples of o's share (render --passes I/N): with render_run.c and sidecar.c both
 * asking, it lives below them. */
void tool_share_range(const tool_render_opts *o, int *total, int *first, int *count)
{
    const long long t = o->rd.spp ? o->rd.spp : 16;
    *total = (int)t;
    *first = o->passes ? (int)(t * o->pass_index / o->passes) : 0;
    *count = o->passes ? (int)(t * (o->pass_index + 1) / o->passes) - *first : (int)t;
}

int tool_commit_tmp(FILE *f, const char *path)
{
    if (!f) return tool_runtime_error("%s: cannot make a temporary file", path);
    long n = ftell(f);
    char *text = n >= 0 ? malloc((size_t)n + 1) : NULL;
    rewind(f);
    int rc = EXIT_RUNTIME;
    if (text && fread(text, 1, (size_t)n, f) == (size_t)n &&
        lumis_write_text(path, text, (size_t)n, &tool_errors) == LUMIS_OK)
        rc = EXIT_OK;
    free(text);
    fclose(f);
    return rc;
}

void tool_markup_escape(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '<')
            fputs("&lt;", f);
        else if (*s == '>')
            fputs("&gt;", f);
        else if (*s == '&')
            fputs("&amp;", f);
        else if (*s == '"')
            fputs("&quot;", f);
        else
            fputc(*s, f);
    }
}
