/* lumis merge SHARE... -o OUT.exr: the image of a render split by passes (lumis render
 * --passes I/N) from its shares: each share's mean weighted by its samples, which is the
 * whole render's mean.  The shares' sidecars say which shares they are; every share of
 * one render must be there, once. */
#include "common.h"

#include <cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: lumis merge SHARE.exr... -o OUT.exr [--no-sidecar]\n\n"
    "Joins the shares of a render split by passes (lumis render --passes I/N, each on its\n"
    "own machine) into the image one render of all the samples gives: the shares' means\n"
    "weighted by their sample counts, in double precision (equal to the whole render's image\n"
    "up to the order of the floating-point sums: a few units in the last place of a float).\n"
    "Each share's sidecar (SHARE.json) must say which share it is, and the shares must be\n"
    "every share of one render (the same scene, map, method, sequence, seed, size and\n"
    "samples), each once.  OUT.json gets the first share's sidecar with the samples and the\n"
    "render times summed.\n\n"
    "options:\n"
    "  -o, --output OUT   the merged image (.exr, .pfm or .hdr; required)\n"
    "  --no-sidecar       no OUT.json\n";

/* The sidecar keys that must agree between the shares of one render. */
static const char *const same_keys[] = {
    "scene",         "environment",  "method",      "estimator",  "heuristic",
    "light_samples", "bsdf_samples", "max_bounces", "seed",       "sequence",
    "width",         "height",       "lights",      "luminaires", NULL};

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

int cmd_merge(int argc, char **argv)
{
    const char *out = NULL, *v;
    int sidecar = 1;
    const char *in[TOOL_FILES_MAX];
    int n = 0;
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "-o", &v) ||
                   tool_option(argc, argv, &i, "--output", &v)) {
            if (!v || !*v) return tool_bad_value("merge", "-o", v, "needs a file");
            out = v;
        } else if (strcmp(argv[i], "--no-sidecar") == 0) {
            sidecar = 0;
        } else if (argv[i][0] != '-') {
            if (n == TOOL_MERGE_MAX)
                return tool_usage_error("merge", "at most %d shares", TOOL_MERGE_MAX);
            in[n++] = argv[i];
        } else {
            return tool_usage_error("merge", "unknown argument '%s'", argv[i]);
        }
    }
    if (!out) return tool_usage_error("merge", "no output file (-o OUT.exr)");
    if (n < 1) return tool_usage_error("merge", "no shares to merge");
    char side_out[4096];
    tool_sidecar_path(out, side_out, sizeof side_out);
    tool_files files = {0};
    static char side_in[TOOL_FILES_MAX][4096]; /* the shares' sidecars: inputs too */
    for (int k = 0; k < n; k++) {
        tool_sidecar_path(in[k], side_in[k], sizeof side_in[k]);
        tool_files_input(&files, "share", in[k]);
        tool_files_input(&files, "share's sidecar", side_in[k]);
    }
    tool_files_output(&files, "-o", out, TOOL_OUT_LINEAR);
    if (sidecar) tool_files_sidecar(&files, side_out, "--no-sidecar, or another OUT");
    int rc = tool_files_check("merge", &files);
    if (rc != EXIT_OK) return rc;

    return tool_merge_shares(in, n, out, sidecar ? side_out : NULL, 0);
}

int tool_merge_shares(const char *const *in, int n, const char *out, const char *side_out,
                      int quiet)
{
    if (n < 1 || n > TOOL_MERGE_MAX)
        return tool_runtime_error("merge: 1 to %d shares, not %d", TOOL_MERGE_MAX, n);
    int rc = EXIT_OK;
    cJSON *side[TOOL_FILES_MAX] = {0};
    lumis_image *img[TOOL_FILES_MAX] = {0};
    int count = 0, seen[TOOL_FILES_MAX] = {0};
    double total = 0, first_total = 0;
    for (int k = 0; k < n && rc == EXIT_OK; k++) {
        char path[4096];
        side[k] = read_sidecar(in[k], path, sizeof path);
        const cJSON *p = side[k] ? cJSON_GetObjectItemCaseSensitive(side[k], "share") : NULL;
        if (!side[k]) {
            rc = tool_runtime_error("merge: %s: no readable sidecar %s (the share's JSON)", in[k],
                                    path);
            break;
        }
        if (!cJSON_IsObject(p)) {
            rc = tool_runtime_error("merge: %s is not a share: its sidecar has no \"share\" "
                                    "(render it with --passes I/N)",
                                    in[k]);
            break;
        }
        const double idx = num(p, "index"), cnt = num(p, "count"), tot = num(p, "spp_total"),
                     spp = num(side[k], "spp");
        if (!(cnt >= 1 && cnt <= TOOL_MERGE_MAX && idx >= 0 && idx < cnt && idx == floor(idx) &&
              spp > 0 && tot >= cnt)) {
            rc = tool_runtime_error("merge: %s: a sidecar's \"share\" that makes no sense", in[k]);
            break;
        }
        if (k == 0) {
            count = (int)cnt;
            first_total = tot;
        } else if ((int)cnt != count || tot != first_total) {
            rc = tool_runtime_error("merge: %s is share %d of %d of %.0f samples, %s of %d of "
                                    "%.0f: not the same render",
                                    in[k], (int)idx, (int)cnt, tot, in[0], count, first_total);
            break;
        }
        for (int q = 0; k > 0 && same_keys[q]; q++) {
            char *a =
                cJSON_PrintUnformatted(cJSON_GetObjectItemCaseSensitive(side[0], same_keys[q]));
            char *b =
                cJSON_PrintUnformatted(cJSON_GetObjectItemCaseSensitive(side[k], same_keys[q]));
            const int differ = (a || b) && (!a || !b || strcmp(a, b) != 0);
            if (differ)
                rc = tool_runtime_error("merge: %s and %s differ in \"%s\" (%s against %s): not "
                                        "shares of one render",
                                        in[0], in[k], same_keys[q], a ? a : "none", b ? b : "none");
            free(a);
            free(b);
            if (rc != EXIT_OK) break;
        }
        if (rc != EXIT_OK) break;
        if (seen[(int)idx]++) {
            rc = tool_runtime_error("merge: share %d of %d given twice (%s)", (int)idx, count,
                                    in[k]);
            break;
        }
        if (tool_load_image(in[k], &img[k], NULL) != LUMIS_OK) {
            rc = EXIT_RUNTIME;
            break;
        }
        if (k > 0 && (img[k]->width != img[0]->width || img[k]->height != img[0]->height)) {
            rc = tool_runtime_error("merge: %s is %d x %d, %s %d x %d", in[k], img[k]->width,
                                    img[k]->height, in[0], img[0]->width, img[0]->height);
            break;
        }
        total += spp;
    }
    if (rc == EXIT_OK && n != count) {
        char missing[512] = "";
        for (int s = 0; s < count; s++)
            if (!seen[s] && strlen(missing) < sizeof missing - 16)
                snprintf(missing + strlen(missing), sizeof missing - strlen(missing), "%s%d",
                         *missing ? ", " : "", s);
        rc = tool_runtime_error("merge: %d of the %d shares given; missing: %s", n, count, missing);
    }
    if (rc == EXIT_OK && total != first_total)
        rc = tool_runtime_error("merge: the shares hold %.0f samples, their render %.0f", total,
                                first_total);
    lumis_image *merged = NULL;
    if (rc == EXIT_OK && lumis_image_create(img[0]->width, img[0]->height, &merged) != LUMIS_OK)
        rc = tool_runtime_error("merge: out of memory");
    if (rc == EXIT_OK) {
        const size_t m = 3 * (size_t)img[0]->width * (size_t)img[0]->height;
        for (size_t q = 0; q < m; q++) {
            double sum = 0.0;
            for (int k = 0; k < n; k++) sum += (double)img[k]->pixels[q] * num(side[k], "spp");
            merged->pixels[q] = (float)(sum / total);
        }
        if (tool_write_image(out, merged, NULL) != LUMIS_OK) rc = EXIT_RUNTIME;
    }
    if (rc == EXIT_OK && side_out) {
        /* the first share's sidecar: all the samples, the passes and times summed, no
         * share */
        cJSON *j = cJSON_Duplicate(side[0], 1);
        cJSON_ReplaceItemInObjectCaseSensitive(j, "spp", cJSON_CreateNumber(total));
        double passes = 0;
        for (int k = 0; k < n; k++) passes += num(side[k], "passes");
        if (isfinite(passes))
            cJSON_ReplaceItemInObjectCaseSensitive(j, "passes", cJSON_CreateNumber(passes));
        cJSON_ReplaceItemInObjectCaseSensitive(j, "share", cJSON_CreateNull());
        cJSON *tm = cJSON_GetObjectItemCaseSensitive(j, "timings");
        for (cJSON *t = tm ? tm->child : NULL; t; t = t->next) {
            if (!cJSON_IsNumber(t)) continue;
            double sum = 0;
            for (int k = 0; k < n; k++)
                sum += num(cJSON_GetObjectItemCaseSensitive(side[k], "timings"), t->string);
            cJSON_SetNumberValue(t, sum);
        }
        cJSON *from = cJSON_AddArrayToObject(j, "merged_from");
        for (int k = 0; k < n; k++) cJSON_AddItemToArray(from, cJSON_CreateString(in[k]));
        if (tool_write_json(side_out, j) != EXIT_OK) rc = EXIT_RUNTIME;
        cJSON_Delete(j);
    }
    if (rc == EXIT_OK && !quiet)
        fprintf(stderr, "merged %d shares of %.0f samples into %s (%d x %d)%s%s\n", n, total, out,
                merged->width, merged->height, side_out ? ", sidecar " : "",
                side_out ? side_out : "");
    lumis_image_destroy(merged);
    for (int k = 0; k < n; k++) {
        cJSON_Delete(side[k]);
        lumis_image_destroy(img[k]);
    }
    return rc;
}
