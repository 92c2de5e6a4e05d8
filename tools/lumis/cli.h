/* The lumis command line (tools/lumis): its commands and the options several share.  What
 * a command does with them is in tools/app (the render pipeline) and tools/harness (bench). */
#ifndef LUMIS_TOOL_CLI_H
#define LUMIS_TOOL_CLI_H

#include "../app/compare.h"
#include "../app/errors.h"
#include "../app/files.h"
#include "../app/lights.h"
#include "../app/load.h"
#include "../app/pipeline.h"
#include "../args.h"
#include "optparse.h"
#include "lumis/io.h"
#include "lumis/lumis.h"
#include "lumis/metrics.h"
#include "lumis/render.h"

#include <stdint.h>
#include <stdio.h>

/* A subcommand: name, one-line summary, entry point (argv[0] is the command name). */
typedef struct tool_command {
    const char *name;
    const char *summary;
    int (*run)(int argc, char **argv);
} tool_command;

/* Usage error when option (NULL: none given) is a PNG-only option (--exposure, --tonemap)
 * and out is not a PNG.  Exit code. */
int tool_png_only_option(const char *cmd, const char *option, const char *out);

/* ---- text in images (tools/lumis/label.c): a 5x7 font, upper case -------------------------- */

/* Width in pixels of text drawn at scale (each glyph 5 x 7 pixels times scale, one column
 * of space between). */
int tool_text_width(const char *text, int scale);
/* Draws text with its top-left corner at (x, y), clipped to the image, in colour c
 * (linear values).  Lower case is drawn as upper case; unknown characters as '?'. */
void tool_draw_text(lumis_image *img, int x, int y, int scale, const char *text, lumis_rgb c);

/* The option tables of the commands (one tool_optspec per command and subcommand), for
 * lumis help --markdown and docs/options.md, in the order of lumis --help. */
extern const tool_optspec *const tool_option_specs[];
extern const tool_optspec tool_sky_spec, tool_studio_spec, tool_convert_spec, tool_render_spec,
    tool_lights_spec, tool_bench_spec, tool_luminaire_create_spec, tool_luminaire_info_spec,
    tool_luminaire_predict_spec, tool_compare_spec, tool_merge_spec, tool_info_spec, tool_demo_spec,
    tool_bench_samplers_spec, tool_sample_spec, tool_pdf_spec;

/* The subcommands. */
int cmd_info(int argc, char **argv);
int cmd_luminaire(int argc, char **argv);
/* lumis luminaire predict (luminaire_predict.c). */
int tool_luminaire_predict(int argc, char **argv);
/* "CAMERA,IMAGE_R,IMAGE_U,RESTRICTED,UNIFORM,GLOBAL,RAY" (nanoseconds, lumis_luminaire_costs'
 * order) into *out; 0 if malformed or refused by the model (draws > 0, the rest >= 0). */
int tool_parse_costs(const char *v, lumis_luminaire_costs *out);
#define TOOL_COSTS_HELP "CAMERA,IMAGE_R,IMAGE_U,RESTRICTED,UNIFORM,GLOBAL,RAY in ns"
int cmd_convert(int argc, char **argv);
int cmd_sky(int argc, char **argv);
int cmd_studio(int argc, char **argv);
int cmd_demo(int argc, char **argv);
int cmd_sample(int argc, char **argv);
int cmd_pdf(int argc, char **argv);
int cmd_bench_samplers(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_merge(int argc, char **argv);
int cmd_lights(int argc, char **argv);
int cmd_bench(int argc, char **argv);

/* lumis info of a photometric file (info_photometric.c): printed, or as JSON; with svg, its
 * polar plot written there.  Exit code. */
int tool_photometric_info(const char *path, int json, const char *svg);
/* Whether path names a photometric file by its extension (.ies, .ldt, any case). */
int tool_is_photometric_path(const char *path);

/* Writes the info report of a map (as `lumis info` prints it) to f. */
int tool_print_info(FILE *f, const char *name, const lumis_image *image,
                    const lumis_read_info *info, int json);

#endif
