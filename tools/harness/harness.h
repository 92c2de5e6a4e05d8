/* The benchmark harness (tools/harness, the static library lumis-harness): the suite model,
 * its items and their keys, the runner, the report's results and writers (tables, SVG,
 * HTML), convergence, merge and Slurm.  `lumis bench` (tools/lumis/cmd_bench.c) parses the
 * command line and calls bench_main; the harness renders through the render pipeline of
 * tools/app.  Shared names carry a bench_ prefix; nothing here is part of any installed
 * library. */
#ifndef LUMIS_HARNESS_H
#define LUMIS_HARNESS_H

#include "../app/compare.h"
#include "../app/errors.h"
#include "../app/files.h"
#include "../app/lights.h"
#include "../app/load.h"
#include "../app/pipeline.h"

#include <stddef.h>
#include <stdio.h>

struct cJSON;

/* ---- the suite (bench_suite.c) ------------------------------------------------------------ */

typedef struct suite_map {
    char label[128], spec[4096];
    float rotation_deg, scale;
    int is_file;
    /* Set by bench_read_inputs: */
    int first;               /* the first map of the same spec: they share what follows */
    unsigned long long hash; /* of the content, as the reference key starts it */
    unsigned char *bytes;    /* the file's bytes, kept for decoding (first only) */
    size_t nbytes;
    lumis_replaced replaced; /* values its decoding replaced by 0 (bench_run) */
} suite_map;

typedef struct suite_scene {
    char label[128], spec[4096]; /* a built-in name or a resolved file path */
    int is_file;
    unsigned char *bytes; /* a file's bytes, for its hash (bench_read_inputs); NULL: missing */
    size_t nbytes;
    unsigned char *maps; /* {"scene": ..., "maps": [...]}: per map, 1 if the pair is in the
                            suite (NULL: every map) */
} suite_scene;

typedef struct suite_method {
    char label[128];
    lumis_sampler_desc sampler;
    int bsdf_only;
    lumis_estimator estimator;
    int power, light_samples, bsdf_samples;
    char lights[32];               /* a light-set method, or "" */
    lumis_lights_mode lights_mode; /* "mode": point (default) or stratified */
    int sun;                       /* "sun": true: render --sun (the image sun) */
    int auto_estimator;            /* "auto": true: render --auto (LUMIS_AUTO_PREDICT); "pilots":
                                      --auto-pilots (LUMIS_AUTO_PILOTS) */
    int lights_draws;              /* "draws": stratified, N draws chosen per vertex (0:
                                      one in every region) */
    int lights_region_draws;       /* "region_draws": stratified, N draws split over every region
                                      before the render (0: one in every region) */
    int lights_k, interleave, upsample; /* 0: defaults (with a time budget K fills the time) */
    lumis_light_params lights_params;   /* "params": the light-set method's parameters */
    lumis_sequence sequence;            /* "sequence": the render's numbers (default sobol) */
} suite_method;

typedef struct suite_budget {
    char label[64];
    int spp;
    double seconds;
} suite_budget;

typedef struct suite {
    char name[128], description[1024], dir[4096];
    suite_map *maps;
    suite_scene *scenes;
    suite_method *methods, reference;
    suite_budget *budgets;
    int nmaps, nscenes, nmethods, nbudgets;
    int ref_spp, width, height, bounces, flip_hdr;
    unsigned long long seed;
    float exposure_ev, preview_ev;
    int exposure_auto, preview_auto; /* "auto": per reference, its mean luminance to 0.18 */
    char compare[8][2][128];         /* pairs of method labels to compare in the report */
    int ncompare;
} suite;

/* Reads and checks a suite file; prints errors itself.  Exit code; on success the caller
 * frees s with bench_suite_free. */
int bench_parse_suite(const char *path, suite *s);
void bench_suite_free(suite *s);

/* Reads every map and scene file of the suite once, for the keys (each file's content is
 * hashed, not its name); with keep_maps, each map file's bytes stay in s for bench_run to
 * decode.  Call it after bench_parse_suite, before any key is asked for.  Exit code. */
int bench_read_inputs(suite *s, int keep_maps);

/* Copies at most cap - 1 bytes (a cut label is still a label). */
void bench_copy_cut(char *out, size_t cap, const char *in);

/* ---- items and their keys (bench_keys.c) ------------------------------------------------- */

typedef struct item {
    int map, scene, method, budget;
    char id[600];
} item;

int bench_nitems(const suite *s);
/* Whether the pair (map m, scene sc) is in the suite (a scene may list its maps): the
 * items of a pair that is not are never rendered, needed or counted. */
int bench_pair_listed(const suite *s, int m, int sc);
/* The items of the listed pairs (bench_nitems counts every pair: the items' indices). */
int bench_nlisted(const suite *s);
/* Items are ordered map, scene, method, budget (the budget varies fastest). */
item bench_item_at(const suite *s, int index);
/* The index of an item. */
int bench_idx(const suite *s, int m, int sc, int me, int b);

/* The hash that names a reference (16 hex digits in out). */
void bench_reference_key(const suite *s, int m, int sc, char *out, size_t cap);
/* The hash of everything an item's result depends on besides its reference. */
void bench_item_key(const suite *s, const item *it, char *out, size_t cap);
/* The item's result file, parsed, if it exists and belongs to the suite as it is now. */
struct cJSON *bench_load_item(const suite *s, const char *out, const item *it);
int bench_item_done(const suite *s, const char *out, const item *it);
/* Whether item k belongs to shard shard_i of shard_n (never when its pair is not listed). */
int bench_in_shard(const suite *s, int k, long shard_i, long shard_n);
/* Whether any item of the (map, scene) pair is not done: the pair needs its reference. */
int bench_pair_needed(const suite *s, const char *out, int m, int sc);

/* References, checked rather than only present: DIR/refs/KEY.exr reads and has the suite's
 * size.  And the share I of P of a reference split by passes (DIR/refs/parts/KEY.pass-I-of-P
 * .exr): it reads, has the size, and its sidecar says it is that share. */
void bench_reference_path(const suite *s, const char *out, int m, int sc, char *exr, size_t cap);
void bench_reference_part_path(const suite *s, const char *out, int m, int sc, long i, long p,
                               char *exr, size_t cap);
int bench_reference_ok(const suite *s, const char *out, int m, int sc);
int bench_reference_part_ok(const suite *s, const char *out, int m, int sc, long i, long p);

/* ---- running (bench_run.c) ---------------------------------------------------------------- */

typedef struct bench_run_opts {
    const char *out;
    int threads; /* --threads: per render; 0: every core for references, cores / jobs for items */
    long jobs, shard_i, shard_n;
    int items_only; /* --items-only: render no reference (a missing one is an error) */
    int argc;       /* the command line, for the sidecars */
    char **argv;
} bench_run_opts;

/* Loads the maps this shard renders with (each once, from the bytes bench_read_inputs kept,
 * which it frees), renders the references this shard needs, then its items, in o->jobs
 * processes.  Exit code. */
/* Exit code; *failed_items: the items whose process failed (recorded in DIR/failures/: the
 * run went on without them, and returns EXIT_RUNTIME). */
int bench_run(suite *s, const bench_run_opts *o, int *failed_items);
/* --reference-task T with --reference-passes P: share T % P of the reference of pair T / P
 * (pairs ordered map, then scene), into its part file, unless the reference or that part is
 * done, or no item of the pair needs it.  Exit code. */
int bench_render_reference_part(suite *s, const bench_run_opts *o, long task, long passes);
/* --merge-references with --reference-passes P: every needed reference that is not done is
 * merged from its P parts (lumis merge), with its preview, and the parts removed.  A
 * reference whose parts are not all there is an error that names them.  Exit code. */
int bench_merge_references(suite *s, const char *out, long passes);

int bench_file_exists(const char *path);

/* ---- the report: results and tables (bench_tables.c) ------------------------------------- */

enum { M_RMSE, M_RELMSE, M_PSNR, M_LAB, M_FLIP_LDR, M_FLIP_HDR, NMETRICS };
extern const char *const bench_metric_key[NMETRICS];
extern const char *const bench_metric_title[NMETRICS];

typedef struct result {
    int present;
    double v[NMETRICS];
    double seconds, build_ms, table_bytes;
    double prep; /* seconds before the first sample, inside an equal-time budget */
    int spp;
    /* What the item used (prep + every attempt: a light set's K refitted renders twice),
     * its attempts, and contention: the session's wall and CPU seconds and the render
     * threads' CPU share (NaN, 0: results made before 2026-12) */
    double used, wall, cpu, share;
    int attempts, contended;
    char auto_chosen[32]; /* "auto": the candidate it chose ("" for other methods) */
} result;

typedef struct summary {
    double mean[NMETRICS], rank[NMETRICS], seconds, spp, build_ms, table_bytes, prep;
    double used; /* prep + every attempt's render (NaN when a result predates it) */
    int n;
} summary;

/* The axes of the convergence analyses: the time budgets ({"time": S}: equal time) and the
 * sample budgets ({"spp": N}: equal samples); each axis is analysed on its own, the other's
 * budgets take no part. */
typedef enum bench_axis { BENCH_TIME, BENCH_SPP, BENCH_NAXES } bench_axis;

/* How the report names an axis (bench_axes[axis]). */
typedef struct bench_axis_words {
    const char *title;   /* the section's heading: "Convergence (equal time)" */
    const char *budget;  /* "time budget" */
    const char *log_x;   /* what the slope is against: "log(seconds)" */
    const char *others;  /* the other axis' budgets: " Budgets in samples take no part." */
    const char *note;    /* more of the section's paragraph, or "" */
    const char *unit;    /* after a value of x (a crossing, an axis' tick): " s" */
    const char *json;    /* results.json's object: "convergence" */
    const char *x_key;   /* its arrays of x, and a crossing's: "seconds" */
    const char *scene;   /* a scene labelled so has its plot named as the axis' would be: "all" */
    const char *svg;     /* the axis' plot (bench_convergence_svg_name): "convergence-all.svg" */
    const char *svg_alt; /* its name when a scene is labelled .scene: "...-all-scenes.svg" */
    const char *x_title; /* the plot's title, after "... vs ": "time budget, equal time" */
    const char *x_name;  /* the plot's x axis: "time budget (log)" */
} bench_axis_words;
extern const bench_axis_words bench_axes[BENCH_NAXES];

/* The convergence analysis along one axis (with two or more budgets on it): per method and
 * budget the geometric mean of relMSE over the (map, scene) pairs with a result (relMSE
 * finite and > 0), and the least-squares slope of its log against log(x), x the budget's
 * seconds or samples per pixel, over all pairs and per scene. */
typedef struct bench_convergence {
    bench_axis axis;  /* BENCH_TIME or BENCH_SPP */
    int nt;           /* budgets on the axis; 0: no analysis (fewer than two) */
    int *budget;      /* [nt]: their indices in the suite, by increasing x */
    double *x;        /* [nt]: their seconds (BENCH_TIME) or samples per pixel (BENCH_SPP) */
    double *geomean;  /* [method * nt + k]; NAN where no pair has a result */
    int *pairs;       /* [method * nt + k]: the pairs counted */
    double *slope;    /* [method]; NAN with fewer than two budgets that have a geomean */
    double *sc_geo;   /* [(scene * nmethods + method) * nt + k]: over that scene's maps */
    double *sc_slope; /* [scene * nmethods + method] */
} bench_convergence;

/* Everything the report's writers share. */
typedef struct bench_report {
    const suite *s;
    const char *out;
    result *res;  /* per item */
    summary *sum; /* per budget, then method */
    int n, found; /* items, items with a current result */
    char machine[400], cmd[4096], date[64];
    bench_convergence conv[BENCH_NAXES]; /* per axis, set by bench_report_load */
} bench_report;

/* Loads the results DIR holds and summarises them; prints errors itself.  Exit code; on
 * success the caller frees r with bench_report_free. */
int bench_report_load(bench_report *r, const suite *s, const char *out, int argc, char **argv);
void bench_report_free(bench_report *r);

int bench_write_csv(const bench_report *r, const char *path);
int bench_write_json(const bench_report *r, const char *path);
int bench_write_md(const bench_report *r, const char *path);

typedef enum bench_markup { BENCH_MD, BENCH_HTML } bench_markup;

/* For each compare pair, per budget: in how many (map, scene) pairs the first beats the
 * second on relMSE and FLIP, the geometric mean of their relMSE ratio, and where the
 * first loses; then their sampling tables' sizes.  Headings, tables and text. */
void bench_write_comparisons(FILE *f, bench_markup mk, const suite *s, const result *res);
/* A reference should have this many times the samples of the items it judges, at least. */
#define BENCH_REF_FACTOR 4

/* The items (of one budget and method; -1: any) whose reference has fewer than
 * BENCH_REF_FACTOR times the samples they reached (at equal time too): its noise then
 * weighs in their errors.  Returns how many; *max_spp: the most samples among them. */
int bench_noisy_reference(const bench_report *r, int budget, int method, int *max_spp);
/* The warning, with a table of those items per budget and method (nothing if none). */
void bench_write_reference_warning(FILE *f, bench_markup mk, const bench_report *r);
/* The equal-time items whose render threads shared their cores (contention: their budget
 * bought less than on an idle machine): a warning with a table of them; returns their
 * number. */
int bench_write_contention_warning(FILE *f, bench_markup mk, const bench_report *r);
/* The reference's method as a reader would name it: "inversion + MIS (balance)", "light
 * set variance-min, stratified, K = 32", "BSDF sampling". */
void bench_method_words(const suite_method *m, char *out, size_t cap);
/* The items whose process failed (DIR/failures/ID.txt): a list; returns their number. */
int bench_write_failures(FILE *f, bench_markup mk, const bench_report *r);

/* The automatic estimator (bench_auto.c): methods with "auto": true against the best of the
 * suite's other methods at each (map, scene, budget).  A case misses when auto's relMSE is
 * more than BENCH_AUTO_MISS times the best fixed one's (issue 39: within 10 %). */
#define BENCH_AUTO_MISS 1.10
/* How many of the suite's methods are "auto". */
int bench_auto_methods(const suite *s);
/* Per auto method: a summary per budget (pairs, geometric mean of auto / best fixed, the
 * misses, the choices made) and a table of every case (nothing without an auto method). */
void bench_write_auto(FILE *f, bench_markup mk, const bench_report *r);
/* results.json's "auto" array: the same per auto method (nothing without one). */
void bench_json_auto(struct cJSON *j, const bench_report *r);

/* relMSE per (map, scene) and method at the last budget: a heading and a table. */
void bench_write_per_map(FILE *f, bench_markup mk, const suite *s, const result *res);

/* The tables' markup (bench_markup.c), Markdown or HTML: a heading, a paragraph, a table's
 * start and end, one row of n cells (a rule under the header in Markdown; the cells are
 * labels and numbers: nothing in them needs escaping). */
void bench_heading(FILE *f, bench_markup mk, const char *text);
void bench_paragraph(FILE *f, bench_markup mk, const char *text);
void bench_table_begin(FILE *f, bench_markup mk);
void bench_table_row(FILE *f, bench_markup mk, int header, int n, char cells[][4200]);
void bench_table_end(FILE *f, bench_markup mk);
/* The index of the method labelled `label`, -1 for none. */
int bench_method_index(const suite *s, const char *label);

/* ---- the convergence analysis (bench_convergence.c) --------------------------------------- */

/* The least-squares slope of y against x over the n points where both are finite; NAN
 * when fewer than two such points have distinct x. */
double bench_loglog_slope(const double *x, const double *y, int n);
/* Where curve a crosses curve b, both sampled at the n increasing times t (NAN: no value):
 * between consecutive times that have both values and where the sign of log(a / b)
 * changes, by linear interpolation of log(a / b) against log(t) (through times where
 * a == b: at them, the geometric middle of several; touching without a change of sign is no
 * crossing).  Writes up to cap crossing times to at[] and, for each, after[]: 1 when a is
 * below b after it, 0 when above.  Returns the number of crossings; with none, *order says
 * -1 (a below b, or equal, at every time that has both), 1 (above), 2 (equal at every
 * one), 0 (no time has both). */
int bench_crossings(const double *t, const double *a, const double *b, int n, double *at,
                    int *after, int cap, int *order);
/* Computes r->conv[] from r->res, both axes (bench_report_load calls it); frees with the
 * report. */
int bench_convergence_compute(bench_report *r);
void bench_convergence_free(bench_convergence *c);
/* The analysis c's object of results.json, named bench_axes[c->axis].json: "convergence"
 * (time) or "convergence_spp" (nothing without the analysis). */
void bench_json_convergence(struct cJSON *j, const bench_report *r, const bench_convergence *c);
/* The section "Convergence (equal time)" or "Convergence (equal samples)": slopes,
 * geometric means, and per compare pair the ratio per budget and the crossings (in seconds
 * or samples per pixel); with the plot (nothing without the analysis). */
void bench_write_convergence(FILE *f, bench_markup mk, const bench_report *r,
                             const bench_convergence *c);
/* The file name of an axis' plot of all pairs: convergence-all.svg (time) and
 * convergence-spp.svg (samples), unless a scene has that label (its own plot has that
 * name): convergence-all-scenes.svg, convergence-spp-scenes.svg. */
const char *bench_convergence_svg_name(const suite *s, bench_axis axis);

/* A metric as the tables show it ("–" for none, "∞"). */
void bench_fmt_metric(char *buf, size_t cap, double v, int metric);

/* ---- the report: plots and page (bench_svg.c, bench_html.c) ------------------------------ */

/* The convergence plot of scene sc (no file, and no stale one, when nothing is plotted). */
int bench_write_svg(const char *path, const suite *s, const result *res, int sc);
/* DIR/<bench_convergence_svg_name>: the geometric mean of relMSE over all pairs against the
 * budget of c's axis, log-log, one line per method with its slope in the legend (no file, and
 * no stale one, without the analysis).  bench_write_html writes both axes'. */
int bench_write_convergence_svg(const bench_report *r, const bench_convergence *c);
int bench_write_html(const bench_report *r, const char *path);

/* ---- Slurm (bench_slurm.c) ---------------------------------------------------------------- */

#define BENCH_SLURM_EXTRA_MAX 16
#define BENCH_REF_PASSES_MAX  (1 << 20) /* --reference-passes: as render --passes splits */

typedef struct bench_slurm_opts {
    long tasks;       /* --tasks: the items' array tasks (shards); 0: one per (map, scene) pair */
    long ref_passes;  /* --reference-passes: the tasks each reference is split into */
    long cpus;        /* --cpus: cores per items task (its render threads) */
    long ref_cpus;    /* --reference-cpus: cores per reference task (0: as --cpus) */
    long max_running; /* --max-running: tasks of an array at once (0: no limit) */
    int exclusive;    /* --exclusive: an items task has its node to itself */
    int submit;       /* 0 (--no-submit): write the scripts only */
    const char *partition, *time_limit;
    const char *extra[BENCH_SLURM_EXTRA_MAX]; /* --sbatch OPTION, repeatable */
    int nextra;
} bench_slurm_opts;

/* lumis bench SUITE --slurm: what is not done yet (references' parts, their merge, the shards
 * with items left, the report) as sbatch scripts in DIR/slurm/, with DIR/slurm/submit.sh
 * that submits them as job arrays chained by dependencies; runs it unless !o->submit.
 * Exit code. */
int bench_slurm(const suite *s, const char *suite_path, const char *out, const bench_slurm_opts *o);
/* The report job's account of what the array tasks left undone (after bench --report-only
 * --tasks N --reference-passes P): per items task, its items not done; per pair, a missing
 * reference.  Written to DIR/slurm/status.txt and stderr.  Returns the number of items
 * not done. */
int bench_slurm_status(const suite *s, const char *out, long tasks, long ref_passes);

/* ---- merging (bench_merge.c) --------------------------------------------------------------- */

/* Copies every results/ and previews/ file (and refs/ PNGs) of src into dst. */
int bench_merge_dir(const suite *s, const char *src, const char *dst);

/* ---- the flow (harness.c) ------------------------------------------------------------------ */

/* One run of lumis bench, as its options chose it (tools/lumis/cmd_bench.c checks them). */
typedef struct bench_opts {
    const char *suite_path, *out; /* out NULL: bench-out/SUITE_NAME */
    long jobs, threads, shard_i, shard_n;
    int report_only, merging, sharded, slurm, items_only, merge_refs;
    long ref_task; /* --reference-task; -1: none */
    bench_slurm_opts so;
    int argc; /* the command line: --merge's folders, and the sidecars' and the report's */
    char **argv;
} bench_opts;

/* Reads the suite, checks --out and makes its folders, then runs as o says: --merge folders
 * copied in, --slurm scripts, a reference task or their merge, or the items rendered; then
 * the report (unless sharded) and the Slurm status.  Prints errors itself.  Exit code. */
int bench_main(const bench_opts *o);

#endif
