/* Loading what a command reads: maps (files or procedural specs), envmaps, samplers,
 * luminaires (presets through the cache of acquired ones), and the preview's exposure. */
#include "errors.h"
#include "files.h"
#include "load.h"
#include "lights.h"

#include "lumis/metrics.h"
#include "lumis/render.h"

#include <cJSON.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- maps and samplers ------------------------------------------------------------------- */

/* Tiny negatives (compression noise, in most real HDRIs) are a one-line note that
 * LUMIS_NOTES=0 silences; NaN, Inf and negatives of consequence are a warning naming the
 * worst pixel; saturated spikes (lumis_image_spikes) are named one by one. */
static void warn(const char *what, lumis_replaced r, const lumis_image *img, int spikes)
{
    double mean = 0.0;
    if (img) {
        const size_t n = (size_t)img->width * (size_t)img->height;
        for (size_t k = 0; k < n; k++)
            mean += 0.2126 * img->pixels[3 * k] + 0.7152 * img->pixels[3 * k + 1] +
                    0.0722 * img->pixels[3 * k + 2];
        mean /= (double)(n ? n : 1);
    }
    if (lumis_replaced_total(r)) {
        const char *quiet = getenv("LUMIS_NOTES");
        /* what the negatives held, against the map's whole: under 1e-4 of it is noise */
        const double total = mean * (img ? (double)img->width * (double)img->height : 0.0);
        const int tiny = r.nan == 0 && r.inf == 0 && img && -r.negative_sum <= 1e-4 * total;
        const int w = img && img->width > 0 ? img->width : 1;
        const unsigned long long px = (unsigned long long)(r.negative_min_at / 3);
        if (tiny && !(quiet && strcmp(quiet, "0") == 0))
            fprintf(stderr,
                    "lumis: note: %s: %llu small negative values (down to %.3g; %.2g of the map's "
                    "sum: compression noise) replaced by 0 (LUMIS_NOTES=0 silences this)\n",
                    what, (unsigned long long)r.negative, (double)r.negative_min,
                    -r.negative_sum / (total > 0 ? total : 1));
        else if (!tiny)
            fprintf(stderr,
                    "lumis: warning: %s: %llu channel values replaced by 0 (NaN %llu, Inf %llu, "
                    "negative %llu%s",
                    what, (unsigned long long)lumis_replaced_total(r), (unsigned long long)r.nan,
                    (unsigned long long)r.inf, (unsigned long long)r.negative,
                    r.negative ? "" : ")\n");
        if (!tiny && r.negative)
            fprintf(stderr, ", the worst %.4g at pixel (%llu, %llu); %.2g of the map's sum)\n",
                    (double)r.negative_min, px % (unsigned long long)w, px / (unsigned long long)w,
                    -r.negative_sum / (total > 0 ? total : 1));
    }
    if (!img || !spikes) return;
    lumis_spike sp[3];
    const int n = lumis_image_spikes(img, sp, 3);
    for (int k = 0; k < n && k < 3; k++) {
        const float *p = img->pixels + 3 * ((size_t)sp[k].y * (size_t)img->width + (size_t)sp[k].x);
        fprintf(stderr,
                "lumis: warning: %s: pixel (%d, %d) = (%.4g, %.4g, %.4g) is a saturated spike, "
                "%.3g x its neighbours: no camera makes one (a broken compression block?); it "
                "will draw samples as a light would\n",
                what, sp[k].x, sp[k].y, (double)p[0], (double)p[1], (double)p[2],
                (double)sp[k].ratio);
    }
    if (n > 3) fprintf(stderr, "lumis: warning: %s: %d more such spikes\n", what, n - 3);
}

void tool_warn_replaced(const char *what, lumis_replaced r, const lumis_image *img)
{
    warn(what, r, img, 1);
}

static lumis_status load(const char *spec, lumis_image **out, lumis_read_info *info, int is_map)
{
    lumis_read_options opt = {0};
    opt.errors = tool_errors;
    lumis_read_info local;
    if (!info) info = &local;
    const lumis_status st = lumis_map_read(spec, &opt, out, info);
    /* every command says what it replaced: a NaN read as 0 changes a render or a score; a
     * spike is named only in a map, where it would draw samples (a render's fireflies are
     * its estimator's, and a dark reference's bright pixel is no camera's fault) */
    if (st == LUMIS_OK) warn(spec, info->replaced, *out, is_map);
    return st;
}

lumis_status tool_load_image(const char *spec, lumis_image **out, lumis_read_info *info)
{
    return load(spec, out, info, 1);
}

lumis_status tool_load_render(const char *path, lumis_image **out, lumis_read_info *info)
{
    return load(path, out, info, 0);
}

lumis_status tool_make_envmap(const char *spec, const lumis_image *preloaded, float rotation,
                              float scale, lumis_envmap **env, lumis_replaced *replaced)
{
    lumis_image *img = NULL;
    *env = NULL;
    if (!preloaded) {
        lumis_read_info info;
        lumis_status st = tool_load_image(spec, &img, &info);
        if (st == LUMIS_OK && replaced) *replaced = info.replaced;
        if (st != LUMIS_OK) return st;
        preloaded = img;
    }
    lumis_envmap_desc ed = {0};
    ed.pixels = preloaded->pixels;
    ed.width = preloaded->width;
    ed.height = preloaded->height;
    ed.rotation_deg = rotation;
    ed.scale = scale;
    ed.errors = tool_errors;
    lumis_status st = lumis_envmap_create(&ed, env);
    lumis_image_destroy(img);
    return st;
}

lumis_status tool_make_sampler(const char *spec, float rotation, float scale,
                               const lumis_sampler_desc *desc, lumis_envmap **env,
                               lumis_sampler **sampler)
{
    *sampler = NULL;
    lumis_status st = tool_make_envmap(spec, NULL, rotation, scale, env, NULL);
    if (st != LUMIS_OK) return st;
    lumis_sampler_desc d = *desc;
    d.errors = tool_errors;
    st = lumis_sampler_create(*env, &d, sampler);
    if (st != LUMIS_OK) {
        lumis_envmap_destroy(*env);
        *env = NULL;
    }
    return st;
}

/* "auto" exposure: the stops that bring the reference's mean luminance to 0.18. */
/* What shapes an acquired preset: its name, the library's version and the numbers of its
 * layout and emitter (field by field: no padding bytes). */
static uint64_t preset_key(const char *name, lumis_luminaire_preset preset)
{
    lumis_luminaire_desc l;
    lumis_emitter_desc e;
    lumis_emitter_disk disks[16];
    uint64_t h = 0xcbf29ce484222325ull;
    h = tool_fnv(h, name, strlen(name));
    h = tool_fnv(h, LUMIS_VERSION_STRING, strlen(LUMIS_VERSION_STRING));
    if (lumis_luminaire_preset_get(preset, &l, &e, disks) != LUMIS_OK) return h;
    const double g[] = {l.delta,           l.grid_origin[0],  l.grid_origin[1],  l.grid_spacing[0],
                        l.grid_spacing[1], l.image_origin[0], l.image_origin[1], l.image_size[0],
                        l.image_size[1],   e.plate_z,         e.period[0],       e.period[1],
                        e.contrast,        e.tint.r,          e.tint.g,          e.tint.b};
    const int n[] = {(int)l.basis, l.grid[0],    l.grid[1],     l.width,
                     l.height,     e.disk_count, (int)e.pattern};
    h = tool_fnv(h, g, sizeof g);
    h = tool_fnv(h, n, sizeof n);
    for (int k = 0; k < e.disk_count && k < 16; k++) {
        const double dk[] = {disks[k].center[0],  disks[k].center[1],  disks[k].center[2],
                             disks[k].radius,     disks[k].radiance.r, disks[k].radiance.g,
                             disks[k].radiance.b, disks[k].exponent};
        h = tool_fnv(h, dk, sizeof dk);
    }
    return h;
}

/* Acquiring a preset takes seconds (the car: ~10 s), so what was acquired is kept under
 * $XDG_CACHE_HOME/lumis (else ~/.cache/lumis), one luminaire file per key, written
 * atomically and checked on read (its pixels' digest); LUMIS_NO_CACHE=1 turns it off.  A
 * cache that cannot be written or read is only a note: the preset is acquired. */
static lumis_status load_preset(const char *spec, lumis_luminaire_preset preset,
                                lumis_luminaire **out)
{
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME"),
               *off = getenv("LUMIS_NO_CACHE");
    char dir[2048] = "", path[2300] = "";
    if (!(off && *off && strcmp(off, "0") != 0)) {
        if (xdg && xdg[0] == '/')
            snprintf(dir, sizeof dir, "%s/lumis", xdg);
        else if (home && home[0] == '/')
            snprintf(dir, sizeof dir, "%s/.cache/lumis", home);
    }
    if (dir[0]) {
        snprintf(path, sizeof path, "%s/%s-%016llx.json", dir, spec + 7,
                 (unsigned long long)preset_key(spec + 7, preset));
        struct stat sb;
        if (stat(path, &sb) == 0) {
            lumis_luminaire_read_options ro = {0}; /* quiet: a bad entry is replaced */
            if (lumis_luminaire_read(path, &ro, out) == LUMIS_OK) return LUMIS_OK;
            fprintf(stderr, "lumis: the cached %s (%s) does not read back: acquiring it again\n",
                    spec, path);
        }
    }
    fprintf(stderr, "lumis: acquiring %s from its emitter (seconds)%s%s ...\n", spec,
            dir[0] ? "; kept for later runs in " : "", dir);
    lumis_status st = lumis_luminaire_preset_create(preset, LUMIS_BASIS_DEFAULT, &tool_errors, out);
    if (st != LUMIS_OK || !dir[0]) return st;
    /* the cache folder, then the luminaire (its manifest last) */
    if (tool_make_dir(dir) != EXIT_OK) {
        fprintf(stderr, "lumis: note: could not cache %s in %s\n", spec, dir);
        return LUMIS_OK;
    }
    lumis_luminaire_write_options wo = {0};
    wo.image_format = LUMIS_FORMAT_PFM; /* lossless and fast to read */
    if (lumis_luminaire_write(path, *out, &wo) != LUMIS_OK)
        fprintf(stderr, "lumis: note: could not cache %s in %s\n", spec, dir);
    return LUMIS_OK;
}

lumis_status tool_scene_load_preset(void *user, const char *spec, lumis_luminaire **out)
{
    (void)user;
    return tool_load_luminaire(spec, out);
}

lumis_status tool_load_luminaire(const char *spec, lumis_luminaire **out)
{
    if (strncmp(spec, "preset:", 7) == 0) {
        lumis_luminaire_preset preset;
        if (lumis_luminaire_preset_from_name(spec + 7, &preset) != LUMIS_OK) {
            tool_runtime_error("%s: unknown preset (preset:car, preset:bike or preset:small)",
                               spec);
            return LUMIS_ERR_INVALID_ARGUMENT;
        }
        return load_preset(spec, preset, out);
    }
    /* A manifest is JSON; a file that is not, but reads as IES or EULUMDAT, is a fixture:
     * point at the commands that take one rather than report "malformed JSON". */
    FILE *fp = fopen(spec, "rb");
    int c = EOF;
    if (fp) {
        do c = fgetc(fp);
        while (c == ' ' || c == '\t' || c == '\r' || c == '\n');
        fclose(fp);
    }
    lumis_photometric_file *pf = NULL;
    if (c != EOF && c != '{' && lumis_photometric_read(spec, NULL, &pf) == LUMIS_OK) {
        lumis_photometric_file_destroy(pf);
        tool_runtime_error("%s is a photometric file (IES or EULUMDAT), not a light-field "
                           "luminaire: 'lumis info %s' describes it, a scene file or render "
                           "--fixture places it, and 'lumis luminaire create OUT.json --from "
                           "%s' makes its light field",
                           spec, spec, spec);
        return LUMIS_ERR_INVALID_ARGUMENT;
    }
    lumis_luminaire_read_options ro = {0};
    ro.errors = tool_errors;
    return lumis_luminaire_read(spec, &ro, out);
}

float tool_auto_exposure(const lumis_image *ref)
{
    double sum = 0.0;
    const size_t n = (size_t)ref->width * (size_t)ref->height;
    for (size_t p = 0; p < n; p++) {
        const float *q = ref->pixels + 3 * p;
        sum += 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
    }
    double mean = sum / (double)n;
    return mean > 0.0 ? (float)log2(0.18 / mean) : 0.0f;
}
