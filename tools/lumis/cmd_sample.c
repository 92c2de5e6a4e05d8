/* lumis sample MAP --method M -n N ... and lumis pdf MAP --method M ...: the samplers on
 * the command line, in the exact text forms other tools read. */
#include "cli.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* What sample and pdf read from their arguments. */
typedef struct sample_cli {
    const char *map;
    lumis_sampler_desc d;
    float rot;
    long n;
    unsigned long long seed;
} sample_cli;

static int parse_method(const char *v, void *field)
{
    return lumis_sampler_method_from_name(v, field) == LUMIS_OK;
}

static int parse_importance(const char *v, void *field)
{
    static const char *const names[] = {"luminance", "average", "max-channel"};
    static const lumis_importance values[] = {LUMIS_IMPORTANCE_LUMINANCE, LUMIS_IMPORTANCE_AVERAGE,
                                              LUMIS_IMPORTANCE_MAX_CHANNEL};
    for (int k = 0; k < 3; k++)
        if (strcmp(v, names[k]) == 0) {
            *(lumis_importance *)field = values[k];
            return 1;
        }
    return 0;
}

static int sample_positional(const char *cmd, const char *arg, void *ctx)
{
    sample_cli *c = ctx;
    if (c->map) return tool_usage_error(cmd, "one map at a time (got '%s' and '%s')", c->map, arg);
    c->map = arg;
    return EXIT_OK;
}

#define AT(f) offsetof(sample_cli, f)
/* The sampler's options, sample's and pdf's alike. */
#define SAMPLER_OPTIONS                                                                            \
    {.kind = TOOL_OPT_GROUP, .name = "sampler options"},                                           \
        {.kind = TOOL_OPT_PARSE,                                                                   \
         .name = "--method",                                                                       \
         .metavar = "M",                                                                           \
         .help = "inversion, inversion-guided (default), alias, kdtree,\n"                         \
                 "kdtree-exact, hierarchical, uniform",                                            \
         .at = AT(d.method),                                                                       \
         .parse = parse_method,                                                                    \
         .what = "must be one of inversion, inversion-guided, alias, kdtree, kdtree-exact, "       \
                 "hierarchical, uniform"},                                                         \
        {.kind = TOOL_OPT_INT,                                                                     \
         .name = "--blocks",                                                                       \
         .metavar = "K",                                                                           \
         .help = "kd-tree blocks (default 6144)",                                                  \
         .at = AT(d.kdtree_blocks),                                                                \
         .lo = 1,                                                                                  \
         .hi = 1 << 24},                                                                           \
        {.kind = TOOL_OPT_FLAG,                                                                    \
         .name = "--kdtree-uniform-angles",                                                        \
         .help = "the paper's literal in-block warp (uniform in angles)",                          \
         .at = AT(d.kdtree_uniform_angles)},                                                       \
        {.kind = TOOL_OPT_FLAG,                                                                    \
         .name = "--compensate",                                                                   \
         .help = "MIS compensation (Karlik et al. 2019)",                                          \
         .at = AT(d.compensate)},                                                                  \
        {.kind = TOOL_OPT_PARSE,                                                                   \
         .name = "--importance",                                                                   \
         .metavar = "I",                                                                           \
         .help = "luminance (default), average or max-channel",                                    \
         .at = AT(d.importance),                                                                   \
         .parse = parse_importance,                                                                \
         .what = "must be luminance, average or max-channel"},                                     \
    {                                                                                              \
        .kind = TOOL_OPT_FLOAT, .name = "--rotate", .metavar = "DEG",                              \
        .help = "rotate the map about +y", .at = AT(rot), .lo = -1e6, .hi = 1e6, .what = "degrees" \
    }

static const tool_opt sample_table[] = {
    {.kind = TOOL_OPT_LONG,
     .name = "-n",
     .metavar = "N",
     .help = "samples to draw (required)",
     .at = AT(n),
     .lo = 0,
     .hi = 1000000000,
     .what = "a sample count"},
    {.kind = TOOL_OPT_U64,
     .name = "--seed",
     .metavar = "S",
     .help = "PCG32's seed (default 1)",
     .at = AT(seed)},
    SAMPLER_OPTIONS,
    {0},
};

static const tool_opt pdf_table[] = {SAMPLER_OPTIONS, {0}};

const tool_optspec tool_sample_spec = {
    .cmd = "sample",
    .usage = "usage: lumis sample MAP --method M -n N [--seed S] [sampler options]",
    .intro =
        "Prints N lines 'x y z pdf r g b': a unit direction, its density per steradian and\n"
        "the map's radiance there.  Uniform numbers come from PCG32 seeded with S (default 1),\n"
        "two 53-bit doubles per sample, so the output is reproducible.",
    .opts = sample_table,
    .positional = sample_positional,
};

const tool_optspec tool_pdf_spec = {
    .cmd = "pdf",
    .usage = "usage: lumis pdf MAP --method M [sampler options] < directions",
    .intro =
        "Reads lines 'x y z' (need not be normalized) from stdin and prints 'pdf r g b' for each:\n"
        "the density per steradian of sampling that direction, and the radiance there.",
    .opts = pdf_table,
    .positional = sample_positional,
};

/* The arguments into c.  -1 to go on, else an exit code. */
static int parse_common(const tool_optspec *spec, int argc, char **argv, sample_cli *c)
{
    const int rc = tool_optparse(spec, argc, argv, c);
    if (rc >= 0) return rc;
    if (!c->map) return tool_usage_error(spec->cmd, "no map given");
    if (spec == &tool_sample_spec && c->n < 0)
        return tool_usage_error(spec->cmd, "-n N is required");
    return -1;
}

int cmd_sample(int argc, char **argv)
{
    sample_cli c = {.n = -1, .seed = 1};
    const int rc = parse_common(&tool_sample_spec, argc, argv, &c);
    if (rc >= 0) return rc;
    const char *map = c.map;
    lumis_sampler_desc d = c.d;
    const float rot = c.rot;
    const long n = c.n;
    const unsigned long long seed = c.seed;
    lumis_envmap *env;
    lumis_sampler *s;
    if (tool_make_sampler(map, rot, 1.0f, &d, &env, &s) != LUMIS_OK) return EXIT_RUNTIME;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, seed, 0);
    for (long k = 0; k < n; k++) {
        double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
        lumis_env_sample e = lumis_sampler_sample(s, u1, u2);
        printf("%.9g %.9g %.9g %.9g %.9g %.9g %.9g\n", e.dir.x, e.dir.y, e.dir.z, e.pdf,
               e.radiance.r, e.radiance.g, e.radiance.b);
    }
    lumis_sampler_destroy(s);
    lumis_envmap_destroy(env);
    return fflush(stdout) == 0 && !ferror(stdout) ? EXIT_OK
                                                  : tool_runtime_error("write error on stdout");
}

int cmd_pdf(int argc, char **argv)
{
    sample_cli c = {0};
    int rc = parse_common(&tool_pdf_spec, argc, argv, &c);
    if (rc >= 0) return rc;
    const char *map = c.map;
    lumis_sampler_desc d = c.d;
    const float rot = c.rot;
    lumis_envmap *env;
    lumis_sampler *s;
    if (tool_make_sampler(map, rot, 1.0f, &d, &env, &s) != LUMIS_OK) return EXIT_RUNTIME;
    char line[512];
    long lineno = 0;
    rc = EXIT_OK;
    while (fgets(line, sizeof line, stdin)) {
        lineno++;
        double x, y, z;
        char extra;
        if (line[0] == '\n' || line[0] == '#') continue;
        if (sscanf(line, "%lf %lf %lf %c", &x, &y, &z, &extra) != 3) {
            rc = tool_runtime_error("stdin line %ld: expected 'x y z'", lineno);
            break;
        }
        const double len2 = x * x + y * y + z * z;
        if (!(len2 > 1e-30) || !isfinite(len2)) {
            rc = tool_runtime_error("stdin line %ld: the direction (%g %g %g) has no finite, "
                                    "nonzero length",
                                    lineno, x, y, z);
            break;
        }
        lumis_vec3 dir = {(float)x, (float)y, (float)z};
        float p = lumis_sampler_pdf(s, dir);
        lumis_rgb L = lumis_envmap_eval(env, dir);
        printf("%.9g %.9g %.9g %.9g\n", p, L.r, L.g, L.b);
    }
    lumis_sampler_destroy(s);
    lumis_envmap_destroy(env);
    return rc;
}
