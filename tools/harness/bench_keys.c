/* lumis bench: items and the keys that cache their work.  A reference is named by a hash
 * of everything that makes it; an item's result carries a hash of everything else it
 * depends on, so that a result left by other settings is stale and redone. */
#include "harness.h"

#include <cJSON.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int bench_nitems(const suite *s)
{
    return s->nmaps * s->nscenes * s->nmethods * s->nbudgets;
}

int bench_pair_listed(const suite *s, int m, int sc)
{
    return !s->scenes[sc].maps || s->scenes[sc].maps[m];
}

int bench_nlisted(const suite *s)
{
    int pairs = 0;
    for (int m = 0; m < s->nmaps; m++)
        for (int sc = 0; sc < s->nscenes; sc++) pairs += bench_pair_listed(s, m, sc);
    return pairs * s->nmethods * s->nbudgets;
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

static uint64_t fnv_str(uint64_t h, const char *s)
{
    return tool_fnv(h, s, strlen(s) + 1);
}

/* Where every reference key starts (the map's content comes next). */
static uint64_t reference_basis(void)
{
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv_str(h, "lumis-reference-v1");
    return fnv_str(h, LUMIS_VERSION_STRING);
}

int bench_read_inputs(suite *s, int keep_maps)
{
    const uint64_t basis = reference_basis();
    for (int m = 0; m < s->nmaps; m++) {
        suite_map *map = &s->maps[m];
        map->first = m;
        for (int j = 0; j < m && map->first == m; j++)
            if (strcmp(s->maps[j].spec, map->spec) == 0) map->first = j;
        if (map->first != m) {
            map->hash = s->maps[map->first].hash;
            continue;
        }
        if (!map->is_file) {
            map->hash = fnv_str(basis, map->spec);
            continue;
        }
        int oom;
        unsigned char *b = tool_read_file(map->spec, &map->nbytes, &oom);
        if (oom) return tool_runtime_error("bench: out of memory reading %s", map->spec);
        map->hash = b ? tool_fnv(basis, b, map->nbytes) : fnv_str(basis, map->spec);
        if (keep_maps)
            map->bytes = b;
        else
            free(b);
    }
    for (int k = 0; k < s->nscenes; k++) {
        suite_scene *sc = &s->scenes[k];
        int oom;
        if (sc->is_file) sc->bytes = tool_read_file(sc->spec, &sc->nbytes, &oom);
        if (sc->is_file && oom)
            return tool_runtime_error("bench: out of memory reading %s", sc->spec);
    }
    return EXIT_OK;
}

/* Everything that makes a reference image: the map's content, its rotation and scale,
 * the scene (a file's content; a built-in's name and lumis' version), the size, the
 * reference's method, samples, bounces and seed. */
void bench_reference_key(const suite *s, int m, int sc, char *out, size_t cap)
{
    const suite_map *map = &s->maps[m];
    uint64_t h = map->hash; /* reference_basis() and the map's content, hashed once */
    char buf[512];
    snprintf(buf, sizeof buf, "%.9g %.9g %d %d %d %d %d %d %d %d %d %d %llu", map->rotation_deg,
             map->scale, s->width, s->height, s->ref_spp, (int)s->reference.sampler.method,
             s->reference.sampler.kdtree_blocks, s->reference.bsdf_only,
             (int)s->reference.estimator * 2 + s->reference.power, s->reference.light_samples,
             s->reference.bsdf_samples, s->bounces, s->seed);
    h = fnv_str(h, buf);
    if (s->reference.lights[0]) { /* a stratified light set: only such references extend it */
        char params[1024];
        lumis_light_params_format(&s->reference.lights_params, params, sizeof params);
        snprintf(buf, sizeof buf, " lights %s %d ", s->reference.lights, s->reference.lights_k);
        h = fnv_str(fnv_str(h, buf), params);
        if (s->reference.lights_draws) {
            snprintf(buf, sizeof buf, " draws %d", s->reference.lights_draws);
            h = fnv_str(h, buf);
        }
    }
    if (s->reference.sun) h = fnv_str(h, " sun"); /* keys without the sun stay */
    const lumis_sequence rq = lumis_sequence_resolve(s->reference.sequence);
    if (rq != LUMIS_SEQUENCE_PCG) { /* PCG32's keys stay as they were before sequences */
        snprintf(buf, sizeof buf, " sequence %s", lumis_sequence_name(rq));
        h = fnv_str(h, buf);
    }
    const suite_scene *scene = &s->scenes[sc];
    h = scene->bytes ? tool_fnv(h, scene->bytes, scene->nbytes) : fnv_str(h, scene->spec);
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
    if (m->lights[0]) { /* only light sets extend the key: samplers' keys stay as they were */
        snprintf(buf, sizeof buf, " lights %s %d %d %d", m->lights, m->lights_k, m->interleave,
                 m->upsample);
        h = fnv_str(h, buf);
        if (m->lights_mode) h = fnv_str(h, " stratified"); /* point mode's keys stay */
        if (m->lights_draws) { /* and those of one draw in every region */
            snprintf(buf, sizeof buf, " draws %d", m->lights_draws);
            h = fnv_str(h, buf);
        }
        if (m->lights_region_draws) { /* allocated draws: their count, as the draws' */
            snprintf(buf, sizeof buf, " region_draws %d", m->lights_region_draws);
            h = fnv_str(h, buf);
        }
        char params[1024];
        lumis_light_params_format(&m->lights_params, params, sizeof params);
        if (*params) h = fnv_str(h, params); /* parameters extend only the keys that have them */
    }
    if (m->sun) h = fnv_str(h, " sun"); /* keys without the sun stay as they were */
    /* and those without auto; the pilots keep their key of before the prediction existed */
    if (m->auto_estimator)
        h = fnv_str(h, m->auto_estimator == LUMIS_AUTO_PILOTS ? " auto" : " auto-predict");
    const lumis_sequence q = lumis_sequence_resolve(m->sequence);
    if (q != LUMIS_SEQUENCE_PCG) { /* PCG32's keys stay as they were before sequences */
        snprintf(buf, sizeof buf, " sequence %s", lumis_sequence_name(q));
        h = fnv_str(h, buf);
    }
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
    /* a result is whole when it has its key and its numbers (it is written last, atomically,
     * so anything less was not written by this tool) */
    const cJSON *spp = cJSON_GetObjectItemCaseSensitive(j, "spp"),
                *rel = cJSON_GetObjectItemCaseSensitive(j, "relmse");
    if (!cJSON_IsString(k) || strcmp(k->valuestring, key) != 0 || !cJSON_IsNumber(spp) ||
        spp->valuedouble < 1 || !cJSON_IsNumber(rel)) {
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
    const item it = bench_item_at(s, k);
    if (!bench_pair_listed(s, it.map, it.scene)) return 0;
    const int pairs = s->nmaps * s->nscenes;
    if (pairs >= shard_n) return (k / (s->nmethods * s->nbudgets)) % shard_n == shard_i;
    return k % shard_n == shard_i;
}

int bench_pair_needed(const suite *s, const char *out, int m, int sc)
{
    if (!bench_pair_listed(s, m, sc)) return 0;
    for (int me = 0; me < s->nmethods; me++)
        for (int b = 0; b < s->nbudgets; b++) {
            item it = bench_item_at(s, bench_idx(s, m, sc, me, b));
            if (!bench_item_done(s, out, &it)) return 1;
        }
    return 0;
}

void bench_reference_path(const suite *s, const char *out, int m, int sc, char *exr, size_t cap)
{
    char key[32];
    bench_reference_key(s, m, sc, key, sizeof key);
    snprintf(exr, cap, "%s/refs/%s.exr", out, key);
}

void bench_reference_part_path(const suite *s, const char *out, int m, int sc, long i, long p,
                               char *exr, size_t cap)
{
    char key[32];
    bench_reference_key(s, m, sc, key, sizeof key);
    snprintf(exr, cap, "%s/refs/parts/%s.pass-%ld-of-%ld.exr", out, key, i, p);
}

/* path reads (quietly) as an image of the suite's size (any, without "size": the scene's
 * camera's). */
static int image_ok(const suite *s, const char *path)
{
    lumis_image *img = NULL;
    const int ok = lumis_image_read(path, NULL, &img, NULL) == LUMIS_OK &&
                   (s->width == 0 || (img->width == s->width && img->height == s->height));
    lumis_image_destroy(img);
    return ok;
}

int bench_reference_ok(const suite *s, const char *out, int m, int sc)
{
    char exr[8800];
    bench_reference_path(s, out, m, sc, exr, sizeof exr);
    return image_ok(s, exr);
}

int bench_reference_part_ok(const suite *s, const char *out, int m, int sc, long i, long p)
{
    char exr[8800], side[8900];
    bench_reference_part_path(s, out, m, sc, i, p, exr, sizeof exr);
    tool_sidecar_path(exr, side, sizeof side);
    size_t len = 0;
    int oom = 0;
    unsigned char *text = tool_read_file(side, &len, &oom);
    cJSON *j = text ? cJSON_ParseWithLength((const char *)text, len) : NULL;
    free(text);
    const cJSON *sh = cJSON_GetObjectItemCaseSensitive(j, "share");
    const cJSON *idx = cJSON_GetObjectItemCaseSensitive(sh, "index"),
                *cnt = cJSON_GetObjectItemCaseSensitive(sh, "count"),
                *tot = cJSON_GetObjectItemCaseSensitive(sh, "spp_total");
    const int ok = cJSON_IsNumber(idx) && idx->valuedouble == (double)i && cJSON_IsNumber(cnt) &&
                   cnt->valuedouble == (double)p && cJSON_IsNumber(tot) &&
                   tot->valuedouble == (double)s->ref_spp && image_ok(s, exr);
    cJSON_Delete(j);
    return ok;
}
