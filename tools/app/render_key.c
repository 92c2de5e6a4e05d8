/* The render key: one digest of everything that determines a render's image, recorded in
 * the sidecar of each share (render --passes I/N) and compared by lumis merge.  It is the
 * sidecar itself, less an explicit list of what may differ between two shares of one
 * render (timings, counts of work, the host, the share's index): a key that names what to
 * include misses the next setting someone adds, a key that names what to leave out does
 * not.  The sidecar's "inputs" (every file read, by content) make it cover the files too.
 * (The bench's item key is the same idea: bench_keys.c.) */
#include "files.h"
#include "pipeline.h"

#include <cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* What may differ between two shares of one render, as "key" or "object.key".  Anything
 * else in a share's sidecar is in its render key. */
static const char *const may_differ[] = {
    "render_key",                   /* itself */
    "command",                      /* the share's own -o, --passes and --threads */
    "share.index",                  /* which share; its count and total are in the key */
    "share.first_sample",           /* follows from the index: checked by merge */
    "spp",                          /* follows from the index: checked by merge */
    "passes",                       /* one per share, or more: not in the image */
    "threads",                      /* any thread count renders the same image */
    "timings",                      /* seconds */
    "rays",                         /* counts of this share's work, and rays per second */
    "outputs",                      /* the share's own file names */
    "host",                         /* the machine */
    "simd_variant",                 /* code paths of this CPU (the image agrees to rounding) */
    "embree_config",                /* the same */
    "sampler.build_ms",             /* a timing */
    "lights.build_ms",              /* a timing */
    "luminaires.samples",           /* this share's samples */
    "luminaires.samples_per_pixel", /* the same per pixel */
    "merged_from",                  /* a merged render's */
    "auto_off_by", /* which option fixed the estimator (the estimator itself is keyed) */
    NULL};

int tool_render_key_may_differ(const char *path)
{
    for (int k = 0; may_differ[k]; k++)
        if (strcmp(may_differ[k], path) == 0) return 1;
    return 0;
}

/* A copy of the sidecar without what may differ. */
static cJSON *keyed_part(const cJSON *side)
{
    cJSON *c = cJSON_Duplicate(side, 1);
    for (int k = 0; c && may_differ[k]; k++) {
        const char *dot = strchr(may_differ[k], '.');
        if (!dot) {
            cJSON_DeleteItemFromObjectCaseSensitive(c, may_differ[k]);
            continue;
        }
        char head[64];
        snprintf(head, sizeof head, "%.*s", (int)(dot - may_differ[k]), may_differ[k]);
        cJSON *o = cJSON_GetObjectItemCaseSensitive(c, head);
        if (cJSON_IsObject(o)) cJSON_DeleteItemFromObjectCaseSensitive(o, dot + 1);
    }
    return c;
}

int tool_render_key(const cJSON *side, char *out, size_t cap)
{
    cJSON *c = keyed_part(side);
    char *text = c ? cJSON_PrintUnformatted(c) : NULL;
    cJSON_Delete(c);
    if (!text) return 0;
    uint64_t h = tool_fnv(0xcbf29ce484222325ull, "lumis-render-key-v1", 20);
    h = tool_fnv(h, text, strlen(text));
    free(text);
    snprintf(out, cap, "%016llx", (unsigned long long)h);
    return 1;
}

/* The first field (depth first, a's order, then b's) in which a and b differ, as "key" or
 * "object.key"; 0 if none. */
static int first_difference(const cJSON *a, const cJSON *b, const char *prefix, char *path,
                            size_t cap)
{
    for (int pass = 0; pass < 2; pass++)
        for (const cJSON *x = (pass ? b : a)->child; x; x = x->next) {
            const cJSON *y = cJSON_GetObjectItemCaseSensitive(pass ? a : b, x->string);
            char here[512];
            snprintf(here, sizeof here, "%s%s%s", prefix, *prefix ? "." : "", x->string);
            if (y && cJSON_IsObject(x) && cJSON_IsObject(y)) {
                if (first_difference(x, y, here, path, cap)) return 1;
                continue;
            }
            if (y && cJSON_Compare(x, y, 1)) continue;
            snprintf(path, cap, "%s", here);
            return 1;
        }
    return 0;
}

int tool_render_key_difference(const cJSON *a, const cJSON *b, char *field, size_t cap, char *va,
                               char *vb, size_t vcap)
{
    cJSON *ka = keyed_part(a), *kb = keyed_part(b);
    int found = ka && kb && first_difference(ka, kb, "", field, cap);
    if (found) {
        const cJSON *xa = ka, *xb = kb;
        char copy[512];
        snprintf(copy, sizeof copy, "%s", field);
        for (char *save = NULL, *part = strtok_r(copy, ".", &save); part;
             part = strtok_r(NULL, ".", &save)) {
            xa = xa ? cJSON_GetObjectItemCaseSensitive(xa, part) : NULL;
            xb = xb ? cJSON_GetObjectItemCaseSensitive(xb, part) : NULL;
        }
        char *pa = xa ? cJSON_PrintUnformatted(xa) : NULL,
             *pb = xb ? cJSON_PrintUnformatted(xb) : NULL;
        snprintf(va, vcap, "%.200s", pa ? pa : "none");
        snprintf(vb, vcap, "%.200s", pb ? pb : "none");
        free(pa);
        free(pb);
    }
    cJSON_Delete(ka);
    cJSON_Delete(kb);
    return found;
}
