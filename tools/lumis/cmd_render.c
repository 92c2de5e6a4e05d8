/* lumis render SCENE.json | --scene NAME ...: the evaluation renderer, with a fixed sample
 * count or a time budget, a progress bar, and a JSON sidecar describing the run. */
#include "cli.h"

#include "lumis/render.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

/* lumis render's options: the render's, and what the checks after them need. */
typedef struct render_cli {
    tool_render_opts o;
    const char *png_only;    /* --exposure or --tonemap, if given */
    const char *mis;         /* --mis, if given */
    const char *sampler_opt; /* --method or --blocks, if given */
    const char *spp_given;   /* --spp, if given */
    const char *fixed_opt;   /* an option that fixes the estimator (the automatic one's off) */
    int no_auto;             /* --no-auto */
    int auto_pilots;         /* --auto-pilots */
} render_cli;

/* --fixture-at, -aim, -up: "X,Y,Z", three finite numbers within [-1e30, 1e30], into the
 * double[3] at opt->at; the int at opt->at2 says it was given. */
static int triple_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    double *out = (double *)((char *)ctx + opt->at);
    if (tool_parse_doubles(v, out, 3) != 3 || !(fabs(out[0]) <= 1e30) || !(fabs(out[1]) <= 1e30) ||
        !(fabs(out[2]) <= 1e30))
        return tool_bad_value(cmd, opt->name, v, "needs X,Y,Z (three numbers)");
    *(int *)((char *)ctx + opt->at2) = 1;
    return EXIT_OK;
}

static int method_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    tool_render_opts *o = &((render_cli *)ctx)->o;
    if (v && strcmp(v, "bsdf") == 0)
        o->bsdf_only = 1;
    else if (!v || lumis_sampler_method_from_name(v, &o->sampler.method) != LUMIS_OK)
        return tool_bad_value(cmd, opt->name, v, "must be a sampler name or 'bsdf'");
    return EXIT_OK;
}

static int lights_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    if (!v || !tool_lights_method_known(v)) {
        char want[256];
        snprintf(want, sizeof want, "must be one of %s", tool_lights_method_names());
        return tool_bad_value(cmd, opt->name, v, want);
    }
    ((render_cli *)ctx)->o.lights = v;
    return EXIT_OK;
}

static int lights_param_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    return tool_light_params_parse(&((render_cli *)ctx)->o.lights_params, cmd, opt->name, v);
}

static int lum_costs_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    tool_render_opts *o = &((render_cli *)ctx)->o;
    if (!v || !tool_parse_costs(v, &o->lum_costs))
        return tool_bad_value(cmd, opt->name, v, TOOL_COSTS_HELP);
    o->lum_costs_given = 1;
    return EXIT_OK;
}

static int mis_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    tool_render_opts *o = &((render_cli *)ctx)->o;
    ((render_cli *)ctx)->mis = v;
    if (v && strcmp(v, "balance") == 0)
        o->rd.power_heuristic = 0;
    else if (v && strcmp(v, "power") == 0)
        o->rd.power_heuristic = 1;
    else if (v && strcmp(v, "none") == 0)
        o->rd.lighting.estimator = LUMIS_ESTIMATOR_LIGHT;
    else
        return tool_bad_value(cmd, opt->name, v, "must be balance, power or none");
    return EXIT_OK;
}

static int passes_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    tool_render_opts *o = &((render_cli *)ctx)->o;
    long a = -1, b = -1;
    const char *slash = v ? strchr(v, '/') : NULL;
    char head[32];
    if (slash && (size_t)(slash - v) < sizeof head) {
        memcpy(head, v, (size_t)(slash - v));
        head[slash - v] = '\0';
    }
    if (!slash || (size_t)(slash - v) >= sizeof head || !tool_parse_int(head, 0, 1 << 20, &a) ||
        !tool_parse_int(slash + 1, 1, 1 << 20, &b) || a >= b)
        return tool_bad_value(cmd, opt->name, v, "needs I/N, 0 <= I < N (share I of N)");
    o->pass_index = (int)a;
    o->passes = (int)b;
    return EXIT_OK;
}

static int no_sidecar_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    (void)cmd, (void)opt, (void)v;
    ((render_cli *)ctx)->o.sidecar = "";
    return EXIT_OK;
}

static int parse_lights_mode(const char *v, void *field)
{
    return lumis_lights_mode_from_name(v, field) == LUMIS_OK;
}
static int parse_strategy(const char *v, void *field)
{
    return lumis_luminaire_strategy_from_name(v, field) == LUMIS_OK;
}
static int parse_search(const char *v, void *field)
{
    return strcmp(v, "default") != 0 && lumis_luminaire_search_from_name(v, field) == LUMIS_OK;
}
static int parse_visibility(const char *v, void *field)
{
    return lumis_visibility_from_name(v, field) == LUMIS_OK;
}
static int parse_sequence(const char *v, void *field)
{
    return lumis_sequence_from_name(v, field) == LUMIS_OK;
}

#define AT(f)    offsetof(render_cli, o.f)
#define LUM_NOTE TOOL_NOTE(render_cli, o.lum_option)
static const tool_opt render_opts[] = {
    {.kind = TOOL_OPT_GROUP, .name = "the scene and its lighting"},
    {.kind = TOOL_OPT_STRING,
     .name = "--scene",
     .metavar = "NAME",
     .help = "a built-in scene instead of SCENE.json",
     .at = AT(scene_name),
     .what = "a name"},
    {.kind = TOOL_OPT_STRING,
     .name = "--env",
     .metavar = "MAP",
     .help = ".exr/.hdr/.pfm file or sky[:WxH] / studio[:WxH] (default: the\n"
             "scene's map, else sky)",
     .at = AT(envspec),
     .what = "a map"},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--method",
     .metavar = "M",
     .help = "light sampler (see lumis sample --help; default inversion-guided)\n"
             "or 'bsdf' for BSDF sampling only",
     .handle = method_option,
     .note = TOOL_NOTE(render_cli, sampler_opt)},
    {.kind = TOOL_OPT_INT,
     .name = "--blocks",
     .metavar = "K",
     .help = "kd-tree blocks",
     .at = AT(sampler.kdtree_blocks),
     .lo = 1,
     .hi = 1 << 24,
     .note = TOOL_NOTE(render_cli, sampler_opt)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--auto",
     .help = "the automatic estimator (the default for a map's light when no\n"
             "option below fixes one), predicted from the scene: the surfaces the\n"
             "camera sees (a grid of rays) reflecting mostly diffusely (a diffuse\n"
             "share >= 0.5) get the map's median-cut regions as strata (K = 32),\n"
             "mostly glossy ones the map sampled with MIS.  Given, --method and\n"
             "--blocks choose the MIS candidate's sampler.  docs/render.md",
     .at = AT(auto_estimator)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--auto-pilots",
     .help = "the automatic estimator, chosen by pilot renders of the scene instead:\n"
             "MIS, strata at K = 16, 32, 64 and, on a sun-dominated map, the image\n"
             "sun split off, whichever the pilots find most efficient (relMSE x\n"
             "time; at most 15 % of --time, or of the render).  docs/render.md",
     .at = offsetof(render_cli, auto_pilots)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--no-auto",
     .help = "no automatic estimator: the map sampled with MIS (inversion-guided),\n"
             "as before 2026-11-28.  Any of --method, --blocks, --lights, --sun,\n"
             "--lights-mode, --lights-draws, --lights-k, --interleave,\n"
             "--lights-param, --upsample, --mis, --light-samples, --bsdf-samples\n"
             "or --passes fixes the estimator too",
     .at = offsetof(render_cli, no_auto)},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--lights",
     .metavar = "M",
     .help = "light the scene with a light set instead of sampling the map:\n"
             "median-cut, variance-min, fhis, tmms (a variant; docs/lights.md),\n"
             "wu (Wu's decomposition: EnvDirects and EnvIndirects), or its\n"
             "ablations wu-is, wu-is-mask, wu-is-kmeans,\n"
             "wu-original-cut; every light of the pixel's set, one shadow ray\n"
             "each (docs/lights.md)",
     .handle = lights_option,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--sun",
     .help = "find a compact bright source in the map (lumis_sun_find) and\n"
             "sample its pixels by their power, MIS with the BSDF, the rest (the\n"
             "residual) by the sampler or the light set; unbiased (docs/lights.md,\n"
             "\"The image sun\"); no sun found: the whole map as usual",
     .at = AT(sun),
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_PARSE,
     .name = "--lights-mode",
     .metavar = "M",
     .help = "point (default): each region as a point light at its centroid,\n"
             "deterministic and biased (the preview, and what lumis lights\n"
             "exports); stratified: each region as a stratum of the map, one\n"
             "direction drawn in every region per sample, MIS with the BSDF\n"
             "(--mis): unbiased, converges with --time or --spp",
     .at = AT(lights_mode),
     .parse = parse_lights_mode,
     .what = "must be point or stratified",
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_INT,
     .name = "--lights-draws",
     .metavar = "N",
     .help = "stratified: N draws per sample and vertex over regions chosen\n"
             "in proportion to a weight of their light there (power, cosine,\n"
             "BSDF) instead of one in every region (docs/lights.md)",
     .at = AT(rd.lighting.light_set.draws),
     .lo = 1,
     .hi = LUMIS_LIGHT_SET_MAX_DRAWS,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_INT,
     .name = "--lights-region-draws",
     .metavar = "N",
     .help = "stratified: N draws per sample and vertex in all, at least one\n"
             "in every region, the rest to the regions of most noise (power x\n"
             "solid angle^1/4), fixed before the render (docs/lights.md)",
     .at = AT(rd.lighting.light_set.region_draws),
     .lo = 1,
     .hi = LUMIS_LIGHT_SET_MAX_DRAWS,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_INT,
     .name = "--lights-k",
     .metavar = "K",
     .help = "lights per set (default 64; stratified 32).  Point mode with\n"
             "--time and no --lights-k: K is chosen to fill the time at 4\n"
             "samples per pixel (or --spp): small pilot renders at K = 4, 64\n"
             "and where their fit lands, within a fifth of the budget, fit the\n"
             "time (Wu's equal-time rule).  K stays at 4 or more by lowering the\n"
             "samples (not a given --spp) first; a K under 4 is said.  With both,\n"
             "passes of samples fill the time.  The stratified mode keeps K and\n"
             "fills the time with passes",
     .at = AT(lights_k),
     .lo = 1,
     .hi = 1 << 20,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_INT,
     .name = "--interleave",
     .metavar = "N",
     .help = "interleaved light sets, the original and N-1 jittered (default 8)",
     .at = AT(interleave),
     .lo = 1,
     .hi = 64,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--lights-param",
     .metavar = "P",
     .help = "the light-set method's parameters, NAME=VALUE[,NAME=VALUE...]\n"
             "(repeatable; names as in lumis lights --param, docs/lights.md)",
     .handle = lights_param_option,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_INT,
     .name = "--upsample",
     .metavar = "F",
     .help = "Wu: EnvIndirects at 1/F resolution per axis, joint-bilateral\n"
             "upsampled and added to the EnvDirects (default 2; 1: 'Ours w/o U';\n"
             "the stratified mode's default is 1: the upsampling is a bias)",
     .at = AT(upsample),
     .lo = 1,
     .hi = 16,
     .what = "a factor",
     .note = TOOL_NOTE(render_cli, fixed_opt)},

    {.kind = TOOL_OPT_GROUP, .name = "photometric fixtures"},
    {.kind = TOOL_OPT_STRING,
     .name = "--fixture",
     .metavar = "FILE",
     .help = "light the scene by a photometric fixture (IES or EULUMDAT;\n"
             "docs/photometric.md) instead of its map or its own fixtures",
     .at = AT(fixture),
     .what = "a file"},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--fixture-at",
     .metavar = "X,Y,Z",
     .help = "where it is (required with --fixture)",
     .handle = triple_option,
     .at = AT(fixture_at),
     .at2 = AT(fixture_at_given)},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--fixture-aim",
     .metavar = "X,Y,Z",
     .help = "a point it aims at (default straight down, -y)",
     .handle = triple_option,
     .at = AT(fixture_aim),
     .at2 = AT(fixture_aim_given)},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--fixture-up",
     .metavar = "X,Y,Z",
     .help = "where its local +x points, made perpendicular to the aim\n"
             "(C0 of type C, the top of types A, B; default: type C\n"
             "tilted from hanging with C0 +x, A and B on a yoke)",
     .handle = triple_option,
     .at = AT(fixture_up),
     .at2 = AT(fixture_up_given)},
    {.kind = TOOL_OPT_DOUBLE,
     .name = "--fixture-roll",
     .metavar = "DEG",
     .help = "turned about its aim (default 0)",
     .at = AT(fixture_roll),
     .lo = -36000,
     .hi = 36000,
     .what = "degrees"},
    {.kind = TOOL_OPT_DOUBLE,
     .name = "--fixture-multiplier",
     .metavar = "M",
     .help = "its candela times M (default 1)",
     .at = AT(fixture_multiplier),
     .lo = 0,
     .open_lo = 1,
     .hi = 1e30},
    {.kind = TOOL_OPT_FLAG,
     .name = "--fixture-area",
     .help = "its luminous opening (a disk or rectangle), not a point",
     .at = AT(fixture_area)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--fixture-near-field",
     .help = "a near-field fixture: the light field of its opening (made as the\n"
             "render starts) near it, its table far away, blended where the\n"
             "field's measured error meets the point model's (docs/photometric.md)",
     .at = AT(fixture_near_field)},

    {.kind = TOOL_OPT_GROUP, .name = "luminaires"},
    {.kind = TOOL_OPT_STRING,
     .name = "--luminaire",
     .metavar = "L",
     .help = "replace every luminaire of the scene by L (a manifest written by\n"
             "lumis luminaire create, or preset:car|bike|small)",
     .at = AT(luminaire),
     .what = "a manifest or preset"},
    {.kind = TOOL_OPT_PARSE,
     .name = "--lum-strategy",
     .metavar = "S",
     .help = "scenes with luminaires (headlight, headlight-close, or a scene file\n"
             "with \"luminaires\"): restricted (Lu et al., default), uniform (over\n"
             "the restricted box), global (precomputed CDFs, the same samples\n"
             "for every point) or auto (per luminaire, the one predicted\n"
             "fastest at equal error from the points in view: 'lumis luminaire\n"
             "predict'); docs/luminaire.md",
     .at = AT(lum.strategy),
     .parse = parse_strategy,
     .what = "must be restricted, uniform, global or auto",
     .note = LUM_NOTE},
    {.kind = TOOL_OPT_FLAG,
     .name = "--lum-auto-bands",
     .help = "with auto: a band of distance may take its own strategy when that\n"
             "is predicted to pay 10% (off: it also applies to what the probes\n"
             "missed; docs/results/lu-strategy)",
     .at = AT(lum.auto_bands),
     .note = LUM_NOTE},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--lum-costs",
     .metavar = "C,IR,IU,R,U,G,RAY",
     .help = "with auto: the cost model in ns (camera ray, per\n"
             "image restricted and uniform, per draw restricted, uniform and\n"
             "global, per shadow ray; default measured on headlight)",
     .handle = lum_costs_option,
     .note = LUM_NOTE},
    {.kind = TOOL_OPT_INT,
     .name = "--lum-budget",
     .metavar = "K",
     .help = "luminaire samples per camera sample, shared among images (32)",
     .at = AT(lum.budget),
     .lo = 1,
     .hi = 65536,
     .note = LUM_NOTE},
    {.kind = TOOL_OPT_INT,
     .name = "--lum-kmax",
     .metavar = "N",
     .help = "at most N samples for one image (default: no cap)",
     .at = AT(lum.k_max),
     .lo = 1,
     .hi = 65536,
     .note = LUM_NOTE},
    {.kind = TOOL_OPT_PARSE,
     .name = "--lum-search",
     .metavar = "S",
     .help = "CDF inversion: secant (the paper's) or binary",
     .at = AT(lum.search),
     .parse = parse_search,
     .what = "must be secant or binary",
     .note = LUM_NOTE},
    {.kind = TOOL_OPT_INT,
     .name = "--lum-depth",
     .metavar = "D",
     .help = "search depth, 0 exact (default); a limit is approximate (biased)",
     .at = AT(lum.depth),
     .lo = 0,
     .hi = 64,
     .note = LUM_NOTE},
    {.kind = TOOL_OPT_PARSE,
     .name = "--visibility",
     .metavar = "V",
     .help = "exact (a shadow ray per sample, default), approx (Lu et al. 6.2: a\n"
             "ray per basis cell, averaged over each function's cells),\n"
             "shadowmap (the same cells read from 256x256 depth maps rendered\n"
             "once, as the paper) or none",
     .at = AT(lum.visibility),
     .parse = parse_visibility,
     .what = "must be exact, approx, shadowmap or none",
     .note = LUM_NOTE},

    {.kind = TOOL_OPT_GROUP, .name = "sampling"},
    {.kind = TOOL_OPT_PARSE,
     .name = "--sequence",
     .metavar = "Q",
     .help = "where every number comes from (docs/sampling.md): sobol\n"
             "(Owen-scrambled (0,2) points, progressive; the default), zsobol\n"
             "(the same in z-order: blue-noise error at the --spp given), pmj02,\n"
             "halton, stratified, or pcg (independent numbers)",
     .at = AT(rd.sequence),
     .parse = parse_sequence,
     .what = "must be sobol, zsobol, pmj02, halton, stratified, pcg or default"},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--mis",
     .metavar = "H",
     .help = "balance (default), power, or none (light sampling only)",
     .handle = mis_option,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_INT,
     .name = "--light-samples",
     .metavar = "N",
     .help = "light samples per camera sample (default 1)",
     .at = AT(rd.light_samples),
     .lo = 1,
     .hi = 4096,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_INT,
     .name = "--bsdf-samples",
     .metavar = "N",
     .help = "BSDF samples per camera sample (default 1)",
     .at = AT(rd.bsdf_samples),
     .lo = 1,
     .hi = 4096,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_INT,
     .name = "--spp",
     .metavar = "N",
     .help = "camera samples per pixel (default 16)",
     .at = AT(rd.spp),
     .lo = 1,
     .hi = 1 << 20,
     .note = TOOL_NOTE(render_cli, spp_given)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--pixel-centers",
     .help = "every camera ray through its pixel's centre (no anti-aliasing):\n"
             "the noise left is the lights' alone",
     .at = AT(rd.pixel_centers)},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--passes",
     .metavar = "I/N",
     .help = "render share I (0 to N - 1) of the --spp samples split in N: the\n"
             "whole render's samples k = I spp/N ... (I+1) spp/N - 1, the same\n"
             "whichever machine draws them; lumis merge joins the shares",
     .handle = passes_option,
     .note = TOOL_NOTE(render_cli, fixed_opt)},
    {.kind = TOOL_OPT_DOUBLE,
     .name = "--time",
     .metavar = "S",
     .help = "instead of --spp: progressive passes until S seconds of rendering\n"
             "(equal-time comparisons; the samples reached are reported)",
     .at = AT(time_budget),
     .lo = 0,
     .open_lo = 1,
     .hi = 1e6,
     .what = "seconds"},
    {.kind = TOOL_OPT_INT,
     .name = "--bounces",
     .metavar = "N",
     .help = "path tracing with up to N indirect bounces (default 0: direct\n"
             "illumination only, the evaluation mode)",
     .at = AT(rd.max_bounces),
     .lo = 0,
     .hi = 1024},
    {.kind = TOOL_OPT_U64,
     .name = "--seed",
     .metavar = "S",
     .help = "the image depends on it, never on --threads (default 1)",
     .at = AT(rd.seed),
     .hi = 2147483647.0},
    {.kind = TOOL_OPT_INT,
     .name = "--threads",
     .metavar = "N",
     .help = "worker threads (default: all cores)",
     .at = AT(rd.threads),
     .lo = 1,
     .hi = 4096},

    {.kind = TOOL_OPT_GROUP, .name = "output"},
    {.kind = TOOL_OPT_SIZE,
     .name = "--size",
     .metavar = "WxH",
     .help = "image size (default: the scene's camera)",
     .at = AT(width),
     .at2 = AT(height),
     .hi = 16384},
    {.kind = TOOL_OPT_STRING,
     .name = "--output",
     .alias = "-o",
     .metavar = "OUT",
     .help = "linear EXR (required)",
     .at = AT(out),
     .what = "a file"},
    {.kind = TOOL_OPT_STRING,
     .name = "--png",
     .metavar = "OUT.png",
     .help = "also a tone-mapped PNG preview",
     .at = AT(png),
     .what = "a file"},
    {.kind = TOOL_OPT_EXPOSURE,
     .name = "--exposure",
     .metavar = "EV",
     .help = "the preview's exposure in stops, or 'auto' (default: the mean\n"
             "luminance to 0.18)",
     .at = AT(png_options.exposure_ev),
     .at2 = AT(png_auto_exposure),
     .note = TOOL_NOTE(render_cli, png_only)},
    {.kind = TOOL_OPT_PARSE,
     .name = "--tonemap",
     .metavar = "T",
     .help = "the preview's tone map: clamp (default), reinhard or aces",
     .at = AT(png_options.tonemap),
     .parse = tool_opt_tonemap,
     .what = TOOL_TONEMAP_WHAT,
     .note = TOOL_NOTE(render_cli, png_only)},
    {.kind = TOOL_OPT_STRING,
     .name = "--sidecar",
     .metavar = "PATH",
     .help = "where the JSON sidecar goes (default: OUT with .json)",
     .at = AT(sidecar),
     .what = "a path"},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--no-sidecar",
     .help = "write no JSON sidecar",
     .handle = no_sidecar_option},
    {.kind = TOOL_OPT_FLAG,
     .name = "--quiet",
     .help = "no progress bar and no summary line",
     .at = AT(quiet)},
    {0},
};

static int render_positional(const char *cmd, const char *arg, void *ctx)
{
    tool_render_opts *o = &((render_cli *)ctx)->o;
    if (o->scene_path) return tool_usage_error(cmd, "unknown argument '%s'", arg);
    o->scene_path = arg;
    return EXIT_OK;
}

const tool_optspec tool_render_spec = {
    .cmd = "render",
    .usage = "usage: lumis render [SCENE.json | --scene NAME] [options] -o OUT.exr",
    .intro =
        "Renders direct illumination from an environment map (or, with --bounces N, path-traced\n"
        "global illumination).  SCENE.json follows the schema in docs/render.md (camera,\n"
        "environment, objects: sphere, plane, mesh with transform or instances).  Built-in\n"
        "scenes: spheres (Lambert, Ward and GGX spheres, Ergun et al.'s Figure 6), bunny-plane\n"
        "(the Stanford bunny and a sphere on a ground plane) and ward-aniso (Ward alpha_x = 0.5,\n"
        "alpha_y = 0.001: their Figure 7), wu-diffuse, wu-satin, wu-glossy, wu-mixed (the\n"
        "bunny, Suzanne and spheres on a ground plane, diffuse to semi-glossy: Wu's scenes), and\n"
        "headlight, headlight-close (a light-field car headlight lighting a floor and a wall, far\n"
        "and close: Lu et al.'s Fig. 13; lit by the luminaire alone).  Without a map in the scene\n"
        "or --env, the procedural sky lights it.  Writes OUT.exr (linear float), an optional PNG\n"
        "preview, and OUT.json: the settings, timings, rays per second and the sampler's build\n"
        "time and bytes.",
    .opts = render_opts,
    .positional = render_positional,
};

/* The options that contradict each other or lack another (which choices go together
 * is the library's to say, in tool_render).  Exit code. */
static int render_check(render_cli *c)
{
    tool_render_opts *o = &c->o;
    if (!o->scene_name == !o->scene_path)
        return tool_usage_error("render", "give one scene: SCENE.json or --scene NAME");
    if (o->scene_name) {
        int known = 0;
        char names[512] = "";
        size_t used = 0;
        for (const char *const *n = lumis_scene_builtin_names(); *n; n++) {
            known |= strcmp(*n, o->scene_name) == 0;
            if (used < sizeof names)
                used += (size_t)snprintf(names + used, sizeof names - used, "%s%s",
                                         used ? ", " : "", *n);
        }
        if (!known)
            return tool_usage_error("render", "unknown scene '%s' (built in: %s)", o->scene_name,
                                    names);
    }
    const int stratified = o->lights && o->lights_mode == LUMIS_LIGHTS_STRATIFIED;
    if (c->spp_given && o->time_budget > 0.0 && (!o->lights || stratified))
        return tool_usage_error("render", "give --spp or --time, not both (both go together "
                                          "only with --lights in point mode)");
    if (o->passes && o->time_budget > 0.0)
        return tool_usage_error("render", "--passes splits a number of samples (--spp), not a "
                                          "time budget");
    if (o->passes > (o->rd.spp ? o->rd.spp : 16))
        return tool_usage_error("render", "--passes %d/%d: more shares than the %d samples",
                                o->pass_index, o->passes, o->rd.spp ? o->rd.spp : 16);
    if (o->lights && o->time_budget > 0.0 && o->lights_k && c->spp_given)
        return tool_usage_error("render", "--lights-k K with --time fills the time with "
                                          "samples: --spp does not apply");
    if (!o->out) return tool_usage_error("render", "no output file (-o OUT.exr)");
    if (c->png_only && !o->png)
        return tool_usage_error("render", "%s applies to the PNG preview: give --png OUT.png",
                                c->png_only);
    if (o->lights) {
        const int prc =
            tool_light_params_check(&o->lights_params, "render", "--lights-param", o->lights);
        if (prc != EXIT_OK) return prc;
    }
    /* Which choices go together is the library's to say (lumis_session_check, when the
     * scene is loaded: tool_render); here only flags that contradict each other. */
    if (c->mis && o->bsdf_only)
        return tool_usage_error("render",
                                "--mis %s: --method bsdf samples the BSDF only and "
                                "combines nothing",
                                c->mis);
    const int fixture_opt = o->fixture_at_given || o->fixture_aim_given || o->fixture_up_given ||
                            o->fixture_area || o->fixture_near_field || o->fixture_roll != 0 ||
                            o->fixture_multiplier != 0;
    if (fixture_opt && !o->fixture)
        return tool_usage_error("render", "--fixture-at, -aim, -up, -roll, -multiplier, -area "
                                          "and -near-field need --fixture FILE");
    /* before the field is made (seconds): the library refuses the pair too (light_field) */
    if (o->fixture_near_field && o->fixture_area)
        return tool_usage_error("render", "--fixture-near-field: a point with a light field near "
                                          "it (lighting.photometric's light_field), not an "
                                          "opening: drop --fixture-area");
    if (o->fixture && !o->fixture_at_given)
        return tool_usage_error("render", "--fixture %s needs --fixture-at X,Y,Z", o->fixture);
    return EXIT_OK;
}

int cmd_render(int argc, char **argv)
{
    render_cli c;
    memset(&c, 0, sizeof c);
    tool_render_opts *o = &c.o;
    o->scale = 1.0f;
    o->rd.seed = 1;
    o->png_auto_exposure = 1;
    o->lum.strategy = LUMIS_LUM_RESTRICTED;
    o->argc = argc;
    o->argv = argv;
    int rc = tool_optparse(&tool_render_spec, argc, argv, &c);
    if (rc >= 0) return rc;
    if (o->rd.threads) o->rd.threads = tool_cap_threads("render", o->rd.threads);
    rc = render_check(&c);
    if (rc != EXIT_OK) return rc;
    o->sampler_opt = o->bsdf_only ? NULL : c.sampler_opt;
    /* The automatic estimator is the default for a map's light: an option that fixes the
     * estimator, or --no-auto, turns it off (tool_render applies it when the map lights the
     * scene; luminaires and fixtures are not its). */
    if ((o->auto_estimator || c.auto_pilots) && c.no_auto)
        return tool_usage_error("render", "--%s and --no-auto: give one",
                                c.auto_pilots ? "auto-pilots" : "auto");
    if (o->auto_estimator && c.auto_pilots)
        return tool_usage_error("render", "--auto and --auto-pilots: give one");
    if (c.auto_pilots)
        o->auto_estimator = LUMIS_AUTO_PILOTS;
    else if (o->auto_estimator)
        o->auto_estimator = LUMIS_AUTO_PREDICT;
    o->auto_fixed_by = c.no_auto ? "--no-auto" : c.fixed_opt ? c.fixed_opt : c.sampler_opt;
    o->auto_default = !o->auto_estimator && !o->auto_fixed_by;
    tool_render_result r;
    rc = tool_render(o, &r);
    lumis_image_destroy(r.image);
    return rc;
}
