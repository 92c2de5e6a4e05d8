/* lumis sample MAP --method M -n N ... and lumis pdf MAP --method M ...: the samplers on
 * the command line, in the exact text forms other tools read. */
#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char sampler_options[] =
    "sampler options:\n"
    "  --method M               inversion, inversion-guided (default), alias, kdtree,\n"
    "                           kdtree-exact, hierarchical, uniform\n"
    "  --blocks K               kd-tree blocks (default 6144)\n"
    "  --kdtree-uniform-angles  the paper's literal in-block warp (uniform in angles)\n"
    "  --compensate             MIS compensation (Karlik et al. 2019)\n"
    "  --importance I           luminance (default), average or max-channel\n"
    "  --rotate DEG             rotate the map about +y\n";

static const char sample_usage[] =
    "usage: lumis sample MAP --method M -n N [--seed S] [sampler options]\n\n"
    "Prints N lines 'x y z pdf r g b': a unit direction, its density per steradian and\n"
    "the map's radiance there.  Uniform numbers come from PCG32 seeded with S (default 1),\n"
    "two 53-bit doubles per sample, so the output is reproducible.\n\n";

static const char pdf_usage[] =
    "usage: lumis pdf MAP --method M [sampler options] < directions\n\n"
    "Reads lines 'x y z' (need not be normalized) from stdin and prints 'pdf r g b' for each:\n"
    "the density per steradian of sampling that direction, and the radiance there.\n\n";

static int parse_common(const char *cmd, int argc, char **argv, const char *usage, int is_sample,
                        const char **map, lumis_sampler_desc *d, float *rot, long *n,
                        unsigned long long *seed)
{
    const char *v;
    for (int i = 1; i < argc; i++) {
        int rc = tool_sampler_option(cmd, argc, argv, &i, d, rot);
        if (rc > 0) return rc;
        if (rc == 0) continue;
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            fputs(sampler_options, stdout);
            return -1;
        } else if (is_sample && tool_option(argc, argv, &i, "-n", &v)) {
            if (!tool_parse_int(v, 0, 1000000000L, n))
                return tool_bad_value(cmd, "-n", v, "needs a sample count in [0, 10^9]");
        } else if (is_sample && tool_option(argc, argv, &i, "--seed", &v)) {
            if (!tool_parse_u64(v, 10, seed))
                return tool_bad_value(cmd, "--seed", v, "needs an integer in [0, 2^64 - 1]");
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return tool_usage_error(cmd, "unknown option '%s'", argv[i]);
        } else if (!*map) {
            *map = argv[i];
        } else {
            return tool_usage_error(cmd, "one map at a time (got '%s' and '%s')", *map, argv[i]);
        }
    }
    if (!*map) return tool_usage_error(cmd, "no map given");
    if (is_sample && *n < 0) return tool_usage_error(cmd, "-n N is required");
    return EXIT_OK;
}

int cmd_sample(int argc, char **argv)
{
    const char *map = NULL;
    lumis_sampler_desc d = {0};
    float rot = 0.0f;
    long n = -1;
    unsigned long long seed = 1;
    int rc = parse_common("sample", argc, argv, sample_usage, 1, &map, &d, &rot, &n, &seed);
    if (rc) return rc < 0 ? EXIT_OK : rc;
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
    const char *map = NULL;
    lumis_sampler_desc d = {0};
    float rot = 0.0f;
    long n = 0;
    unsigned long long seed = 0;
    int rc = parse_common("pdf", argc, argv, pdf_usage, 0, &map, &d, &rot, &n, &seed);
    if (rc) return rc < 0 ? EXIT_OK : rc;
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
