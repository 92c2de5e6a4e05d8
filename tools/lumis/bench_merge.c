/* lumis bench --merge: joins the folders of other runs (shards) into one, before the
 * report is written from it. */
#include "bench.h"

#include <dirent.h>
#include <stdlib.h>

/* Copies every results/ and previews/ file (and refs/ PNGs) of src into dst. */
int bench_merge_dir(const char *src, const char *dst)
{
    static const char *const subs[] = {"results", "previews", "refs"};
    for (int k = 0; k < 3; k++) {
        char sd[8800], dd[8800];
        snprintf(sd, sizeof sd, "%s/%s", src, subs[k]);
        snprintf(dd, sizeof dd, "%s/%s", dst, subs[k]);
        DIR *d = opendir(sd);
        if (!d) {
            if (k == 0) return tool_runtime_error("--merge %s: no results/ folder there", src);
            continue;
        }
        for (struct dirent *de; (de = readdir(d));) {
            if (de->d_name[0] == '.') continue;
            char a[9600], b[9600];
            snprintf(a, sizeof a, "%s/%s", sd, de->d_name);
            snprintf(b, sizeof b, "%s/%s", dd, de->d_name);
            if (k == 2 && bench_file_exists(b)) continue; /* references are shared by hash */
            FILE *in = fopen(a, "rb");
            if (!in) continue;
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
            lumis_status st =
                buf ? lumis_write_text(b, buf, len, &tool_errors) : LUMIS_ERR_OUT_OF_MEMORY;
            free(buf);
            if (st != LUMIS_OK) {
                closedir(d);
                return EXIT_RUNTIME;
            }
        }
        closedir(d);
    }
    return EXIT_OK;
}
