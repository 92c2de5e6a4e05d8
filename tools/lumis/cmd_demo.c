/* lumis demo [--out DIR] [--time S]: the default sky, its statistics, and the spheres scene
 * rendered under it with inversion and kd-tree sampling at equal time, side by side. */
#include "common.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

static const char usage[] =
    "usage: lumis demo [--out DIR] [--time S] [--threads N]\n\n"
    "1. Writes the default procedural sky (sun at 35 degrees elevation, 60 degrees azimuth,\n"
    "   turbidity 2.5, 1024x512) to DIR/sky.exr and a tone-mapped preview DIR/sky.png\n"
    "   (default DIR: demo), and prints its statistics as 'lumis info' does.\n"
    "2. Renders the built-in 'spheres' scene (Lambert, Ward, GGX) under that sky with the\n"
    "   inversion (CDF) sampler and with the kd-tree sampler, each for S seconds of\n"
    "   rendering (default 3), and writes DIR/spheres-inversion.exr, DIR/spheres-kdtree.exr\n"
    "   (with JSON sidecars) and DIR/spheres-equal-time.png: inversion left, kd-tree right.\n"
    "   Compare their noise at equal time; 'lumis render --help' has every option.\n";

/* a | gap | b, black between. */
static lumis_image *side_by_side(const lumis_image *a, const lumis_image *b, int gap)
{
    lumis_image *out = NULL;
    if (a->height != b->height ||
        lumis_image_create(a->width + gap + b->width, a->height, &out) != LUMIS_OK)
        return NULL;
    for (int y = 0; y < a->height; y++) {
        float *row = out->pixels + 3 * (size_t)y * (size_t)out->width;
        memcpy(row, a->pixels + 3 * (size_t)y * (size_t)a->width,
               3 * sizeof(float) * (size_t)a->width);
        memset(row + 3 * a->width, 0, 3 * sizeof(float) * (size_t)gap);
        memcpy(row + 3 * (a->width + gap), b->pixels + 3 * (size_t)y * (size_t)b->width,
               3 * sizeof(float) * (size_t)b->width);
    }
    return out;
}

int cmd_demo(int argc, char **argv)
{
    const char *dir = "demo", *v;
    double budget = 3.0;
    long threads = 0;
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--out", &v)) {
            if (!v || !*v) return tool_usage_error("demo", "--out needs a folder");
            dir = v;
        } else if (tool_option(argc, argv, &i, "--time", &v)) {
            if (!tool_parse_double(v, &budget) || !(budget > 0.0) || budget > 3600.0)
                return tool_usage_error("demo", "--time needs seconds in (0, 3600]");
        } else if (tool_option(argc, argv, &i, "--threads", &v)) {
            if (!tool_parse_int(v, 1, 4096, &threads))
                return tool_usage_error("demo", "--threads needs a count");
        } else {
            return tool_usage_error("demo", "unknown argument '%s'", argv[i]);
        }
    }
    if (mkdir(dir, 0755) != 0 && errno != EEXIST)
        return tool_runtime_error("%s: cannot create folder: %s", dir, strerror(errno));

    /* 1. The sky. */
    lumis_image *sky = NULL;
    lumis_read_info info = {0};
    if (tool_load_image("sky", &sky, &info) != LUMIS_OK) return EXIT_RUNTIME;
    char exr[4096], png[4096];
    snprintf(exr, sizeof exr, "%s/sky.exr", dir);
    snprintf(png, sizeof png, "%s/sky.png", dir);
    lumis_write_options wo = {0};
    wo.exposure_ev = -3.0f; /* the sky is a few kcd/m^2: bring it near display white */
    wo.tonemap = LUMIS_TONEMAP_ACES;
    int rc = EXIT_RUNTIME;
    if (tool_write_image(exr, sky, NULL) == LUMIS_OK &&
        tool_write_image(png, sky, &wo) == LUMIS_OK) {
        printf("wrote %s and %s\n\n", exr, png);
        rc = tool_print_info(stdout, "sky (procedural default)", sky, &info, 0);
    }
    lumis_image_destroy(sky);
    if (rc != EXIT_OK) return rc;

    /* 2. Equal-time renders. */
    printf("\nspheres under the sky, %.3g s of rendering each (direct illumination, MIS):\n",
           budget);
    fflush(stdout);
    const lumis_sampler_method methods[2] = {LUMIS_METHOD_INVERSION, LUMIS_METHOD_KDTREE};
    const char *names[2] = {"inversion", "kdtree"};
    tool_render_result res[2];
    memset(res, 0, sizeof res);
    char outs[2][4096];
    for (int k = 0; k < 2 && rc == EXIT_OK; k++) {
        tool_render_opts o;
        memset(&o, 0, sizeof o);
        o.scene_name = "spheres";
        o.envspec = "sky";
        o.scale = 1.0f;
        o.sampler.method = methods[k];
        o.rd.seed = 1;
        o.rd.threads = (int)threads;
        o.time_budget = budget;
        o.quiet = 1;
        snprintf(outs[k], sizeof outs[k], "%s/spheres-%s.exr", dir, names[k]);
        o.out = outs[k];
        o.argc = argc;
        o.argv = argv;
        rc = tool_render(&o, &res[k]);
    }
    if (rc == EXIT_OK) {
        printf("  %-10s %6s %9s %12s %14s %12s\n", "method", "spp", "render s", "rays/s",
               "sampler build", "table bytes");
        for (int k = 0; k < 2; k++) {
            const lumis_render_stats *s = &res[k].stats;
            double rays = s->camera_rays + s->shadow_rays + s->bounce_rays;
            printf("  %-10s %6d %9.3f %12.3g %11.2f ms %12zu\n", names[k], s->spp, s->seconds,
                   rays / s->seconds, res[k].sampler_build_ms, res[k].sampler_table_bytes);
        }
        lumis_image *both = side_by_side(res[0].image, res[1].image, 8);
        snprintf(png, sizeof png, "%s/spheres-equal-time.png", dir);
        lumis_write_options pw = {0};
        pw.exposure_ev = -4.0f;
        pw.tonemap = LUMIS_TONEMAP_ACES;
        if (!both || tool_write_image(png, both, &pw) != LUMIS_OK)
            rc = EXIT_RUNTIME;
        else
            printf("wrote %s, %s (JSON sidecars beside them) and %s: inversion left, kd-tree "
                   "right\n",
                   outs[0], outs[1], png);
        lumis_image_destroy(both);
    }
    lumis_image_destroy(res[0].image);
    lumis_image_destroy(res[1].image);
    return rc;
}
