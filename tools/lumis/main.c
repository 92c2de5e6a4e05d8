/* lumis: command-line front end.  Each subcommand lives in its own cmd_*.c file. */
#include "cli.h"

#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>

static const tool_command commands[] = {
    {"info", "statistics of an environment map (resolution, luminance, power, top shares)",
     cmd_info},
    {"convert", "convert between EXR, HDR, PFM and PNG; expose, tone map, resize", cmd_convert},
    {"sky", "write a procedural clear sky (Preetham et al. 1999) with a sun", cmd_sky},
    {"studio", "write a procedural studio map (dark surround, soft boxes)", cmd_studio},
    {"sample", "draw directions from a map with a sampler: 'x y z pdf r g b' lines", cmd_sample},
    {"pdf", "densities of directions read from stdin: 'pdf r g b' lines", cmd_pdf},
    {"bench-samplers", "build time, memory, speed and quality of every sampler",
     cmd_bench_samplers},
    {"render", "render a scene lit by a map (light, BSDF or MIS sampling; path tracing)",
     cmd_render},
    {"lights", "an environment map as K directional lights: JSON, glTF, a picture", cmd_lights},
    {"luminaire", "light-field luminaires: create one by simulated acquisition, inspect, render",
     cmd_luminaire},
    {"merge", "join the shares of a render split by passes (render --passes I/N)", cmd_merge},
    {"compare", "image metrics: RMSE, relMSE, PSNR, CIELAB, LDR- and HDR-FLIP; error maps",
     cmd_compare},
    {"bench", "run a benchmark suite: renders, references, metrics, tables, plots, HTML",
     cmd_bench},
    {"demo", "the default sky, its info, and spheres by inversion and kd-tree at equal time",
     cmd_demo},
};
enum { NCOMMANDS = sizeof commands / sizeof commands[0] };

const tool_optspec *const tool_option_specs[] = {
    &tool_info_spec,
    &tool_convert_spec,
    &tool_sky_spec,
    &tool_studio_spec,
    &tool_sample_spec,
    &tool_pdf_spec,
    &tool_bench_samplers_spec,
    &tool_render_spec,
    &tool_lights_spec,
    &tool_luminaire_create_spec,
    &tool_luminaire_info_spec,
    &tool_luminaire_predict_spec,
    &tool_merge_spec,
    &tool_compare_spec,
    &tool_bench_spec,
    &tool_demo_spec,
    NULL,
};

/* lumis help --markdown [CMD]: the option tables as Markdown (docs/options.md is all of them). */
static int markdown_help(const char *cmd)
{
    int found = 0;
    if (!cmd)
        printf("# lumis's options\n\n"
               "Generated from the option tables of tools/lumis (`make options-doc`, which runs\n"
               "`lumis help --markdown`); the test options_documented fails when this file is\n"
               "stale.  `lumis COMMAND --help` prints the same.\n\n");
    for (const tool_optspec *const *s = tool_option_specs; *s; s++) {
        const size_t n = cmd ? strlen(cmd) : 0;
        /* "luminaire" names luminaire create, info, ... too */
        if (cmd &&
            !(strncmp((*s)->cmd, cmd, n) == 0 && ((*s)->cmd[n] == '\0' || (*s)->cmd[n] == ' ')))
            continue;
        tool_optmarkdown(*s, stdout);
        found = 1;
    }
    if (found) return EXIT_OK;
    fprintf(stderr, "lumis help: no option table for '%s' (see 'lumis --help')\n", cmd);
    return EXIT_USAGE;
}

static void print_help(FILE *f)
{
    fprintf(f,
            "lumis %s - importance sampling of light sources for physically based rendering\n\n"
            "usage: lumis COMMAND [OPTIONS]   (lumis COMMAND --help for its options)\n\n"
            "commands:\n",
            lumis_version());
    for (int i = 0; i < NCOMMANDS; i++)
        fprintf(f, "  %-15s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\nmaps: an image file (.exr, .hdr, .pfm) or a procedural spec sky[:WxH] or\n"
               "studio[:WxH].  Exit status: 0 success, 1 runtime error, 2 usage error.\n");
}

/* Every command's standard output is checked before the exit status is given: a full disk
 * or a closed pipe (lumis info --json > /dev/full) must not exit 0 with the output lost. */
static int finish(int rc)
{
    errno = 0;
    const int failed = fflush(stdout) != 0 || ferror(stdout);
    const int err = errno;
    if ((fclose(stdout) != 0 || failed) && rc == EXIT_OK) { /* a failed command said why */
        fprintf(stderr, "lumis: writing to standard output failed: %s\n",
                err     ? strerror(err)
                : errno ? strerror(errno)
                        : "I/O error");
        return EXIT_RUNTIME;
    }
    return rc;
}

/* SIGINT / SIGTERM: the temporary files of writes in progress are removed, then the
 * signal takes its default course (the exit status says it). */
static void on_signal(int sig)
{
    lumis_io_remove_partial_outputs();
    signal(sig, SIG_DFL);
    raise(sig);
}

/* An option given twice is refused: the first would be silently ignored (-o a.exr -o b.exr
 * never wrote a.exr).  The options that add up (--lights-param, --param, --merge's folders)
 * may repeat. */
static int repeated_option(const char *cmd, int argc, char **argv)
{
    static const char *const repeatable[] = {"--lights-param", "--param", "--merge"};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const int opt = (a[0] == '-' && a[1] == '-' && a[2]) ||
                        (a[0] == '-' && (a[1] == 'o' || a[1] == 'n' || a[1] == 'k') && !a[2]);
        if (!opt) continue;
        const size_t n = strcspn(a, "=");
        int adds = 0;
        for (size_t r = 0; r < sizeof repeatable / sizeof repeatable[0]; r++)
            adds |= strlen(repeatable[r]) == n && strncmp(a, repeatable[r], n) == 0;
        if (adds) continue;
        for (int j = 1; j < i; j++)
            if (strncmp(argv[j], a, n) == 0 && (argv[j][n] == '\0' || argv[j][n] == '=') &&
                (a[n] == '\0' || a[n] == '=')) {
                fprintf(stderr,
                        "lumis %s: %.*s given twice (the first would be ignored)\n(see 'lumis "
                        "%s --help')\n",
                        cmd, (int)n, a, cmd);
                return 1;
            }
    }
    return 0;
}

int main(int argc, char **argv)
{
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    if (argc < 2) {
        print_help(stderr);
        return EXIT_USAGE;
    }
    if (strcmp(argv[1], "help") == 0 && argc > 2 && strcmp(argv[2], "--markdown") == 0)
        return finish(markdown_help(argc > 3 ? argv[3] : NULL));
    if (strcmp(argv[1], "help") == 0 && argc > 2 && tool_is_help(argv[2])) {
        print_help(stdout);
        return finish(EXIT_OK);
    }
    if (strcmp(argv[1], "help") == 0 && argc > 2) { /* lumis help COMMAND */
        for (int i = 0; i < NCOMMANDS; i++)
            if (strcmp(argv[2], commands[i].name) == 0) {
                char *args[] = {argv[2], (char *)"--help", NULL};
                return finish(commands[i].run(2, args));
            }
        fprintf(stderr, "lumis help: unknown command '%s' (see 'lumis --help')\n", argv[2]);
        return EXIT_USAGE;
    }
    if (tool_is_help(argv[1]) || strcmp(argv[1], "help") == 0) {
        print_help(stdout);
        return finish(EXIT_OK);
    }
    if (!lumis_simd_variant()) {
        fprintf(stderr, "lumis: LUMIS_SIMD=%s names no SIMD variant (avx512, avx2 or baseline)\n",
                getenv("LUMIS_SIMD"));
        return EXIT_USAGE;
    }
    if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "version") == 0) {
        const char *embree = getenv("LUMIS_EMBREE_CONFIG");
        printf("lumis %s (SIMD variant: %s; Embree config: %s)\n", lumis_version(),
               lumis_simd_variant(), embree && *embree ? embree : "default");
        return finish(EXIT_OK);
    }
    for (int i = 0; i < NCOMMANDS; i++)
        if (strcmp(argv[1], commands[i].name) == 0) {
            if (repeated_option(argv[1], argc - 1, argv + 1)) return EXIT_USAGE;
            return finish(commands[i].run(argc - 1, argv + 1));
        }
    fprintf(stderr, "lumis: unknown command '%s' (see 'lumis --help')\n", argv[1]);
    return EXIT_USAGE;
}
