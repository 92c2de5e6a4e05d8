/* Joining the shares of a render split by passes (lumis merge, and the bench's references
 * split into shares): each share's mean weighted by its samples, which is the whole
 * render's mean.  The shares' sidecars say which shares they are; every share of one
 * render must be there, once. */
#include "errors.h"
#include "files.h"
#include "load.h"
#include "pipeline.h"

#include <cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static cJSON *read_sidecar(const char *image, char *path, size_t cap)
{
    tool_sidecar_path(image, path, cap);
    size_t len = 0;
    int oom = 0;
    unsigned char *text = tool_read_file(path, &len, &oom);
    cJSON *j = text ? cJSON_ParseWithLength((const char *)text, len) : NULL;
    free(text);
    return j;
}

static double num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}
/* Whether x is an integer in [lo, hi]. */
static int whole(double x, double lo, double hi)
{
    return x >= lo && x <= hi && x == floor(x);
}

/* The shares' sidecars, each checked against the first and against itself: a share of its
 * render (one render key, one count, one total), its samples derived from its index. */
static int check_sidecars(const char *const *in, int n, cJSON **first, int *index, int *count,
                          int *total, cJSON *timings, double *passes)
{
    int rc = EXIT_OK;
    unsigned char *seen = NULL;
    *passes = 0;
    for (int k = 0; k < n && rc == EXIT_OK; k++) {
        char path[4096], key[32], field[512], va[256], vb[256];
        cJSON *side = read_sidecar(in[k], path, sizeof path);
        const cJSON *p = cJSON_GetObjectItemCaseSensitive(side, "share"),
                    *rk = cJSON_GetObjectItemCaseSensitive(side, "render_key");
        const double idx = num(p, "index"), cnt = num(p, "count"), tot = num(p, "spp_total"),
                     spp = num(side, "spp"), fs = num(p, "first_sample");
        if (!side) {
            rc = tool_runtime_error("merge: %s: no readable sidecar %s (the share's JSON)", in[k],
                                    path);
        } else if (!cJSON_IsObject(p)) {
            rc = tool_runtime_error("merge: %s is not a share: its sidecar has no \"share\" "
                                    "(render it with --passes I/N)",
                                    in[k]);
        } else if (!whole(cnt, 1, TOOL_MERGE_MAX) || !whole(tot, cnt, TOOL_MERGE_MAX)) {
            rc = tool_runtime_error("merge: %s: \"share\" says %g shares of %g samples: not "
                                    "whole numbers with 1 <= shares <= samples <= 2^20",
                                    in[k], cnt, tot);
        } else if (!whole(idx, 0, cnt - 1)) {
            rc = tool_runtime_error("merge: %s: \"share.index\" %g: not a whole number in [0, %g]",
                                    in[k], idx, cnt - 1);
        } else if (!cJSON_IsString(rk)) {
            rc = tool_runtime_error("merge: %s: its sidecar has no \"render_key\" (rendered by an "
                                    "older lumis: render the share again)",
                                    in[k]);
        } else if (k > 0 && tool_render_key_difference(*first, side, field, sizeof field, va, vb,
                                                       sizeof va)) {
            rc = tool_runtime_error("merge: %s is not a share of the render of %s: they differ "
                                    "in \"%s\" (%s against %s)",
                                    in[k], in[0], field, vb, va);
        } else if (!tool_render_key(side, key, sizeof key)) {
            rc = tool_runtime_error("merge: out of memory");
        } else if (strcmp(key, rk->valuestring) != 0) {
            rc = tool_runtime_error("merge: %s: its \"render_key\" %s is not the key of its "
                                    "fields (%s): the sidecar was edited",
                                    in[k], rk->valuestring, key);
        } else if (k > 0 &&
                   strcmp(rk->valuestring,
                          cJSON_GetObjectItemCaseSensitive(*first, "render_key")->valuestring) !=
                       0) {
            rc = tool_runtime_error("merge: %s and %s have different render keys", in[k], in[0]);
        }
        if (rc != EXIT_OK) {
            cJSON_Delete(side);
            break;
        }
        /* the samples of share idx of cnt of tot, as render --passes splits them */
        const long long T = (long long)tot, N = (long long)cnt, I = (long long)idx;
        const long long from = T * I / N, own = T * (I + 1) / N - from;
        if (spp != (double)own || fs != (double)from) {
            rc = tool_runtime_error("merge: %s: share %lld of %lld of %lld samples holds samples "
                                    "%lld to %lld (%lld), its sidecar says \"spp\" %g from "
                                    "\"share.first_sample\" %g",
                                    in[k], I, N, T, from, from + own - 1, own, spp, fs);
            cJSON_Delete(side);
            break;
        }
        if (k == 0) {
            *first = side;
            *count = (int)N;
            *total = (int)T;
            if (!(seen = calloc((size_t)N, 1))) {
                rc = tool_runtime_error("merge: out of memory");
                break;
            }
        }
        if (seen[I]++) {
            rc = tool_runtime_error("merge: share %lld of %lld given twice (%s)", I, N, in[k]);
            if (k > 0) cJSON_Delete(side);
            break;
        }
        index[k] = (int)I;
        *passes += num(side, "passes");
        const cJSON *tm = cJSON_GetObjectItemCaseSensitive(side, "timings");
        for (cJSON *t = timings->child; t; t = t->next)
            if (cJSON_IsNumber(t)) cJSON_SetNumberValue(t, t->valuedouble + num(tm, t->string));
        if (k == 0) { /* the sums start from the first share's timings' names */
            for (const cJSON *t = tm ? tm->child : NULL; t; t = t->next)
                if (cJSON_IsNumber(t)) cJSON_AddNumberToObject(timings, t->string, t->valuedouble);
        } else {
            cJSON_Delete(side);
        }
    }
    if (rc == EXIT_OK && n != *count) {
        char missing[600] = "";
        int m = 0;
        for (int s = 0; s < *count; s++) {
            if (seen[s]) continue;
            if (m++ < 24)
                snprintf(missing + strlen(missing), sizeof missing - strlen(missing), "%s%d",
                         *missing ? ", " : "", s);
        }
        rc = tool_runtime_error("merge: %d of the %d shares given; missing: %s%s", n, *count,
                                missing, m > 24 ? " and more" : "");
        if (m > 24) fprintf(stderr, "lumis: merge: %d shares missing in all\n", m);
    }
    free(seen);
    return rc;
}

int tool_merge_shares(const char *const *in, int n, const char *out, const char *side_out,
                      int quiet, int allow_replaced)
{
    if (n < 1 || n > TOOL_MERGE_MAX)
        return tool_runtime_error("merge: 1 to %d shares, not %d", TOOL_MERGE_MAX, n);
    cJSON *first = NULL, *timings = cJSON_CreateObject();
    int *index = malloc(sizeof(int) * (size_t)n), count = 0, total = 0;
    double passes = 0;
    int rc = index && timings ? EXIT_OK : tool_runtime_error("merge: out of memory");
    if (rc == EXIT_OK) rc = check_sidecars(in, n, &first, index, &count, &total, timings, &passes);
    /* the images, one at a time: their sum weighted by their samples, in double */
    const int w = (int)num(first, "width"), h = (int)num(first, "height");
    double *sum = NULL;
    if (rc == EXIT_OK &&
        !(w > 0 && h > 0 && (sum = calloc(3 * (size_t)w * (size_t)h, sizeof *sum))))
        rc = tool_runtime_error("merge: out of memory, or no size in %s's sidecar", in[0]);
    for (int k = 0; k < n && rc == EXIT_OK; k++) {
        lumis_image *img = NULL;
        lumis_read_info info;
        memset(&info, 0, sizeof info);
        if (tool_load_render(in[k], &img, &info) != LUMIS_OK) {
            rc = EXIT_RUNTIME;
            break;
        }
        const unsigned long long bad = lumis_replaced_total(info.replaced);
        if (img->width != w || img->height != h) {
            rc = tool_runtime_error("merge: %s is %d x %d, its sidecar says %d x %d", in[k],
                                    img->width, img->height, w, h);
        } else if (bad && !allow_replaced) {
            rc = tool_runtime_error("merge: %s: share %d has %llu pixel values that are not "
                                    "finite and non-negative (NaN %llu, Inf %llu, negative %llu): "
                                    "read as 0 they would bias the image; render it again, or "
                                    "--allow-replaced",
                                    in[k], index[k], bad, (unsigned long long)info.replaced.nan,
                                    (unsigned long long)info.replaced.inf,
                                    (unsigned long long)info.replaced.negative);
        } else {
            const long long T = total, N = count, I = index[k];
            const double spp = (double)(T * (I + 1) / N - T * I / N);
            const size_t m = 3 * (size_t)w * (size_t)h;
            for (size_t q = 0; q < m; q++) sum[q] += (double)img->pixels[q] * spp;
        }
        lumis_image_destroy(img);
    }
    lumis_image *merged = NULL;
    if (rc == EXIT_OK && lumis_image_create(w, h, &merged) != LUMIS_OK)
        rc = tool_runtime_error("merge: out of memory");
    if (rc == EXIT_OK) {
        const size_t m = 3 * (size_t)w * (size_t)h;
        for (size_t q = 0; q < m; q++) merged->pixels[q] = (float)(sum[q] / total);
        if (tool_write_image(out, merged, NULL) != LUMIS_OK) rc = EXIT_RUNTIME;
    }
    if (rc == EXIT_OK && side_out) {
        /* the first share's sidecar: all the samples, the passes and times summed, no
         * share; its render key stays (the render the shares were of) */
        cJSON *j = cJSON_Duplicate(first, 1);
        cJSON_ReplaceItemInObjectCaseSensitive(j, "spp", cJSON_CreateNumber(total));
        if (isfinite(passes))
            cJSON_ReplaceItemInObjectCaseSensitive(j, "passes", cJSON_CreateNumber(passes));
        cJSON_ReplaceItemInObjectCaseSensitive(j, "share", cJSON_CreateNull());
        cJSON *tm = cJSON_GetObjectItemCaseSensitive(j, "timings");
        for (cJSON *t = tm ? tm->child : NULL; t; t = t->next)
            if (cJSON_IsNumber(t)) cJSON_SetNumberValue(t, num(timings, t->string));
        cJSON_DeleteItemFromObjectCaseSensitive(j, "host");
        cJSON *from = cJSON_AddArrayToObject(j, "merged_from");
        for (int k = 0; k < n; k++) cJSON_AddItemToArray(from, cJSON_CreateString(in[k]));
        if (tool_write_json(side_out, j) != EXIT_OK) rc = EXIT_RUNTIME;
        cJSON_Delete(j);
    }
    if (rc == EXIT_OK && !quiet)
        fprintf(stderr, "merged %d shares of %d samples into %s (%d x %d)%s%s\n", n, total, out, w,
                h, side_out ? ", sidecar " : "", side_out ? side_out : "");
    lumis_image_destroy(merged);
    free(sum);
    free(index);
    cJSON_Delete(first);
    cJSON_Delete(timings);
    return rc;
}
