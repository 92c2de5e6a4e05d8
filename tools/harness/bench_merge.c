/* lumis bench --merge: joins the folders of other runs (shards) into one, before the
 * report is written from it. */
#include "harness.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>

/* Copies file a to b (crash-safe).  Exit code. */
static int copy_file(const char *a, const char *b)
{
    FILE *in = fopen(a, "rb");
    if (!in) return EXIT_OK; /* nothing to copy */
    size_t cap = 1 << 20, len = 0;
    char *buf = malloc(cap);
    for (size_t got; buf && (got = fread(buf + len, 1, cap - len, in)) > 0;) {
        len += got;
        if (len == cap) {
            char *g = realloc(buf, cap *= 2);
            if (!g) free(buf);
            buf = g;
        }
    }
    fclose(in);
    lumis_status st = buf ? lumis_write_text(b, buf, len, &tool_errors) : LUMIS_ERR_OUT_OF_MEMORY;
    free(buf);
    return st == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
}

/* Copies from src into dst the results of this suite's items that src holds with the
 * suite's current settings (their item keys), with their previews, and every reference
 * dst lacks (they are shared by hash).  A folder of another suite, or of other settings,
 * would have replaced good results with stale ones: its results are left out and counted,
 * and a folder with results none of which belong is an error. */
int bench_merge_dir(const suite *s, const char *src, const char *dst)
{
    char sd[8800];
    snprintf(sd, sizeof sd, "%s/results", src);
    DIR *d = opendir(sd);
    if (!d) return tool_runtime_error("--merge %s: no results/ folder there", src);
    int files = 0;
    for (struct dirent *de; (de = readdir(d));)
        files += de->d_name[0] != '.' && strstr(de->d_name, ".json") != NULL;
    closedir(d);
    int merged = 0;
    for (int k = 0; k < bench_nitems(s); k++) {
        item it = bench_item_at(s, k);
        if (!bench_item_done(s, src, &it)) continue;
        char a[9600], b[9600];
        snprintf(a, sizeof a, "%s/results/%s.json", src, it.id);
        snprintf(b, sizeof b, "%s/results/%s.json", dst, it.id);
        static const char *const previews[] = {"%s/previews/%s.png", "%s/previews/%s-flip.png"};
        for (int q = 0; q < 2; q++) {
            char pa[9600], pb[9600];
            snprintf(pa, sizeof pa, previews[q], src, it.id);
            snprintf(pb, sizeof pb, previews[q], dst, it.id);
            if (copy_file(pa, pb) != EXIT_OK) return EXIT_RUNTIME;
        }
        if (copy_file(a, b) != EXIT_OK) return EXIT_RUNTIME; /* last: it marks the item done */
        merged++;
    }
    if (files > 0 && merged == 0)
        return tool_runtime_error("--merge %s: none of its %d results belongs to suite '%s' as "
                                  "it is now (another suite, or other settings): nothing merged",
                                  src, files, s->name);
    if (files > merged)
        fprintf(stderr,
                "lumis bench: --merge %s: %d of its %d results left out (not this suite's items "
                "with these settings)\n",
                src, files - merged, files);
    snprintf(sd, sizeof sd, "%s/refs", src);
    d = opendir(sd);
    for (struct dirent *de; d && (de = readdir(d));) {
        if (de->d_name[0] == '.') continue;
        char a[9600], b[9600];
        snprintf(a, sizeof a, "%s/%s", sd, de->d_name);
        snprintf(b, sizeof b, "%s/refs/%s", dst, de->d_name);
        if (bench_file_exists(b)) continue; /* references are shared by hash */
        if (copy_file(a, b) != EXIT_OK) {
            closedir(d);
            return EXIT_RUNTIME;
        }
    }
    if (d) closedir(d);
    return EXIT_OK;
}
