/* lumis render SCENE.json | --scene NAME ...: the evaluation renderer, with a fixed sample
 * count or a time budget, a progress bar, and a JSON sidecar describing the run. */
#include "cli.h"

#include "lumis/render.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static const char usage[] =
    "usage: lumis render [SCENE.json | --scene NAME] [options] -o OUT.exr\n\n"
    "Renders direct illumination from an environment map (or, with --bounces N, path-traced\n"
    "global illumination).  SCENE.json follows the schema in docs/render.md (camera,\n"
    "environment, objects: sphere, plane, mesh with transform or instances).  Built-in\n"
    "scenes: spheres (Lambert, Ward and GGX spheres, Ergun et al.'s Figure 6), bunny-plane\n"
    "(the Stanford bunny and a sphere on a ground plane) and ward-aniso (Ward alpha_x = 0.5,\n"
    "alpha_y = 0.001: their Figure 7), wu-diffuse, wu-satin, wu-glossy, wu-mixed (the\n"
    "bunny, Suzanne and spheres on a ground plane, diffuse to semi-glossy: Wu's scenes), and\n"
    "headlight, headlight-close (a light-field car headlight lighting a floor and a wall, far\n"
    "and close: Lu et al.'s Fig. 13; lit by the luminaire alone).  Without a map in the scene\n"
    "or --env, the procedural\n"
    "sky lights it.  Writes OUT.exr (linear float), an optional PNG preview, and OUT.json:\n"
    "the settings, timings, rays per second and the sampler's build time and bytes.\n\n"
    "options:\n"
    "  --scene NAME       a built-in scene instead of SCENE.json\n"
    "  --env MAP          .exr/.hdr/.pfm file or sky[:WxH] / studio[:WxH] (default: the\n"
    "                     scene's map, else sky)\n"
    "  --method M         light sampler (see lumis sample --help; default inversion-guided)\n"
    "                     or 'bsdf' for BSDF sampling only\n"
    "  --mis H            balance (default), power, or none (light sampling only)\n"
    "  --lights M         light the scene with a light set instead of sampling the map:\n"
    "                     median-cut, variance-min, fhis, tmms (a variant; docs/lights.md),\n"
    "                     wu (Wu's decomposition: EnvDirects and EnvIndirects), or its\n"
    "                     ablations wu-is, wu-is-mask, wu-is-kmeans,\n"
    "                     wu-original-cut; every light of the pixel's set, one shadow ray\n"
    "                     each (docs/lights.md)\n"
    "  --lights-mode M    point (default): each region as a point light at its centroid,\n"
    "                     deterministic and biased (the preview, and what lumis lights\n"
    "                     exports); stratified: each region as a stratum of the map, one\n"
    "                     direction drawn in every region per sample, MIS with the BSDF\n"
    "                     (--mis): unbiased, converges with --time or --spp\n"
    "  --lights-draws N   stratified: N draws per sample and vertex over regions chosen\n"
    "                     in proportion to a weight of their light there (power, cosine,\n"
    "                     BSDF) instead of one in every region (1 .. 4096; docs/lights.md)\n"
    "  --lights-k K       lights per set (default 64; stratified 32).  Point mode with\n"
    "                     --time and no --lights-k: K is chosen to fill the time at 4\n"
    "                     samples per pixel (or --spp): small pilot renders at K = 4, 64\n"
    "                     and where their fit lands, within a fifth of the budget, fit the\n"
    "                     time (Wu's equal-time rule).  K stays at 4 or more by lowering the\n"
    "                     samples (not a given --spp) first; a K under 4 is said.  With both,\n"
    "                     passes of samples fill the time.  The stratified mode keeps K and\n"
    "                     fills the time with passes\n"
    "  --interleave N     interleaved light sets, the original and N-1 jittered (default 8)\n"
    "  --lights-param P   the light-set method's parameters, NAME=VALUE[,NAME=VALUE...]\n"
    "                     (repeatable; names as in lumis lights --param, docs/lights.md)\n"
    "  --upsample F       Wu: EnvIndirects at 1/F resolution per axis, joint-bilateral\n"
    "                     upsampled and added to the EnvDirects (default 2; 1: 'Ours w/o U';\n"
    "                     the stratified mode's default is 1: the upsampling is a bias)\n"
    "  --fixture FILE     light the scene by a photometric fixture (IES or EULUMDAT;\n"
    "                     docs/photometric.md) instead of its map or its own fixtures:\n"
    "  --fixture-at X,Y,Z     where it is (required with --fixture)\n"
    "  --fixture-aim X,Y,Z    a point it aims at (default straight down, -y)\n"
    "  --fixture-up X,Y,Z     where its local +x points, made perpendicular to the aim\n"
    "                         (C0 of type C, the top of types A, B; default: type C\n"
    "                         tilted from hanging with C0 +x, A and B on a yoke)\n"
    "  --fixture-roll DEG     turned about its aim (default 0)\n"
    "  --fixture-multiplier M its candela times M (default 1)\n"
    "  --fixture-area         its luminous opening (a disk or rectangle), not a point\n"
    "  --luminaire L      replace every luminaire of the scene by L (a manifest written by\n"
    "                     lumis luminaire create, or preset:car|bike|small)\n"
    "  --lum-strategy S   scenes with luminaires (headlight, headlight-close, or a scene file\n"
    "                     with \"luminaires\"): restricted (Lu et al., default), uniform (over\n"
    "                     the restricted box), global (precomputed CDFs, the same samples\n"
    "                     for every point) or auto (per luminaire, the one predicted\n"
    "                     fastest at equal error from the points in view: 'lumis luminaire\n"
    "                     predict'); docs/luminaire.md\n"
    "  --lum-auto-bands   with auto: a band of distance may take its own strategy when that\n"
    "                     is predicted to pay 10% (off: it also applies to what the probes\n"
    "                     missed; docs/results/lu-strategy)\n"
    "  --lum-costs C,IR,IU,R,U,G,RAY  with auto: the cost model in ns (camera ray, per\n"
    "                     image restricted and uniform, per draw restricted, uniform and\n"
    "                     global, per shadow ray; default measured on headlight)\n"
    "  --lum-budget K     luminaire samples per camera sample, shared among images (32)\n"
    "  --lum-kmax N       at most N samples for one image (default: no cap)\n"
    "  --lum-search S     CDF inversion: secant (the paper's) or binary\n"
    "  --lum-depth D      search depth, 0 exact (default); a limit is approximate (biased)\n"
    "  --visibility V     exact (a shadow ray per sample, default), approx (Lu et al. 6.2: a\n"
    "                     ray per basis cell, averaged over each function's cells),\n"
    "                     shadowmap (the same cells read from 256x256 depth maps rendered\n"
    "                     once, as the paper) or none\n"
    "  --sequence Q       where every number comes from (docs/sampling.md): sobol\n"
    "                     (Owen-scrambled (0,2) points, progressive; the default), zsobol\n"
    "                     (the same in z-order: blue-noise error at the --spp given), pmj02,\n"
    "                     halton, stratified, or pcg (independent numbers)\n"
    "  --light-samples N  light samples per camera sample (default 1)\n"
    "  --bsdf-samples N   BSDF samples per camera sample (default 1)\n"
    "  --spp N            camera samples per pixel (default 16)\n"
    "  --pixel-centers    every camera ray through its pixel's centre (no anti-aliasing):\n"
    "                     the noise left is the lights' alone\n"
    "  --passes I/N       render share I (0 to N - 1) of the --spp samples split in N: the\n"
    "                     whole render's samples k = I spp/N ... (I+1) spp/N - 1, the same\n"
    "                     whichever machine draws them; lumis merge joins the shares\n"
    "  --time S           instead of --spp: progressive passes until S seconds of rendering\n"
    "                     (equal-time comparisons; the samples reached are reported)\n"
    "  --bounces N        path tracing with up to N indirect bounces (default 0: direct\n"
    "                     illumination only, the evaluation mode)\n"
    "  --seed S           the image depends on it, never on --threads (default 1)\n"
    "  --threads N        worker threads (default: all cores)\n"
    "  --size WxH         image size (default: the scene's camera)\n"
    "  --blocks K         kd-tree blocks\n"
    "  -o, --output OUT   linear EXR (required)\n"
    "  --png OUT.png      also a tone-mapped PNG preview\n"
    "  --exposure EV      the preview's exposure in stops, or 'auto' (default: the mean\n"
    "                     luminance to 0.18)\n"
    "  --tonemap T        the preview's tone map: clamp (default), reinhard or aces\n"
    "  --sidecar PATH     where the JSON sidecar goes (default: OUT with .json);\n"
    "                     --no-sidecar writes none\n"
    "  --quiet            no progress bar and no summary line\n";

/* "X,Y,Z": three finite numbers within [-1e30, 1e30]. */
static int parse_triple(const char *v, double out[3])
{
    if (tool_parse_doubles(v, out, 3) != 3) return 0;
    return fabs(out[0]) <= 1e30 && fabs(out[1]) <= 1e30 && fabs(out[2]) <= 1e30;
}

/* lumis render's options: the render's, and what the checks after them need. */
typedef struct render_cli {
    tool_render_opts o;
    const char *png_only;    /* --exposure or --tonemap, if given */
    const char *mis;         /* --mis, if given */
    const char *sampler_opt; /* --method or --blocks, if given */
    int spp_given;
} render_cli;

/* The scene, its map and what lights it: --scene, --env, a sampler's --method and
 * --blocks, --lights and its options, --upsample.  -1 when argv[*i] is none of them, else an exit
 * code. */
static int render_lighting_option(render_cli *c, int argc, char **argv, int *i)
{
    tool_render_opts *o = &c->o;
    const char *v;
    long x;
    if (tool_option(argc, argv, i, "--scene", &v)) {
        if (!v) return tool_bad_value("render", "--scene", v, "needs a name");
        o->scene_name = v;
    } else if (tool_option(argc, argv, i, "--env", &v)) {
        if (!v) return tool_bad_value("render", "--env", v, "needs a map");
        o->envspec = v;
    } else if (tool_option(argc, argv, i, "--method", &v)) {
        c->sampler_opt = "--method";
        if (v && strcmp(v, "bsdf") == 0)
            o->bsdf_only = 1;
        else if (!v || lumis_sampler_method_from_name(v, &o->sampler.method) != LUMIS_OK)
            return tool_bad_value("render", "--method", v, "must be a sampler name or 'bsdf'");
    } else if (tool_option(argc, argv, i, "--lights", &v)) {
        if (!v || !tool_lights_method_known(v)) {
            char want[256];
            snprintf(want, sizeof want, "must be one of %s", tool_lights_method_names());
            return tool_bad_value("render", "--lights", v, want);
        }
        o->lights = v;
    } else if (tool_option(argc, argv, i, "--lights-mode", &v)) {
        if (!v || lumis_lights_mode_from_name(v, &o->lights_mode) != LUMIS_OK)
            return tool_bad_value("render", "--lights-mode", v, "must be point or stratified");
    } else if (tool_option(argc, argv, i, "--lights-draws", &v)) {
        if (!tool_parse_int(v, 1, LUMIS_LIGHT_SET_MAX_DRAWS, &x))
            return tool_bad_value("render", "--lights-draws", v, "needs a count in [1, 4096]");
        o->rd.lighting.light_set.draws = (int)x;
    } else if (tool_option(argc, argv, i, "--lights-k", &v)) {
        if (!tool_parse_int(v, 1, 1 << 20, &x))
            return tool_bad_value("render", "--lights-k", v, "needs a count in [1, 2^20]");
        o->lights_k = (int)x;
    } else if (tool_option(argc, argv, i, "--lights-param", &v)) {
        const int prc = tool_light_params_parse(&o->lights_params, "render", "--lights-param", v);
        if (prc != EXIT_OK) return prc;
    } else if (tool_option(argc, argv, i, "--interleave", &v)) {
        if (!tool_parse_int(v, 1, 64, &x))
            return tool_bad_value("render", "--interleave", v, "needs a count in [1, 64]");
        o->interleave = (int)x;
    } else if (tool_option(argc, argv, i, "--upsample", &v)) {
        if (!tool_parse_int(v, 1, 16, &x))
            return tool_bad_value("render", "--upsample", v, "needs a factor in [1, 16]");
        o->upsample = (int)x;
    } else if (tool_option(argc, argv, i, "--blocks", &v)) {
        c->sampler_opt = "--blocks";
        if (!tool_parse_int(v, 1, 1 << 24, &x))
            return tool_bad_value("render", "--blocks", v, "needs a count in [1, 16777216]");
        o->sampler.kdtree_blocks = (int)x;
    } else {
        return -1;
    }
    return EXIT_OK;
}

/* Self-lit scenes: --fixture and its placement, --luminaire, --lum-*, --visibility.  -1 when
 * argv[*i] is none of them, else an exit code. */
static int render_fixture_option(render_cli *c, int argc, char **argv, int *i)
{
    tool_render_opts *o = &c->o;
    const char *v;
    long x;
    if (tool_option(argc, argv, i, "--fixture", &v)) {
        if (!v || !*v) return tool_bad_value("render", "--fixture", v, "needs a file");
        o->fixture = v;
    } else if (tool_option(argc, argv, i, "--fixture-at", &v)) {
        if (!parse_triple(v, o->fixture_at))
            return tool_bad_value("render", "--fixture-at", v, "needs X,Y,Z (three numbers)");
        o->fixture_at_given = 1;
    } else if (tool_option(argc, argv, i, "--fixture-aim", &v)) {
        if (!parse_triple(v, o->fixture_aim))
            return tool_bad_value("render", "--fixture-aim", v, "needs X,Y,Z (three numbers)");
        o->fixture_aim_given = 1;
    } else if (tool_option(argc, argv, i, "--fixture-up", &v)) {
        if (!parse_triple(v, o->fixture_up))
            return tool_bad_value("render", "--fixture-up", v, "needs X,Y,Z (three numbers)");
        o->fixture_up_given = 1;
    } else if (tool_option(argc, argv, i, "--fixture-roll", &v)) {
        if (!tool_parse_double(v, &o->fixture_roll) || fabs(o->fixture_roll) > 36000)
            return tool_bad_value("render", "--fixture-roll", v, "needs degrees");
    } else if (tool_option(argc, argv, i, "--fixture-multiplier", &v)) {
        if (!tool_parse_double(v, &o->fixture_multiplier) || !(o->fixture_multiplier > 0) ||
            o->fixture_multiplier > 1e30)
            return tool_bad_value("render", "--fixture-multiplier", v, "needs a number > 0");
    } else if (strcmp(argv[*i], "--fixture-area") == 0) {
        o->fixture_area = 1;
    } else if (tool_option(argc, argv, i, "--luminaire", &v)) {
        if (!v) return tool_bad_value("render", "--luminaire", v, "needs a manifest or preset");
        o->luminaire = v;
    } else if (tool_option(argc, argv, i, "--lum-strategy", &v)) {
        o->lum_option = "--lum-strategy";
        if (!v || lumis_luminaire_strategy_from_name(v, &o->lum.strategy) != LUMIS_OK)
            return tool_bad_value("render", "--lum-strategy", v,
                                  "must be restricted, uniform, global or auto");
    } else if (strcmp(argv[*i], "--lum-auto-bands") == 0) {
        o->lum_option = "--lum-auto-bands";
        o->lum.auto_bands = 1;
    } else if (tool_option(argc, argv, i, "--lum-costs", &v)) {
        o->lum_option = "--lum-costs";
        if (!v || !tool_parse_costs(v, &o->lum_costs))
            return tool_bad_value("render", "--lum-costs", v, TOOL_COSTS_HELP);
        o->lum_costs_given = 1;
    } else if (tool_option(argc, argv, i, "--lum-budget", &v)) {
        o->lum_option = "--lum-budget";
        if (!tool_parse_int(v, 1, 65536, &x))
            return tool_bad_value("render", "--lum-budget", v, "needs a count in [1, 65536]");
        o->lum.budget = (int)x;
    } else if (tool_option(argc, argv, i, "--lum-kmax", &v)) {
        o->lum_option = "--lum-kmax";
        if (!tool_parse_int(v, 1, 65536, &x))
            return tool_bad_value("render", "--lum-kmax", v, "needs a count in [1, 65536]");
        o->lum.k_max = (int)x;
    } else if (tool_option(argc, argv, i, "--lum-search", &v)) {
        o->lum_option = "--lum-search";
        if (!v || strcmp(v, "default") == 0 ||
            lumis_luminaire_search_from_name(v, &o->lum.search) != LUMIS_OK)
            return tool_bad_value("render", "--lum-search", v, "must be secant or binary");
    } else if (tool_option(argc, argv, i, "--lum-depth", &v)) {
        o->lum_option = "--lum-depth";
        if (!tool_parse_int(v, 0, 64, &x))
            return tool_bad_value("render", "--lum-depth", v,
                                  "needs a count in [0, 64] (0: exact)");
        o->lum.depth = (int)x;
    } else if (tool_option(argc, argv, i, "--visibility", &v)) {
        o->lum_option = "--visibility";
        if (!v || lumis_visibility_from_name(v, &o->lum.visibility) != LUMIS_OK)
            return tool_bad_value("render", "--visibility", v,
                                  "must be exact, approx, shadowmap or none");
    } else {
        return -1;
    }
    return EXIT_OK;
}

/* How the image is sampled: --sequence, --mis, the samples, --passes, --time,
 * --bounces, --seed, --threads, --pixel-centers.  -1 when argv[*i] is none of them, else an exit
 * code. */
static int render_sampling_option(render_cli *c, int argc, char **argv, int *i)
{
    tool_render_opts *o = &c->o;
    const char *v;
    long x;
    double d;
    if (tool_option(argc, argv, i, "--sequence", &v)) {
        if (!v || lumis_sequence_from_name(v, &o->rd.sequence) != LUMIS_OK)
            return tool_bad_value("render", "--sequence", v,
                                  "must be sobol, zsobol, pmj02, halton, stratified, pcg or "
                                  "default");
    } else if (tool_option(argc, argv, i, "--mis", &v)) {
        c->mis = v;
        if (v && strcmp(v, "balance") == 0)
            o->rd.power_heuristic = 0;
        else if (v && strcmp(v, "power") == 0)
            o->rd.power_heuristic = 1;
        else if (v && strcmp(v, "none") == 0)
            o->rd.lighting.estimator = LUMIS_ESTIMATOR_LIGHT;
        else
            return tool_bad_value("render", "--mis", v, "must be balance, power or none");
    } else if (tool_option(argc, argv, i, "--light-samples", &v)) {
        if (!tool_parse_int(v, 1, 4096, &x))
            return tool_bad_value("render", "--light-samples", v, "needs a count in [1, 4096]");
        o->rd.light_samples = (int)x;
    } else if (tool_option(argc, argv, i, "--bsdf-samples", &v)) {
        if (!tool_parse_int(v, 1, 4096, &x))
            return tool_bad_value("render", "--bsdf-samples", v, "needs a count in [1, 4096]");
        o->rd.bsdf_samples = (int)x;
    } else if (tool_option(argc, argv, i, "--spp", &v)) {
        if (!tool_parse_int(v, 1, 1 << 20, &x))
            return tool_bad_value("render", "--spp", v, "needs a count in [1, 2^20]");
        o->rd.spp = (int)x;
        c->spp_given = 1;
    } else if (tool_option(argc, argv, i, "--passes", &v)) {
        long a = -1, b = -1;
        const char *slash = v ? strchr(v, '/') : NULL;
        char head[32];
        if (slash && (size_t)(slash - v) < sizeof head) {
            memcpy(head, v, (size_t)(slash - v));
            head[slash - v] = '\0';
        }
        if (!slash || (size_t)(slash - v) >= sizeof head || !tool_parse_int(head, 0, 1 << 20, &a) ||
            !tool_parse_int(slash + 1, 1, 1 << 20, &b) || a >= b)
            return tool_bad_value("render", "--passes", v, "needs I/N, 0 <= I < N (share I of N)");
        o->pass_index = (int)a;
        o->passes = (int)b;
    } else if (tool_option(argc, argv, i, "--time", &v)) {
        if (!tool_parse_double(v, &d) || !(d > 0.0) || d > 1e6)
            return tool_bad_value("render", "--time", v, "needs seconds, more than 0");
        o->time_budget = d;
    } else if (tool_option(argc, argv, i, "--bounces", &v)) {
        if (!tool_parse_int(v, 0, 1024, &x))
            return tool_bad_value("render", "--bounces", v, "needs a count in [0, 1024]");
        o->rd.max_bounces = (int)x;
    } else if (tool_option(argc, argv, i, "--seed", &v)) {
        if (!tool_parse_int(v, 0, 2147483647L, &x))
            return tool_bad_value("render", "--seed", v, "needs an integer in [0, 2147483647]");
        o->rd.seed = (unsigned long long)x;
    } else if (tool_option(argc, argv, i, "--threads", &v)) {
        if (!tool_parse_int(v, 1, 4096, &x))
            return tool_bad_value("render", "--threads", v, "needs a count in [1, 4096]");
        o->rd.threads = tool_cap_threads("render", (int)x);
    } else if (strcmp(argv[*i], "--pixel-centers") == 0) {
        o->rd.pixel_centers = 1;
    } else {
        return -1;
    }
    return EXIT_OK;
}

/* What is written: --size, -o, --png and its --exposure and --tonemap, --sidecar,
 * --no-sidecar, --quiet.  -1 when argv[*i] is none of them, else an exit code. */
static int render_output_option(render_cli *c, int argc, char **argv, int *i)
{
    tool_render_opts *o = &c->o;
    const char *v;
    if (tool_option(argc, argv, i, "--size", &v)) {
        if (!tool_parse_size(v, &o->width, &o->height) || o->width > 16384 || o->height > 16384)
            return tool_bad_value("render", "--size", v, "needs WxH up to 16384x16384");
    } else if (tool_option(argc, argv, i, "--output", &v) || tool_option(argc, argv, i, "-o", &v)) {
        if (!v || !*v) return tool_bad_value("render", "-o", v, "needs a file");
        o->out = v;
    } else if (tool_option(argc, argv, i, "--png", &v)) {
        if (!v || !*v) return tool_bad_value("render", "--png", v, "needs a file");
        o->png = v;
    } else if (tool_option(argc, argv, i, "--sidecar", &v)) {
        if (!v || !*v) return tool_bad_value("render", "--sidecar", v, "needs a path");
        o->sidecar = v;
    } else if (strcmp(argv[*i], "--no-sidecar") == 0) {
        o->sidecar = "";
    } else if (strcmp(argv[*i], "--quiet") == 0) {
        o->quiet = 1;
    } else if (tool_option(argc, argv, i, "--exposure", &v)) {
        c->png_only = "--exposure";
        int rc =
            tool_exposure_option("render", v, &o->png_options.exposure_ev, &o->png_auto_exposure);
        if (rc != EXIT_OK) return rc;
    } else if (tool_option(argc, argv, i, "--tonemap", &v)) {
        c->png_only = "--tonemap";
        if (!v || lumis_tonemap_from_name(v, &o->png_options.tonemap) != LUMIS_OK)
            return tool_bad_value("render", "--tonemap", v, "must be clamp, reinhard or aces");
    } else {
        return -1;
    }
    return EXIT_OK;
}

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
                            o->fixture_area || o->fixture_roll != 0 || o->fixture_multiplier != 0;
    if (fixture_opt && !o->fixture)
        return tool_usage_error("render", "--fixture-at, -aim, -up, -roll, -multiplier and -area "
                                          "need --fixture FILE");
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
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        }
        int rc = render_lighting_option(&c, argc, argv, &i);
        if (rc < 0) rc = render_fixture_option(&c, argc, argv, &i);
        if (rc < 0) rc = render_sampling_option(&c, argc, argv, &i);
        if (rc < 0) rc = render_output_option(&c, argc, argv, &i);
        if (rc > 0) return rc;
        if (rc == 0) continue;
        if (argv[i][0] != '-' && !o->scene_path)
            o->scene_path = argv[i];
        else
            return tool_usage_error("render", "unknown argument '%s'", argv[i]);
    }
    int rc = render_check(&c);
    if (rc != EXIT_OK) return rc;
    o->sampler_opt = o->bsdf_only ? NULL : c.sampler_opt;
    tool_render_result r;
    rc = tool_render(o, &r);
    lumis_image_destroy(r.image);
    return rc;
}
