/* lumis demo [--out DIR]: the default sky as EXR and PNG, and its statistics. */
#include "common.h"

#include <errno.h>
#include <string.h>
#include <sys/stat.h>

static const char usage[] =
    "usage: lumis demo [--out DIR]\n\n"
    "Writes the default procedural sky (sun at 35 degrees elevation, 60 degrees azimuth,\n"
    "turbidity 2.5, 1024x512) to\n"
    "DIR/sky.exr and a tone-mapped preview DIR/sky.png (default DIR: demo), then prints\n"
    "its statistics as 'lumis info' does.\n";

int cmd_demo(int argc, char **argv)
{
    const char *dir = "demo", *v;
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--out", &v)) {
            if (!v || !*v) return tool_usage_error("demo", "--out needs a folder");
            dir = v;
        } else {
            return tool_usage_error("demo", "unknown argument '%s'", argv[i]);
        }
    }
    if (mkdir(dir, 0755) != 0 && errno != EEXIST)
        return tool_runtime_error("%s: cannot create folder: %s", dir, strerror(errno));

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
    return rc;
}
