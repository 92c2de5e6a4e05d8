/* Light-set methods and their parameters by name (lumis/lights.h): the names a host
 * application shows its users, the NAME=VALUE pairs they type, and the build they ask for. */
#include "lumis/lights.h"

#include "../core/internal.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Every name, the descriptor it fills and, for Wu, the ablation and the cut. */
static const struct {
    const char *name;
    lumis_lights_method method;
    lumis_decomp_variant variant;
    lumis_cut_objective cut;
} methods[] = {
    {"median-cut", LUMIS_LIGHTS_MEDIAN_CUT, LUMIS_DECOMP_DEFAULT, LUMIS_CUT_DEFAULT},
    {"variance-min", LUMIS_LIGHTS_VARIANCE_MIN, LUMIS_DECOMP_DEFAULT, LUMIS_CUT_DEFAULT},
    {"fhis", LUMIS_LIGHTS_FHIS, LUMIS_DECOMP_DEFAULT, LUMIS_CUT_DEFAULT},
    {"tmms", LUMIS_LIGHTS_TMMS, LUMIS_DECOMP_DEFAULT, LUMIS_CUT_DEFAULT},
    {"wu", LUMIS_LIGHTS_DECOMPOSITION, LUMIS_DECOMP_FULL, LUMIS_CUT_MODIFIED},
    {"wu-is", LUMIS_LIGHTS_DECOMPOSITION, LUMIS_DECOMP_IS_ONLY, LUMIS_CUT_MODIFIED},
    {"wu-is-mask", LUMIS_LIGHTS_DECOMPOSITION, LUMIS_DECOMP_IS_MASK, LUMIS_CUT_MODIFIED},
    {"wu-is-kmeans", LUMIS_LIGHTS_DECOMPOSITION, LUMIS_DECOMP_IS_KMEANS, LUMIS_CUT_MODIFIED},
    {"wu-original-cut", LUMIS_LIGHTS_DECOMPOSITION, LUMIS_DECOMP_FULL, LUMIS_CUT_ORIGINAL},
};
enum { METHODS = sizeof methods / sizeof methods[0] };

static int method_index(const char *name)
{
    for (int k = 0; name && k < METHODS; k++)
        if (strcmp(methods[k].name, name) == 0) return k;
    return -1;
}

const char *const *lumis_lights_method_names(void)
{
    static const char *names[METHODS + 1];
    if (!names[0])
        for (int k = 0; k < METHODS; k++) names[k] = methods[k].name;
    return names;
}

lumis_status lumis_lights_method_from_name(const char *name, lumis_lights_method *out)
{
    const int k = method_index(name);
    if (k < 0 || !out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = methods[k].method;
    return LUMIS_OK;
}

/* ---- parameters ---------------------------------------------------------------------------
 * Each is a field of a library descriptor whose zero means the default, so a value must be
 * positive (a tiny one would stand for zero). */
enum { FOR_WU = 1, FOR_ALL = 2, FOR_TMMS = 4 };
enum { POSITIVE, FRACTION, PERCENT, COUNT, SEED, MASK };
#define PF(field) offsetof(lumis_light_params, field) /* a float field */
static const struct {
    const char *name;
    int applies, type;
    size_t field; /* POSITIVE, FRACTION, PERCENT: the float it sets */
    const char *what;
} params[] = {
    {"percentile", FOR_WU, PERCENT, PF(wu.percentile), "L_b's percentile of Eq. 1, in (0, 100]"},
    {"lambda", FOR_WU, POSITIVE, PF(wu.lambda), "Eq. 1's lambda, > 0"},
    {"gamma", FOR_WU, POSITIVE, PF(wu.gamma), "Eq. 1's gamma, > 0"},
    {"threshold", FOR_WU, POSITIVE, PF(wu.threshold), "L_T itself instead of Eq. 1, > 0"},
    {"a", FOR_WU, POSITIVE, PF(wu.budget_a), "Eq. 2's exponent a, > 0"},
    {"b", FOR_WU, POSITIVE, PF(wu.budget_b), "Eq. 2's exponent b, > 0"},
    {"s", FOR_WU, POSITIVE, PF(wu.mask_scale), "the mask's s of s * 4 pi / K, > 0"},
    {"mask", FOR_WU, MASK, 0, "cap (solid angle s 4 pi / K) or radians"},
    {"return", FOR_WU, POSITIVE, PF(wu.return_factor),
     "the return distance over the mask radius, > 0"},
    {"kmeans-iterations", FOR_WU, COUNT, 0, "a count in [1, 2^20]"},
    {"wv", FOR_WU, POSITIVE, PF(wu.w_v), "Eq. 3's w_V, > 0"},
    {"wd", FOR_WU, POSITIVE, PF(wu.w_d), "Eq. 3's w_D, > 0"},
    {"we", FOR_WU, POSITIVE, PF(wu.w_e), "Eq. 3's w_E, > 0"},
    {"jitter", FOR_ALL, FRACTION, PF(jitter), "a fraction of each light's extent, in (0, 1]"},
    {"seed", FOR_ALL, SEED, 0, "an unsigned integer"},
    {"key", FOR_TMMS, POSITIVE, PF(key), "the tone-mapping key, > 0"},
    {"bandwidth", FOR_TMMS, FRACTION, PF(bandwidth), "the range bandwidth, in (0, 1]"},
    {"min-share", FOR_WU, FRACTION, PF(wu.min_share),
     "each class's least share of the lights over its share of the power, in (0, 1]"},
};
#undef PF
enum { PARAMS = sizeof params / sizeof params[0] };
_Static_assert(PARAMS <= 32, "a bit per parameter in lumis_light_params.given");

static float *float_field(lumis_light_params *p, int q)
{
    return (float *)(void *)((char *)p + params[q].field);
}

static float float_value(const lumis_light_params *p, int q)
{
    return *(const float *)(const void *)((const char *)p + params[q].field);
}

/* Strict numbers: the whole text, no blanks, finite; a count in [lo, hi]; an unsigned
 * integer that starts with a digit (strtoull takes "-5" as 2^64 - 5). */
static int parse_double(const char *s, double *out)
{
    if (!*s) return 0;
    char *end;
    errno = 0;
    const double v = strtod(s, &end);
    if (*end != '\0' || errno == ERANGE || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

static int parse_count(const char *s, long lo, long hi, long *out)
{
    if (!*s) return 0;
    char *end;
    errno = 0;
    const long v = strtol(s, &end, 10);
    if (*end != '\0' || errno == ERANGE || v < lo || v > hi) return 0;
    *out = v;
    return 1;
}

static int parse_u64(const char *s, uint64_t *out)
{
    if (!(*s >= '0' && *s <= '9')) return 0;
    char *end;
    errno = 0;
    const unsigned long long v = strtoull(s, &end, 10);
    if (*end != '\0' || errno == ERANGE) return 0;
    *out = (uint64_t)v;
    return 1;
}

/* One NAME=VALUE (item: NAME=VALUE, NUL-terminated, writable). */
static lumis_status parse_pair(lumis_light_params *p, char *item, const lumis_error_sink *errors)
{
    char *eq = strchr(item, '=');
    if (!eq) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "'%s' is not NAME=VALUE", item);
    *eq = '\0';
    const char *value = eq + 1;
    int q = 0;
    while (q < PARAMS && strcmp(params[q].name, item) != 0) q++;
    if (q == PARAMS) {
        char names[512] = "";
        for (int n = 0; n < PARAMS; n++) {
            strcat(names, n ? ", " : "");
            strcat(names, params[n].name);
        }
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "unknown parameter '%s' (known: %s)",
                           item, names);
    }
    const int type = params[q].type;
    double x = 0.0;
    long n = 0;
    int ok;
    if (type == MASK) {
        ok = strcmp(value, "cap") == 0 || strcmp(value, "radians") == 0;
        if (ok)
            p->wu.mask_radius = value[0] == 'c' ? LUMIS_MASK_CAP_SOLID_ANGLE : LUMIS_MASK_RADIANS;
    } else if (type == COUNT) {
        ok = parse_count(value, 1, 1 << 20, &n);
        if (ok) p->wu.kmeans_max_iterations = (int)n;
    } else if (type == SEED) {
        ok = parse_u64(value, &p->seed);
    } else {
        ok = parse_double(value, &x) && x > 0.0 && x <= FLT_MAX && (float)x > 0.0f;
        if (type == FRACTION) ok = ok && x <= 1.0;
        if (type == PERCENT) ok = ok && x <= 100.0;
        if (ok) *float_field(p, q) = (float)x;
    }
    if (!ok) {
        /* a positive number that a float cannot hold: say that, not "needs > 0" */
        const int number = type != COUNT && type != SEED && type != MASK && parse_double(value, &x);
        const int tiny = number && x > 0.0 && (float)x == 0.0f, huge = number && x > FLT_MAX;
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "%s=VALUE needs %s%s, not '%s'",
                           item, params[q].what,
                           tiny   ? " (and at least 1.2e-38: the parameters are floats)"
                           : huge ? " (and at most 3.4e38: the parameters are floats)"
                                  : "",
                           value);
    }
    p->given |= 1u << q;
    return LUMIS_OK;
}

lumis_status lumis_light_params_parse(lumis_light_params *p, const char *text,
                                      const lumis_error_sink *errors)
{
    if (!p) return LUMIS_ERR_INVALID_ARGUMENT;
    if (!text || !*text)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "needs NAME=VALUE[,NAME=VALUE...]");
    char buf[1024];
    if (strlen(text) >= sizeof buf)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "parameters too long (%zu bytes)",
                           strlen(text));
    strcpy(buf, text);
    char *item = buf;
    for (;;) { /* pairs split at commas (an empty one is not NAME=VALUE) */
        char *comma = strchr(item, ',');
        if (comma) *comma = '\0';
        if (*item) { /* empty pairs (",,") are skipped */
            const lumis_status st = parse_pair(p, item, errors);
            if (st != LUMIS_OK) return st;
        }
        if (!comma) return LUMIS_OK;
        item = comma + 1;
    }
}

lumis_status lumis_light_params_check(const lumis_light_params *p, const char *method,
                                      const lumis_error_sink *errors)
{
    const int k = method_index(method);
    if (!p || k < 0)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "unknown light-set method '%s'",
                           method ? method : "(none)");
    const int wu = methods[k].method == LUMIS_LIGHTS_DECOMPOSITION,
              tmms = methods[k].method == LUMIS_LIGHTS_TMMS;
    for (int q = 0; q < PARAMS; q++) {
        if (!(p->given & (1u << q))) continue;
        const int a = params[q].applies;
        if (a == FOR_ALL || (a == FOR_WU && wu) || (a == FOR_TMMS && tmms)) continue;
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "'%s' is a parameter of %s, not of %s", params[q].name,
                           a == FOR_WU ? "Wu's decomposition (wu...)" : "tmms", method);
    }
    return LUMIS_OK;
}

void lumis_light_params_format(const lumis_light_params *p, char *buf, size_t cap)
{
    if (!buf || cap == 0) return;
    size_t len = 0;
    buf[0] = '\0';
    for (int q = 0; p && q < PARAMS && len < cap; q++) {
        if (!(p->given & (1u << q))) continue;
        const char *sep = len ? "," : "";
        const int type = params[q].type;
        int w;
        if (type == MASK)
            w = snprintf(buf + len, cap - len, "%s%s=%s", sep, params[q].name,
                         p->wu.mask_radius == LUMIS_MASK_RADIANS ? "radians" : "cap");
        else if (type == COUNT)
            w = snprintf(buf + len, cap - len, "%s%s=%d", sep, params[q].name,
                         p->wu.kmeans_max_iterations);
        else if (type == SEED)
            w = snprintf(buf + len, cap - len, "%s%s=%llu", sep, params[q].name,
                         (unsigned long long)p->seed);
        else { /* the shortest decimal that reads back as the same float */
            const float f = float_value(p, q);
            char num[32];
            for (int digits = 6; digits <= 9; digits++) {
                snprintf(num, sizeof num, "%.*g", digits, (double)f);
                if (strtof(num, NULL) == f) break;
            }
            w = snprintf(buf + len, cap - len, "%s%s=%s", sep, params[q].name, num);
        }
        if (w < 0) break;
        len += (size_t)w;
    }
}

lumis_status lumis_lights_by_name(const lumis_envmap *env, const char *method, int count, int sets,
                                  const lumis_light_params *params_in,
                                  const lumis_error_sink *errors, lumis_light_set **out)
{
    static const lumis_light_params defaults;
    const lumis_light_params *p = params_in ? params_in : &defaults;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    const int k = method_index(method);
    if (k < 0)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "unknown light-set method '%s'",
                           method ? method : "(none)");
    const lumis_error_sink none = {0};
    const lumis_error_sink sink = errors ? *errors : none;
    switch (methods[k].method) {
    case LUMIS_LIGHTS_DECOMPOSITION: {
        lumis_decomp_desc d = p->wu;
        d.count = count;
        d.sets = sets;
        d.jitter = p->jitter;
        d.seed = p->seed;
        d.variant = methods[k].variant;
        d.cut = methods[k].cut;
        d.errors = sink;
        return lumis_lights_decompose(env, &d, out);
    }
    case LUMIS_LIGHTS_TMMS: {
        lumis_tmms_desc d = {0};
        d.count = count;
        d.sets = sets;
        d.jitter = p->jitter;
        d.seed = p->seed;
        d.key = p->key;
        d.range_bandwidth = p->bandwidth;
        d.errors = sink;
        return lumis_lights_tmms(env, &d, out);
    }
    default: {
        lumis_median_cut_desc d = {0};
        d.count = count;
        d.sets = sets;
        d.jitter = p->jitter;
        d.seed = p->seed;
        d.errors = sink;
        if (methods[k].method == LUMIS_LIGHTS_MEDIAN_CUT)
            return lumis_lights_median_cut(env, &d, out);
        if (methods[k].method == LUMIS_LIGHTS_FHIS) return lumis_lights_fhis(env, &d, out);
        return lumis_lights_variance_min(env, &d, out);
    }
    }
}
