/* lumis bench: items and the keys that cache their work.  A reference is named by a hash
 * of everything that makes it; an item's result carries a hash of everything else it
 * depends on, so that a result left by other settings is stale and redone. */
#include "bench.h"

#include <cJSON.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

int bench_nitems(const suite *s)
{
    return s->nmaps * s->nscenes * s->nmethods * s->nbudgets;
}

item bench_item_at(const suite *s, int index)
{
    item it;
    it.budget = index % s->nbudgets;
    index /= s->nbudgets;
    it.method = index % s->nmethods;
    index /= s->nmethods;
    it.scene = index % s->nscenes;
    it.map = index / s->nscenes;
    snprintf(it.id, sizeof it.id, "%s__%s__%s__%s", s->maps[it.map].label,
             s->scenes[it.scene].label, s->methods[it.method].label, s->budgets[it.budget].label);
    return it;
}

int bench_idx(const suite *s, int m, int sc, int me, int b)
{
    return ((m * s->nscenes + sc) * s->nmethods + me) * s->nbudgets + b;
}

static uint64_t fnv(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t k = 0; k < n; k++) h = (h ^ p[k]) * 0x100000001b3ull;
    return h;
}

static uint64_t fnv_str(uint64_t h, const char *s)
{
    return fnv(h, s, strlen(s) + 1);
}

/* A file's bytes into the hash (a missing file hashes its name, and fails later). */
static uint64_t fnv_file(uint64_t h, const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return fnv_str(h, path);
    unsigned char buf[65536];
    for (size_t n; (n = fread(buf, 1, sizeof buf, f)) > 0;) h = fnv(h, buf, n);
    fclose(f);
    return h;
}

/* Everything that makes a reference image: the map's content, its rotation and scale,
 * the scene (a file's content; a built-in's name and lumis' version), the size, the
 * reference's method, samples, bounces and seed. */
void bench_reference_key(const suite *s, int m, int sc, char *out, size_t cap)
{
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv_str(h, "lumis-reference-v1");
    h = fnv_str(h, LUMIS_VERSION_STRING);
    const suite_map *map = &s->maps[m];
    h = map->is_file ? fnv_file(h, map->spec) : fnv_str(h, map->spec);
    char buf[512];
    snprintf(buf, sizeof buf, "%.9g %.9g %d %d %d %d %d %d %d %d %d %d %llu", map->rotation_deg,
             map->scale, s->width, s->height, s->ref_spp, (int)s->reference.sampler.method,
             s->reference.sampler.kdtree_blocks, s->reference.bsdf_only,
             (int)s->reference.estimator * 2 + s->reference.power, s->reference.light_samples,
             s->reference.bsdf_samples, s->bounces, s->seed);
    h = fnv_str(h, buf);
    const suite_scene *scene = &s->scenes[sc];
    h = scene->is_file ? fnv_file(h, scene->spec) : fnv_str(h, scene->spec);
    snprintf(out, cap, "%016llx", (unsigned long long)h);
}

/* Everything an item's result depends on besides its reference: the method, the budget,
 * the seed, the metrics' settings.  Stored in the result; a result whose key differs
 * (the suite changed under the same labels) is stale and redone. */
void bench_item_key(const suite *s, const item *it, char *out, size_t cap)
{
    char ref[32], buf[1024];
    bench_reference_key(s, it->map, it->scene, ref, sizeof ref);
    const suite_method *m = &s->methods[it->method];
    const suite_budget *b = &s->budgets[it->budget];
    snprintf(buf, sizeof buf,
             "lumis-item-v1 %s %s %d %d %d %d %d %d %d %d %.9g %llu %d %d %d %.9g %d %d %.9g",
             LUMIS_VERSION_STRING, ref, (int)m->sampler.method, m->sampler.kdtree_blocks,
             m->sampler.compensate, m->bsdf_only, (int)m->estimator, m->power, m->light_samples,
             m->bsdf_samples, b->seconds, s->seed, b->spp, s->width, s->height, s->exposure_ev,
             s->exposure_auto, s->flip_hdr, s->preview_ev);
    uint64_t h = fnv_str(0xcbf29ce484222325ull, buf);
    snprintf(out, cap, "%016llx", (unsigned long long)h);
}

/* The item's result file, parsed, if it exists and belongs to the suite as it is now. */
cJSON *bench_load_item(const suite *s, const char *out, const item *it)
{
    char path[8800];
    snprintf(path, sizeof path, "%s/results/%s.json", out, it->id);
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char buf[16384];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    cJSON *j = cJSON_ParseWithLength(buf, n);
    char key[32];
    bench_item_key(s, it, key, sizeof key);
    const cJSON *k = cJSON_GetObjectItemCaseSensitive(j, "item_key");
    if (!cJSON_IsString(k) || strcmp(k->valuestring, key) != 0) {
        cJSON_Delete(j);
        return NULL;
    }
    return j;
}

int bench_item_done(const suite *s, const char *out, const item *it)
{
    cJSON *j = bench_load_item(s, out, it);
    cJSON_Delete(j);
    return j != NULL;
}

/* Shards split the (map, scene) pairs when there are enough of them, so that each
 * reference is rendered by one shard only; otherwise the items. */
int bench_in_shard(const suite *s, int k, long shard_i, long shard_n)
{
    const int pairs = s->nmaps * s->nscenes;
    if (pairs >= shard_n) return (k / (s->nmethods * s->nbudgets)) % shard_n == shard_i;
    return k % shard_n == shard_i;
}
