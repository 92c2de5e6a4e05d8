/* lumis bench: running the items.  References first (cached by their hash), then each
 * item: a render, its metrics against the reference, its previews and its result file
 * (written last: it marks the item done).  Each item in a process of its own (up to --jobs
 * at once), so that one failing or crashing item is recorded and the others go on. */
#include "harness.h"

#include <cJSON.h>
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

typedef struct run_ctx {
    const suite *s;
    const char *out;
    lumis_image *const *images; /* per map, loaded once per run (shared by its spec) */
    int threads;
    int argc;
    char **argv;
} run_ctx;

int bench_file_exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

static void fill_render_opts(const run_ctx *c, const item *it, const suite_method *m,
                             tool_render_opts *o)
{
    const suite *s = c->s;
    memset(o, 0, sizeof *o);
    const suite_scene *sc = &s->scenes[it->scene];
    if (sc->is_file)
        o->scene_path = sc->spec;
    else
        o->scene_name = sc->spec;
    /* a built-in scene lit by its luminaire (headlight): the map and the method's light set,
     * estimator and sample counts change nothing there (docs/bench.md), and render refuses
     * them (lumis_session_check) */
    const int self_lit = !sc->is_file && lumis_scene_builtin_luminaire_spec(sc->spec) != NULL;
    o->envspec = self_lit ? NULL : s->maps[it->map].spec;
    o->env_image = self_lit ? NULL : c->images[it->map];
    o->env_image_replaced = s->maps[it->map].replaced;
    o->rotation_deg = s->maps[it->map].rotation_deg;
    o->scale = s->maps[it->map].scale;
    o->sampler = m->sampler;
    o->bsdf_only = self_lit ? 0 : m->bsdf_only;
    o->lights = m->lights[0] && !self_lit ? m->lights : NULL;
    if (!self_lit) {
        o->lights_mode = m->lights_mode;
        o->sun = m->sun;
        o->auto_estimator = m->auto_estimator;
        o->rd.lighting.light_set.draws = m->lights_draws;
        o->rd.lighting.light_set.region_draws = m->lights_region_draws;
        o->lights_k = m->lights_k;
        o->interleave = m->interleave;
        o->lights_params = m->lights_params;
        o->upsample = m->upsample;
        o->rd.lighting.estimator = m->estimator;
        o->rd.power_heuristic = m->power;
        o->rd.light_samples = m->light_samples;
        o->rd.bsdf_samples = m->bsdf_samples;
    }
    o->rd.seed = s->seed;
    o->rd.sequence = m->sequence;
    o->rd.threads = c->threads;
    o->rd.max_bounces = s->bounces;
    o->width = s->width;
    o->height = s->height;
    o->quiet = 1;
    o->argc = c->argc;
    o->argv = c->argv;
    o->png_options.exposure_ev = s->preview_ev;
    o->png_options.tonemap = LUMIS_TONEMAP_ACES;
}

/* The reference's preview, from its image (with the suite's current settings). */
static int write_reference_preview(const suite *s, const char *png, const lumis_image *img)
{
    lumis_write_options wo = {0};
    wo.tonemap = LUMIS_TONEMAP_ACES;
    wo.exposure_ev = s->preview_auto ? tool_auto_exposure(img) : s->preview_ev;
    return tool_write_image(png, img, &wo) == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
}

/* Renders the reference of (m, sc) into exr, or its share pass_i of passes (passes 0: the
 * whole of it), with its preview png (NULL: none). */
static int render_reference(const run_ctx *c, int m, int sc, int pass_i, int passes,
                            const char *exr, const char *png)
{
    const suite *s = c->s;
    item it = {m, sc, 0, 0, ""};
    tool_render_opts o;
    fill_render_opts(c, &it, &s->reference, &o);
    o.rd.spp = s->ref_spp;
    o.rd.seed = s->seed + 0x5eedull; /* independent of every test image */
    o.pass_index = pass_i;
    o.passes = passes;
    o.out = exr;
    o.png = NULL; /* written below, once the exposure is known */
    if (passes)
        fprintf(stderr, "lumis bench: reference %s / %s: share %d of %d of %d spp ...\n",
                s->maps[m].label, s->scenes[sc].label, pass_i, passes, s->ref_spp);
    else
        fprintf(stderr, "lumis bench: reference %s / %s: %d spp ...\n", s->maps[m].label,
                s->scenes[sc].label, s->ref_spp);
    tool_render_result r;
    int rc = tool_render(&o, &r);
    if (rc == EXIT_OK && png) rc = write_reference_preview(s, png, r.image);
    lumis_image_destroy(r.image);
    return rc;
}

static int ensure_reference(const run_ctx *c, int m, int sc)
{
    const suite *s = c->s;
    char exr[8800], png[8900];
    bench_reference_path(s, c->out, m, sc, exr, sizeof exr);
    snprintf(png, sizeof png, "%.*s.png", (int)strlen(exr) - 4, exr);
    /* cached when it reads and has the size (a file that does not is rendered again); its
     * preview follows the suite's current settings */
    if (bench_reference_ok(s, c->out, m, sc)) {
        lumis_image *img = NULL;
        if (tool_load_render(exr, &img, NULL) != LUMIS_OK) return EXIT_RUNTIME;
        const int rc = write_reference_preview(s, png, img);
        lumis_image_destroy(img);
        return rc;
    }
    return render_reference(c, m, sc, 0, 0, exr, png);
}

static int run_item(const run_ctx *c, const item *it, int index, int total)
{
    const suite *s = c->s;
    char result[8800], exr[8800], png[8800], flip_png[8800], ref_exr[8800];
    snprintf(result, sizeof result, "%s/results/%s.json", c->out, it->id);
    if (bench_item_done(s, c->out, it)) return EXIT_OK; /* resumed: done before */
    char key[32];
    bench_reference_key(s, it->map, it->scene, key, sizeof key);
    bench_reference_path(s, c->out, it->map, it->scene, ref_exr, sizeof ref_exr);
    snprintf(exr, sizeof exr, "%s/renders/%s.exr", c->out, it->id);
    snprintf(png, sizeof png, "%s/previews/%s.png", c->out, it->id);
    snprintf(flip_png, sizeof flip_png, "%s/previews/%s-flip.png", c->out, it->id);
    const suite_budget *b = &s->budgets[it->budget];
    lumis_image *ref = NULL;
    if (tool_load_render(ref_exr, &ref, NULL) != LUMIS_OK) return EXIT_RUNTIME;
    const float ref_ev = tool_auto_exposure(ref), ev = s->exposure_auto ? ref_ev : s->exposure_ev;
    tool_render_opts o;
    fill_render_opts(c, it, &s->methods[it->method], &o);
    o.rd.spp = b->spp;
    o.time_budget = b->seconds;
    o.out = exr;
    o.png = png;
    if (s->preview_auto) o.png_options.exposure_ev = ref_ev;
    tool_render_result r;
    if (tool_render(&o, &r) != EXIT_OK) {
        lumis_image_destroy(ref);
        return EXIT_RUNTIME;
    }
    int rc = EXIT_RUNTIME;
    float *map = malloc(sizeof(float) * (size_t)r.image->width * (size_t)r.image->height);
    tool_metrics m;
    if (map && tool_compare_images(ref, r.image, ev, 0.0, s->flip_hdr, &m, map) == EXIT_OK &&
        tool_write_flip_map(flip_png, map, r.image->width, r.image->height) == EXIT_OK) {
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "id", it->id);
        cJSON_AddStringToObject(j, "suite", s->name);
        cJSON_AddStringToObject(j, "map", s->maps[it->map].label);
        cJSON_AddStringToObject(j, "scene", s->scenes[it->scene].label);
        cJSON_AddStringToObject(j, "method", s->methods[it->method].label);
        cJSON_AddStringToObject(j, "budget", b->label);
        cJSON_AddStringToObject(j, "reference", key);
        char ikey[32];
        bench_item_key(s, it, ikey, sizeof ikey);
        cJSON_AddStringToObject(j, "item_key", ikey);
        cJSON_AddNumberToObject(j, "spp", r.stats.spp);
        cJSON_AddNumberToObject(j, "render_seconds", r.stats.seconds);
        /* inside an equal-time item's budget: tables, light sets, K's pilots */
        cJSON_AddNumberToObject(j, "prep_seconds", r.prep_seconds);
        /* what the item used: prep and every attempt's render (point lights whose pilots
         * misjudged the time render twice; render_seconds is the image's attempt alone) */
        cJSON_AddNumberToObject(j, "used_seconds",
                                b->seconds > 0.0 ? r.budget_used_seconds
                                                 : r.prep_seconds + r.stats.seconds);
        cJSON_AddNumberToObject(j, "attempts", r.lights_retried ? 2 : 1);
        /* contention: the session's wall and CPU time, the render threads' CPU share */
        cJSON_AddNumberToObject(j, "wall_seconds", r.wall_seconds);
        cJSON_AddNumberToObject(j, "cpu_seconds", r.cpu_seconds);
        cJSON_AddNumberToObject(j, "cpu_share", r.cpu_share);
        cJSON_AddBoolToObject(j, "contention", r.contended);
        /* BSDF sampling builds no light sampler worth counting (the CLI makes one anyway). */
        const int bsdf = s->methods[it->method].bsdf_only;
        cJSON_AddNumberToObject(j, "sampler_build_ms", bsdf ? 0.0 : r.sampler_build_ms);
        cJSON_AddNumberToObject(j, "sampler_table_bytes",
                                bsdf ? 0.0 : (double)r.sampler_table_bytes);
        cJSON_AddNumberToObject(j, "shadow_rays", r.stats.shadow_rays);
        cJSON_AddNumberToObject(j, "threads", r.stats.threads);
        if (r.auto_count > 0) { /* "auto": what its pilots measured, and what it chose */
            cJSON_AddStringToObject(j, "auto_chosen", lumis_auto_candidate_name(r.auto_chosen));
            cJSON_AddNumberToObject(j, "auto_seconds", r.auto_seconds);
            cJSON_AddStringToObject(j, "auto_mode",
                                    r.auto_mode == LUMIS_AUTO_PREDICT ? "predict" : "pilots");
            if (r.auto_mode == LUMIS_AUTO_PREDICT)
                cJSON_AddNumberToObject(j, "auto_diffuse_share", r.auto_diffuse_share);
            cJSON *cands = cJSON_AddArrayToObject(j, "auto_candidates");
            for (int c = 0; c < r.auto_count && c < LUMIS_AUTO_CANDIDATES; c++) {
                const lumis_auto_candidate *q = &r.auto_candidates[c];
                cJSON *jc = cJSON_CreateObject();
                cJSON_AddStringToObject(jc, "name", lumis_auto_candidate_name(c));
                cJSON_AddNumberToObject(jc, "error_per_spp", q->error_per_spp);
                cJSON_AddNumberToObject(jc, "per_spp", q->per_spp);
                cJSON_AddNumberToObject(jc, "efficiency", q->efficiency);
                cJSON_AddNumberToObject(jc, "pilot_spp", q->pilot_spp);
                cJSON_AddItemToArray(cands, jc);
            }
        }
        tool_metrics_json(&m, j);
        rc = tool_write_json(result, j); /* last: its existence marks the item done */
        cJSON_Delete(j);
        fprintf(stderr, "[%d/%d] %s: %d spp in %.2f s, relmse %.4g, flip_ldr %.4f%s\n", index + 1,
                total, it->id, r.stats.spp, r.stats.seconds, m.err.relmse, m.flip_ldr,
                r.contended ? " (contention: the cores were shared)" : "");
    }
    free(map);
    lumis_image_destroy(ref);
    lumis_image_destroy(r.image);
    return rc;
}

/* Decodes every map flagged in need (by its first spec) from the bytes bench_read_inputs
 * kept, once, into images (shared by every map of the same spec), and frees the bytes.
 * The parent does this before it forks: the workers share the pixels copy-on-write rather
 * than each reading the map for every item.  (Decoding leaves no thread behind: the EXR
 * reader's pool lives for one read.)  Exit code. */
static int load_maps(suite *s, const unsigned char *need, lumis_image **images)
{
    int rc = EXIT_OK, loaded = 0;
    double bytes = 0;
    for (int m = 0; m < s->nmaps; m++) {
        suite_map *map = &s->maps[m];
        if (map->first == m && need[m] && rc == EXIT_OK) {
            lumis_status st;
            lumis_read_info info;
            memset(&info, 0, sizeof info);
            if (map->bytes) {
                lumis_read_options ro = {0};
                ro.errors = tool_errors;
                st = lumis_image_read_memory(map->bytes, map->nbytes, LUMIS_FORMAT_AUTO, map->spec,
                                             &ro, &images[m], &info);
                if (st == LUMIS_OK) tool_warn_replaced(map->spec, info.replaced, images[m]);
            } else { /* a procedural spec, or a file that would not open (named by the error) */
                st = tool_load_image(map->spec, &images[m], &info); /* warns itself */
            }
            map->replaced = info.replaced; /* for the items' sidecars */
            if (st != LUMIS_OK) rc = EXIT_RUNTIME;
            if (images[m]) {
                loaded++;
                bytes += 12.0 * images[m]->width * images[m]->height;
            }
        }
        images[m] = images[map->first];
        map->replaced = s->maps[map->first].replaced;
        free(map->bytes);
        map->bytes = NULL;
    }
    if (rc == EXIT_OK)
        fprintf(stderr, "lumis bench: loaded %d map%s (%.1f MB), one read each for the whole run\n",
                loaded, loaded == 1 ? "" : "s", bytes / 1e6);
    return rc;
}

/* The next item from *next on that is in this shard and not done (advancing *next past
 * it), or -1. */
static int next_to_render(const suite *s, const char *out, long shard_i, long shard_n, int *next)
{
    for (const int total = bench_nitems(s); *next < total;) {
        const int k = (*next)++;
        if (!bench_in_shard(s, k, shard_i, shard_n)) continue;
        item it = bench_item_at(s, k);
        if (!bench_item_done(s, out, &it)) return k;
    }
    return -1;
}

/* After an item's process ended: its failure (exit status or signal) written to
 * out/failures/ID.txt, or an earlier failure record removed.  Returns 1 if it failed. */
static int record_outcome(const char *out, const item *it, int status)
{
    char path[9800], dir[8800];
    snprintf(dir, sizeof dir, "%s/failures", out);
    snprintf(path, sizeof path, "%s/%s.txt", dir, it->id);
    const int ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
    if (ok) {
        unlink(path);
        return 0;
    }
    char why[128];
    if (WIFSIGNALED(status))
        snprintf(why, sizeof why, "crashed: signal %d (%s)", WTERMSIG(status),
                 strsignal(WTERMSIG(status)));
    else
        snprintf(why, sizeof why, "failed: exit status %d (its error is above in the log)",
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    fprintf(stderr, "lumis bench: item %s %s\n", it->id, why);
    char text[512];
    const int n = snprintf(text, sizeof text, "%s %s\n", it->id, why);
    if (tool_make_dir(dir) == EXIT_OK) (void)lumis_write_text(path, text, (size_t)n, NULL);
    return 1;
}

/* The items of this shard and those not done yet, on stderr; need[first map] of each item
 * to render set. */
static void plan_items(const suite *s, const bench_run_opts *o, unsigned char *need)
{
    const int total = bench_nitems(s);
    int mine = 0, todo = 0;
    for (int k = 0; k < total; k++)
        if (bench_in_shard(s, k, o->shard_i, o->shard_n)) {
            mine++;
            item it = bench_item_at(s, k);
            if (!bench_item_done(s, o->out, &it)) {
                todo++;
                need[s->maps[it.map].first] = 1;
            }
        }
    fprintf(stderr, "lumis bench: suite %s, %d items (%d in this shard, %d to render)\n", s->name,
            bench_nlisted(s), mine, todo);
}

/* Every scene file read once before anything renders (in a child: reading a scene may
 * acquire a luminaire, with threads), so a malformed one stops the run at once, not after
 * the first reference render. */
static int check_scene_files(const suite *s)
{
    fflush(NULL);
    const pid_t vp = fork();
    if (vp == 0) {
        int vrc = EXIT_OK;
        for (int sc = 0; sc < s->nscenes; sc++) {
            if (!s->scenes[sc].is_file) continue;
            lumis_scene_read_options so = {0};
            so.skip_env_map = 1; /* the maps were read above */
            so.errors = tool_errors;
            so.load_preset = tool_scene_load_preset;
            lumis_scene_file *f = NULL;
            if (lumis_scene_file_read(s->scenes[sc].spec, &so, &f) != LUMIS_OK) vrc = EXIT_RUNTIME;
            lumis_scene_file_destroy(f);
        }
        fflush(NULL);
        _exit(vrc);
    }
    int status = 0;
    if (vp < 0) return tool_runtime_error("bench: fork: %s", strerror(errno));
    if (waitpid(vp, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return tool_runtime_error("bench: a scene of the suite does not read (above): nothing "
                                  "was rendered");
    return EXIT_OK;
}

/* The references of the (map, scene) pairs this shard needs, rendered (or, with
 * --items-only, an error if one is missing).  Runs in the child of render_references. */
static int references_of_shard(const run_ctx *all, const bench_run_opts *o)
{
    const suite *s = all->s;
    const char *out = o->out;
    const int total = bench_nitems(s);
    int rc = EXIT_OK;
    for (int m = 0; m < s->nmaps && rc == EXIT_OK; m++)
        for (int sc = 0; sc < s->nscenes && rc == EXIT_OK; sc++) {
            int need = 0;
            for (int k = 0; k < total && !need; k++) {
                item it = bench_item_at(s, k);
                need = it.map == m && it.scene == sc &&
                       bench_in_shard(s, k, o->shard_i, o->shard_n) &&
                       !bench_item_done(s, out, &it);
            }
            if (need && o->items_only && !bench_reference_ok(s, out, m, sc)) {
                char exr[8800];
                bench_reference_path(s, out, m, sc, exr, sizeof exr);
                rc = tool_runtime_error(
                    "bench: --items-only: the reference of %s / %s (%s) is missing or does "
                    "not read: render the references first (bench --slurm chains their "
                    "jobs before the items')",
                    s->maps[m].label, s->scenes[sc].label, exr);
            } else if (need) {
                rc = ensure_reference(all, m, sc);
            }
        }
    return rc;
}

/* References first, with every thread, for the pairs this shard needs.  With --jobs the
 * parent forks workers afterwards, so it must never start OpenMP's or Embree's threads
 * itself (they do not survive a fork): references are rendered in a child process, always
 * (the items are forked from this process after). */
static int render_references(const run_ctx *all, const bench_run_opts *o)
{
    fflush(NULL);
    const pid_t refs_pid = fork();
    if (refs_pid < 0) return tool_runtime_error("bench: fork: %s", strerror(errno));
    if (refs_pid == 0) {
        const int rc = references_of_shard(all, o);
        fflush(NULL);
        _exit(rc);
    }
    int status = 0;
    if (waitpid(refs_pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return EXIT_RUNTIME;
    return EXIT_OK;
}

/* Items: each in a process of its own (at most --jobs at once), forked from this one,
 * which starts no thread: an item that fails or crashes is recorded with its error in
 * DIR/failures/ID.txt (*failed counts them) and the others go on. */
static int render_items(const run_ctx *c, const bench_run_opts *o, int *failed)
{
    const suite *s = c->s;
    const long jobs = o->jobs;
    const int total = bench_nitems(s);
    int rc = EXIT_OK;
    fflush(NULL);
    pid_t *pids = calloc((size_t)jobs, sizeof *pids);
    int *slot_item = calloc((size_t)jobs, sizeof *slot_item);
    if (!pids || !slot_item) rc = tool_runtime_error("bench: out of memory");
    int next = 0, running = 0;
    while (rc == EXIT_OK) {
        /* fill the free slots with the next items of this shard that are not done */
        for (long j = 0; j < jobs; j++) {
            if (pids[j] > 0) continue;
            const int k = next_to_render(s, o->out, o->shard_i, o->shard_n, &next);
            if (k < 0) break;
            item it = bench_item_at(s, k);
            fflush(NULL);
            const pid_t pid = fork();
            if (pid == 0) {
                const int crc = run_item(c, &it, k, total);
                fflush(NULL);
                _exit(crc);
            }
            if (pid < 0) {
                rc = tool_runtime_error("bench: fork: %s", strerror(errno));
                break;
            }
            pids[j] = pid;
            slot_item[j] = k;
            running++;
        }
        if (running == 0) break;
        int status = 0;
        const pid_t done = waitpid(-1, &status, 0);
        if (done < 0) {
            rc = tool_runtime_error("bench: waitpid: %s", strerror(errno));
            break;
        }
        for (long j = 0; j < jobs; j++)
            if (pids[j] == done) {
                pids[j] = 0;
                running--;
                item it = bench_item_at(s, slot_item[j]);
                *failed += record_outcome(o->out, &it, status);
            }
    }
    /* an error above: the items still running are waited for, not orphaned */
    for (long j = 0; pids && j < jobs; j++)
        if (pids[j] > 0) {
            int status = 0;
            waitpid(pids[j], &status, 0);
        }
    free(pids);
    free(slot_item);
    return rc;
}

int bench_run(suite *s, const bench_run_opts *o, int *failed_items)
{
    *failed_items = 0;
    const long jobs = o->jobs;
    const char *out = o->out;
    lumis_image **images = calloc((size_t)s->nmaps, sizeof *images);
    unsigned char *need = calloc((size_t)s->nmaps, 1);
    if (!images || !need) {
        free(images);
        free(need);
        return tool_runtime_error("bench: out of memory");
    }
    plan_items(s, o, need);
    int rc = load_maps(s, need, images);
    free(need);
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    run_ctx c = {s,       out,
                 images,  (int)(o->threads ? o->threads : (cores > jobs ? cores / jobs : 1)),
                 o->argc, o->argv};
    if (rc == EXIT_OK) rc = check_scene_files(s);
    const int started = rc == EXIT_OK; /* something may render from here on */
    run_ctx rc_all = c;
    rc_all.threads = o->threads;
    if (rc == EXIT_OK) rc = render_references(&rc_all, o);
    int failed = 0;
    if (rc == EXIT_OK) rc = render_items(&c, o, &failed);
    *failed_items = failed;
    if (rc == EXIT_OK && failed > 0) {
        fprintf(stderr,
                "lumis bench: %d item%s failed (their errors are in %s/failures/ and in "
                "results.md); every other item is done; run the same command again to retry "
                "them\n",
                failed, failed == 1 ? "" : "s", out);
        rc = EXIT_RUNTIME;
    } else if (rc != EXIT_OK && started) {
        fprintf(stderr, "lumis bench: stopped; run the same command again to resume\n");
    }
    for (int m = 0; m < s->nmaps; m++)
        if (s->maps[m].first == m) lumis_image_destroy(images[m]);
    free(images);
    return rc;
}

/* Decodes the one map m needs (as bench_run does), for a reference task. */
static int load_one_map(suite *s, int m, lumis_image ***images)
{
    *images = calloc((size_t)s->nmaps, sizeof **images);
    unsigned char *need = calloc((size_t)s->nmaps, 1);
    if (!*images || !need) {
        free(need);
        return tool_runtime_error("bench: out of memory");
    }
    need[s->maps[m].first] = 1;
    const int rc = load_maps(s, need, *images);
    free(need);
    return rc;
}

static void free_maps(const suite *s, lumis_image **images)
{
    for (int m = 0; images && m < s->nmaps; m++)
        if (s->maps[m].first == m) lumis_image_destroy(images[m]);
    free(images);
}

int bench_render_reference_part(suite *s, const bench_run_opts *o, long task, long passes)
{
    const long pairs = (long)s->nmaps * s->nscenes;
    if (task < 0 || task >= pairs * passes)
        return tool_runtime_error("bench: --reference-task %ld: the suite has %ld references of "
                                  "%ld shares, tasks 0 to %ld",
                                  task, pairs, passes, pairs * passes - 1);
    const int pair = (int)(task / passes), pass_i = (int)(task % passes);
    const int m = pair / s->nscenes, sc = pair % s->nscenes;
    if (!bench_pair_needed(s, o->out, m, sc) || bench_reference_ok(s, o->out, m, sc)) {
        fprintf(stderr, "lumis bench: reference %s / %s: done or not needed\n", s->maps[m].label,
                s->scenes[sc].label);
        return EXIT_OK;
    }
    if (bench_reference_part_ok(s, o->out, m, sc, pass_i, passes)) {
        fprintf(stderr, "lumis bench: reference %s / %s: share %d of %ld done before\n",
                s->maps[m].label, s->scenes[sc].label, pass_i, passes);
        return EXIT_OK;
    }
    char dir[8800], exr[8800];
    snprintf(dir, sizeof dir, "%s/refs/parts", o->out);
    if (tool_make_dir(dir) != EXIT_OK) return EXIT_RUNTIME;
    bench_reference_part_path(s, o->out, m, sc, pass_i, passes, exr, sizeof exr);
    lumis_image **images = NULL;
    int rc = load_one_map(s, m, &images);
    if (rc == EXIT_OK) {
        run_ctx c = {s, o->out, images, o->threads, o->argc, o->argv};
        rc = render_reference(&c, m, sc, pass_i, (int)passes, exr, NULL);
    }
    free_maps(s, images);
    return rc;
}

int bench_merge_references(suite *s, const char *out, long passes)
{
    if (passes < 1 || passes > BENCH_REF_PASSES_MAX)
        return tool_runtime_error("bench: 1 to %d reference passes", BENCH_REF_PASSES_MAX);
    /* a path per share, each its own length: P may be large */
    char **parts = calloc((size_t)passes, sizeof *parts);
    const char **in = malloc((size_t)passes * sizeof *in);
    if (!parts || !in) {
        free(parts);
        free(in);
        return tool_runtime_error("bench: out of memory");
    }
    int rc = EXIT_OK, merged = 0, missing = 0;
    for (int m = 0; m < s->nmaps; m++)
        for (int sc = 0; sc < s->nscenes; sc++) {
            if (!bench_pair_needed(s, out, m, sc) || bench_reference_ok(s, out, m, sc)) continue;
            char absent[512] = "";
            for (long i = 0; i < passes; i++) {
                char part[8800];
                bench_reference_part_path(s, out, m, sc, i, passes, part, sizeof part);
                free(parts[i]);
                if (!(parts[i] = malloc(strlen(part) + 1))) {
                    rc = tool_runtime_error("bench: out of memory");
                    break;
                }
                strcpy(parts[i], part);
                in[i] = parts[i];
                if (!bench_reference_part_ok(s, out, m, sc, i, passes))
                    snprintf(absent + strlen(absent), sizeof absent - strlen(absent), "%s%ld",
                             *absent ? ", " : "", i);
            }
            if (rc != EXIT_OK) break;
            if (*absent) {
                tool_runtime_error("bench: the reference of %s / %s lacks its shares %s of %ld "
                                   "(their tasks failed or did not run: see the references' "
                                   "logs); resubmit with the same bench --slurm command",
                                   s->maps[m].label, s->scenes[sc].label, absent, passes);
                missing++;
                continue;
            }
            char exr[8800], side[8900], png[8900];
            bench_reference_path(s, out, m, sc, exr, sizeof exr);
            tool_sidecar_path(exr, side, sizeof side);
            snprintf(png, sizeof png, "%.*s.png", (int)strlen(exr) - 4, exr);
            int mrc = tool_merge_shares(in, (int)passes, exr, side, 1, 0);
            lumis_image *img = NULL;
            if (mrc == EXIT_OK && tool_load_render(exr, &img, NULL) != LUMIS_OK) mrc = EXIT_RUNTIME;
            if (mrc == EXIT_OK) mrc = write_reference_preview(s, png, img);
            lumis_image_destroy(img);
            if (mrc != EXIT_OK) {
                rc = EXIT_RUNTIME;
                continue;
            }
            merged++;
            fprintf(stderr, "lumis bench: reference %s / %s: merged its %ld shares\n",
                    s->maps[m].label, s->scenes[sc].label, passes);
            for (long i = 0; i < passes; i++) { /* the reference has them now */
                char ps[8900];
                tool_sidecar_path(parts[i], ps, sizeof ps);
                unlink(parts[i]);
                unlink(ps);
            }
        }
    for (long i = 0; i < passes; i++) free(parts[i]);
    free(parts);
    free(in);
    fprintf(stderr, "lumis bench: merged %d reference%s%s\n", merged, merged == 1 ? "" : "s",
            missing ? "; some lack shares (above)" : "");
    return missing ? EXIT_RUNTIME : rc;
}
