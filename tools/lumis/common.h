/* Shared pieces of the lumis subcommands: option parsing, map loading, error printing. */
#ifndef LUMIS_TOOL_COMMON_H
#define LUMIS_TOOL_COMMON_H

#include "../args.h"
#include "lumis/io.h"
#include "lumis/lumis.h"
#include "lumis/metrics.h"
#include "lumis/render.h"

#include <stdint.h>
#include <stdio.h>

/* Sun of the default sky (`lumis sky`, the "sky" map spec, `lumis demo`). */
#define TOOL_SKY_ELEVATION_DEG LUMIS_MAP_SKY_ELEVATION_DEG
#define TOOL_SKY_AZIMUTH_DEG   LUMIS_MAP_SKY_AZIMUTH_DEG

/* Exit codes of every subcommand. */
enum { EXIT_OK = 0, EXIT_RUNTIME = 1, EXIT_USAGE = 2 };

/* A subcommand: name, one-line summary, entry point (argv[0] is the command name). */
typedef struct tool_command {
    const char *name;
    const char *summary;
    int (*run)(int argc, char **argv);
} tool_command;

/* Error sink that prints "lumis: message" on stderr. */
extern const lumis_error_sink tool_errors;

/* Prints "lumis CMD: message" on stderr; returns EXIT_USAGE. */
int tool_usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* A bad option value: "lumis CMD: OPTION EXPECTED, not 'VALUE'" (or "(no value given)"
 * when value is NULL); returns EXIT_USAGE. */
int tool_bad_value(const char *cmd, const char *option, const char *value, const char *expected);

/* Prints "lumis: message" on stderr; returns EXIT_RUNTIME. */
int tool_runtime_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Loads a map (tools/lumis/load.c): an image file, or a
 * procedural spec "sky", "sky:WxH", "studio", "studio:WxH".  Prints errors itself; returns a
 * lumis_status. */
lumis_status tool_load_image(const char *spec, lumis_image **out, lumis_read_info *info);
/* FNV-1a (64-bit) of n bytes, continued from h (start: 0xcbf29ce484222325): the cache keys
 * of lumis bench and of acquired luminaires. */
uint64_t tool_fnv(uint64_t h, const void *data, size_t n);
/* mkdir -p; prints the error.  Exit code. */
int tool_make_dir(const char *path);
/* Prints what was replaced in the map what (a file or spec): tiny negatives as a note
 * (LUMIS_NOTES=0 silences it), the rest as a warning naming the worst pixel; and img's
 * saturated spikes, by pixel (img may be NULL). */
void tool_warn_replaced(const char *what, lumis_replaced r, const lumis_image *img);

/* Light-set methods by name (lumis_lights_method_from_name): known, Wu's (any wu...), and
 * the names joined for a message. */
int tool_lights_method_known(const char *name);
const char *tool_lights_method_names(void);
int tool_lights_method_is_wu(const char *name);

/* lumis_light_params_parse of option `opt`'s value `text` (lumis lights --param, lumis render
 * --lights-param): a usage error of command `cmd` (EXIT_USAGE) with the library's message,
 * else EXIT_OK. */
int tool_light_params_parse(lumis_light_params *p, const char *cmd, const char *opt,
                            const char *text);
/* lumis_light_params_check against `method`, as a usage error (EXIT_USAGE) or EXIT_OK. */
int tool_light_params_check(const lumis_light_params *p, const char *cmd, const char *opt,
                            const char *method);

/* "auto" exposure: the stops that bring an image's mean luminance to 0.18 (0 for a black
 * image).  The default of every PNG preview. */
/* Monotonic wall-clock seconds. */
double tool_now_seconds(void);
/* The median of n values (sorts them). */
double tool_median(double *v, int n);

/* A luminaire manifest (lumis_luminaire_read) or preset:car|bike|small (acquired); errors
 * printed. */
lumis_status tool_load_luminaire(const char *spec, lumis_luminaire **out);
/* lumis_scene_read_options.load_preset: a preset a scene file names, through the cache of
 * tool_load_luminaire. */
lumis_status tool_scene_load_preset(void *user, const char *spec, lumis_luminaire **out);

float tool_auto_exposure(const lumis_image *image);

/* Parses --exposure's value: "auto" (is_auto = 1) or stops in [-64, 64].  Exit code. */
int tool_exposure_option(const char *cmd, const char *v, float *ev, int *is_auto);

/* Usage error when option (NULL: none given) is a PNG-only option (--exposure, --tonemap)
 * and out is not a PNG.  Exit code. */
int tool_png_only_option(const char *cmd, const char *option, const char *out);

/* Writes with the atomic writer; prints errors itself. */
lumis_status tool_write_image(const char *path, const lumis_image *image,
                              const lumis_write_options *options);

/* ---- outputs, checked before any work (tools/lumis/outputs.c) ------------------------------ */

typedef enum tool_output_kind {
    TOOL_OUT_FILE,   /* any name (JSON, CSV, text) */
    TOOL_OUT_IMAGE,  /* .exr .hdr .pfm .png */
    TOOL_OUT_LINEAR, /* .exr .hdr .pfm: linear values */
    TOOL_OUT_PNG,    /* .png */
    TOOL_OUT_GLTF,   /* .gltf (text) or .glb (binary) */
    TOOL_OUT_DIR,    /* a directory, made if missing (its parent must exist) */
    TOOL_OUT_SIDECAR /* a render's JSON sidecar: replaces only an earlier sidecar */
} tool_output_kind;

enum { TOOL_FILES_MAX = 32 };

/* The files a command reads and writes. */
typedef struct tool_files {
    int n_in, n_out;
    struct {
        const char *what, *path;
        tool_output_kind kind;
        const char *hint; /* TOOL_OUT_SIDECAR: the options that choose another path */
    } in[TOOL_FILES_MAX], out[TOOL_FILES_MAX];
    int n_lists; /* inputs by the list: a luminaire's images (borrowed until the check) */
    struct {
        const char *what;
        const char *const *paths;
        int count;
    } lists[TOOL_FILES_MAX];
} tool_files;

/* Records an input or an output; what names it in messages ("scene file", "--png").  NULL
 * or empty paths are ignored. */
void tool_files_input(tool_files *f, const char *what, const char *path);
void tool_files_output(tool_files *f, const char *what, const char *path, tool_output_kind kind);
/* Records a sidecar output: it may replace an earlier sidecar (tool_is_sidecar) or an empty
 * file, nothing else; hint names the options that choose another path ("--sidecar PATH or
 * --no-sidecar"). */
void tool_files_sidecar(tool_files *f, const char *path, const char *hint);
/* Nonzero when path holds a lumis sidecar: a JSON object with "lumis_version", "command"
 * and "outputs", as tool_write_sidecar writes it. */
int tool_is_sidecar(const char *path);
/* Records count inputs at once (the paths are borrowed until tool_files_check). */
void tool_files_input_list(tool_files *f, const char *what, const char *const *paths, int count);

/* The whole of a file (free it); NULL if it cannot be opened (*oom = 0) or memory is short
 * (*oom = 1). */
unsigned char *tool_read_file(const char *path, size_t *n, int *oom);

/* Usage error (exit 2, naming both paths) unless every output has an extension of its kind,
 * a directory that exists and can be written, and is neither an input nor another output;
 * a sidecar may replace only a sidecar.
 * Same file: by device and inode when both exist, else by resolved directory and name. */
int tool_files_check(const char *cmd, const tool_files *f);
int tool_same_file(const char *a, const char *b);

/* ---- text in images (tools/lumis/label.c): a 5x7 font, upper case -------------------------- */

/* Width in pixels of text drawn at scale (each glyph 5 x 7 pixels times scale, one column
 * of space between). */
int tool_text_width(const char *text, int scale);
/* Draws text with its top-left corner at (x, y), clipped to the image, in colour c
 * (linear values).  Lower case is drawn as upper case; unknown characters as '?'. */
void tool_draw_text(lumis_image *img, int x, int y, int scale, const char *text, lumis_rgb c);

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

/* Parses one sampler option (--method, --blocks, --kdtree-uniform-angles, --compensate,
 * --importance, --rotate) into d; returns -1 if argv[*i] is none of them, else an exit
 * code (0 == parsed). */
int tool_sampler_option(const char *cmd, int argc, char **argv, int *i, lumis_sampler_desc *d,
                        float *rotation);

/* The envmap of a map (file or procedural spec), rotated and scaled; from preloaded (borrowed)
 * when given, spec then only names it.  Prints errors itself. */
lumis_status tool_make_envmap(const char *spec, const lumis_image *preloaded, float rotation,
                              float scale, lumis_envmap **env, lumis_replaced *replaced);

/* Loads a map (file or procedural spec), builds its envmap (rotated, scaled) and a
 * sampler; prints errors itself. */
lumis_status tool_make_sampler(const char *spec, float rotation, float scale,
                               const lumis_sampler_desc *desc, lumis_envmap **env,
                               lumis_sampler **sampler);

/* One render, as `lumis render` does it (also used by `lumis demo`). */
typedef struct tool_render_opts {
    const char *scene_name, *scene_path; /* one of them */
    const char *envspec;                 /* NULL: the scene's map, else "sky" */
    const lumis_image *env_image;        /* envspec's pixels, loaded by the caller (borrowed);
                                            NULL: loaded from envspec */
    lumis_replaced env_image_replaced;   /* what loading env_image replaced (the sidecar's) */
    float rotation_deg, scale;           /* of envspec when given */
    lumis_sampler_desc sampler;
    const char *sampler_opt; /* --method (not bsdf) or --blocks, if given: a sampler is built
                                whatever lights the scene (the library refuses it by name) */
    int bsdf_only;
    const char *lights;               /* a light-set method (tool_lights_method_known), or NULL */
    lumis_lights_mode lights_mode;    /* --lights-mode: point (0) or stratified */
    int lights_k, interleave;         /* its K and number of interleaved sets (0: defaults) */
    lumis_light_params lights_params; /* --lights-param (zero: the method's defaults) */
    int upsample;         /* Wu: EnvIndirects at 1/F resolution per axis (0: 2; 1: none) */
    lumis_render_desc rd; /* estimator, heuristic, counts, seed, threads, bounces */
    /* Scenes with luminaires: how they are sampled (the instances come from the scene). */
    lumis_luminaire_lighting lum;
    lumis_luminaire_costs lum_costs; /* --lum-costs (lum.auto_costs points here when given) */
    int lum_costs_given;
    const char *lum_option; /* the first --lum-* / --visibility / --sequence option given */
    /* --fixture FILE: a photometric fixture lights the scene instead of its own lights (map,
     * fixtures), at --fixture-at (required), aimed at --fixture-aim (default straight down,
     * -y), its local +x towards --fixture-up, rolled, scaled, as its opening with
     * --fixture-area */
    const char *fixture;
    double fixture_at[3], fixture_aim[3], fixture_up[3], fixture_roll, fixture_multiplier;
    int fixture_at_given, fixture_aim_given, fixture_up_given, fixture_area;
    const char *luminaire;  /* --luminaire: replaces every luminaire of the scene (a manifest
                               or preset:NAME); NULL: the scene's own */
    double time_budget;     /* > 0: progressive passes until this much render time */
    int pass_index, passes; /* --passes I/N (passes 0: the whole render) */
    int width, height;      /* 0: the scene's camera */
    const char *out, *png;  /* out NULL: nothing written */
    const char *sidecar;    /* NULL: OUT.json; "": none */
    const char *cmd;        /* names the command in usage errors (NULL: "render") */
    lumis_write_options png_options;
    int png_auto_exposure; /* nonzero: png_options.exposure_ev from the image (auto) */
    int quiet;             /* no progress bar, no summary line */
    int progress;          /* the progress bar (on a terminal) even when quiet */
    int argc;              /* the command line, for the sidecar */
    char **argv;
} tool_render_opts;

typedef struct tool_render_result {
    lumis_image *image; /* the caller destroys it */
    lumis_render_stats stats;
    double load_seconds, scene_seconds, total_seconds, sampler_build_ms;
    size_t sampler_table_bytes;
    int upsample; /* the factor used (1: none) */
    /* --lights with --time: the pilot renders that chose K (0 seconds: none ran), and the
     * session's account of it (lumis_session_result: k_floor, spp_planned, k_limit ...). */
    double lights_pilot_seconds, lights_pilot_per_spp[LUMIS_SESSION_PILOTS],
        lights_pilot_once[LUMIS_SESSION_PILOTS];
    double lights_pilot_chosen; /* K the pilots chose, before any re-render */
    int lights_pilot_k[LUMIS_SESSION_PILOTS], lights_pilot_count;
    double lights_pilot_scale, lights_pilot_predicted;
    int lights_k_floor, lights_spp_planned;
    lumis_k_limit lights_k_limit;
    int lights_retried; /* the pilots misjudged: rendered again with K scaled */
    /* Contention (lumis_session_result): the session's wall and CPU seconds, and over its
     * render passes the CPU share of the busy threads' wall time. */
    double wall_seconds, cpu_seconds, render_wall_seconds, render_cpu_seconds, cpu_share;
    int threads_busy;
    int contended;  /* cpu_share below TOOL_CONTENTION_SHARE: warned */
    int prep_heavy; /* --time: prep_seconds above TOOL_PREP_WARN_SHARE of it: warned */
    /* Equal wall time: seconds before the first sample (sampler tables, light-set generation
     * of every attempt, K's pilots), and that plus every attempt's render (--time only). */
    double prep_seconds, budget_used_seconds;
    lumis_replaced env_replaced; /* the map's values its reader replaced by 0 */
    /* --lum-strategy auto: the strategy of each luminaire, comma-separated (the first 32;
     * "uniform to 0.52 + global" in bands of distance), and the first one's choice */
    char lum_chosen[640];
    char lum_budgets[320]; /* their K (auto gives a global one more: render.h) */
    lumis_luminaire_choice lum_choice;
} tool_render_result;

/* Samples per pixel of a light set rendered to a time budget (--lights with --time): the
 * budget goes to the number of lights. */
#define TOOL_LIGHTS_TIMED_SPP 4

/* A timed render whose threads got less than this share of their wall time as CPU time
 * waited for cores (another process ran on them): the CLI warns, the sidecar and the bench
 * report say so.  Idle, a render's passes measure 0.95-1.0; one thread sharing its core with
 * one busy process, about 0.5. */
#define TOOL_CONTENTION_SHARE 0.8
/* A --time render that spent more than this share of its budget before its first sample
 * (tables, light sets, K's pilots) warns: the method's preparation is then what is compared. */
#define TOOL_PREP_WARN_SHARE 0.3

/* The default sidecar of OUT: OUT.exr -> OUT.json (or OUT + .json). */
void tool_sidecar_path(const char *out, char *buf, size_t cap);
/* The sidecar of a render (sidecar.c): every setting, timing and count.  Exit code. */
int tool_write_sidecar(const tool_render_opts *o, const lumis_render_desc *rd, const char *path,
                       const char *scene_label, const char *envspec, const lumis_envmap *env,
                       const lumis_sampler *smp, const lumis_light_set *lights,
                       const lumis_scene_file *file, const lumis_camera *cam,
                       const tool_render_result *r);
/* "bsdf", "light" or "mis". */
const char *tool_estimator_name(const lumis_render_desc *d);
/* Why K fitted to --time is what it is (r->lights_k_limit), in words; "" when it is what
 * the pilots fitted at the planned samples. */
void tool_k_limit_text(const tool_render_opts *o, const tool_render_result *r, char *buf,
                       size_t cap);

/* The progress bar (progress.c): on stderr when it is a terminal; budget > 0: by time. */
typedef struct progress {
    int enabled;
    double start, budget, last;
    int spp_done;
} progress;
void tool_progress_draw(progress *p, double fraction, int final);
/* lumis_render_desc.progress for a progress (user). */
void tool_on_progress(void *user, int done, int total);

/* Checks every output against every input (the scene file, the map, the meshes) before any
 * work (exit 2), then renders.  Returns an exit code; prints errors, a progress bar (stderr is a
 * terminal) and, unless quiet, a summary line. */
int tool_render(const tool_render_opts *o, tool_render_result *r);
/* The samples of o's share (--passes I/N): the whole render's total, the share's first
 * sample and count (without --passes: 0 and all of them). */
void tool_share_range(const tool_render_opts *o, int *total, int *first, int *count);
/* Writes a text built in a FILE* (tmpfile(); NULL: an error) atomically to path, and
 * closes f.  Exit code. */
int tool_commit_tmp(FILE *f, const char *path);
/* s written to f with HTML's and SVG's special characters (< > & ") as entities. */
void tool_markup_escape(FILE *f, const char *s);
/* lumis info of a photometric file (info_photometric.c): printed, or as JSON; with svg, its
 * polar plot written there.  Exit code. */
int tool_photometric_info(const char *path, int json, const char *svg);
/* Whether path names a photometric file by its extension (.ies, .ldt, any case). */
int tool_is_photometric_path(const char *path);
/* lumis merge (cmd_merge.c): joins the n shares in[] of one render (each with its sidecar)
 * into out, each share's mean weighted by its samples; side_out: the merged sidecar (NULL:
 * none).  Checks that they are every share of one render, each once.  Prints errors (and,
 * unless quiet, a line of what it merged).  Exit code. */
int tool_merge_shares(const char *const *in, int n, const char *out, const char *side_out,
                      int quiet, int allow_replaced);

struct cJSON;
/* The render key (render_key.c): a digest of a share's sidecar less what may differ between
 * the shares of one render (timings, counts of work, host, share index), in out (16 hex
 * digits).  0 when out of memory. */
int tool_render_key(const struct cJSON *side, char *out, size_t cap);
/* Whether "key" or "object.key" of a sidecar may differ between shares of one render. */
int tool_render_key_may_differ(const char *path);
/* The first field of the render key in which sidecars a and b differ, in field, with their
 * values (JSON, shortened) in va and vb; 0 if none. */
int tool_render_key_difference(const struct cJSON *a, const struct cJSON *b, char *field,
                               size_t cap, char *va, char *vb, size_t vcap);

struct cJSON;

/* Every metric of `lumis compare` (tools/lumis/cmd_compare.c). */
typedef struct tool_metrics {
    lumis_image_error_stats err;
    double lab_delta_e, flip_ldr, flip_hdr, flip_start, flip_stop, ppd;
    int has_flip_hdr;
    float exposure_ev;
} tool_metrics;

/* Computes every metric (HDR-FLIP unless hdr_flip == 0); flip_map (optional, width *
 * height) receives the HDR-FLIP map, or the LDR one without HDR-FLIP.  Exit code. */
int tool_compare_images(const lumis_image *ref, const lumis_image *test, float exposure_ev,
                        double ppd, int hdr_flip, tool_metrics *m, float *flip_map);
/* Adds the metrics and their parameters to a JSON object (struct cJSON). */
void tool_metrics_json(const tool_metrics *m, struct cJSON *o);
/* Writes a FLIP error map as a magma-coloured PNG.  Exit code. */
int tool_write_flip_map(const char *path, const float *map, int width, int height);

/* Writes a JSON object (struct cJSON), indented and ending in a newline, with the atomic
 * writer; prints errors itself.  Exit code. */
int tool_write_json(const char *path, const struct cJSON *json);

/* Writes the info report of a map (as `lumis info` prints it) to f. */
int tool_print_info(FILE *f, const char *name, const lumis_image *image,
                    const lumis_read_info *info, int json);

#endif
