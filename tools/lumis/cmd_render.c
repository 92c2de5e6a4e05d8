/* lumis render --scene NAME ...: the evaluation renderer on a built-in scene. */
#include "common.h"

#include "lumis/render.h"

#include <string.h>

static const char usage[] =
    "usage: lumis render [SCENE.json | --scene spheres] [options] -o OUT.exr\n\n"
    "Renders direct illumination from an environment map.  SCENE.json follows the schema\n"
    "in lumis/render.h (camera, environment, objects: sphere, plane, mesh); built-in\n"
    "scenes: spheres (Lambert, Ward and GGX spheres, as in Ergun et al.'s Figure 6) and\n"
    "ward-aniso (a sphere with Ward alpha_x = 0.5, alpha_y = 0.001: their Figure 7).\n"
    "Without a map in the scene or --env, the procedural sky lights it.  --time, the\n"
    "JSON sidecar and the other built-in scenes are not implemented yet.\n\n"
    "options:\n"
    "  --env MAP          .exr/.hdr/.pfm file or sky[:WxH] / studio[:WxH] (default sky)\n"
    "  --method M         light sampler (see lumis sample --help; default inversion-guided)\n"
    "                     or 'bsdf' for BSDF sampling only\n"
    "  --mis H            balance (default), power, or none (light sampling only)\n"
    "  --spp N            camera samples per pixel (default 16)\n"
    "  --seed S           the image depends on it, never on --threads (default 1)\n"
    "  --threads N        worker threads (default: all cores)\n"
    "  --size WxH         image size (default 600x240)\n"
    "  --blocks K         kd-tree blocks\n"
    "  -o, --output OUT   linear EXR (required)\n"
    "  --png OUT          also a tone-mapped PNG preview (--exposure EV, --tonemap T)\n";

/* One sphere with the anisotropic Ward BRDF of Ergun et al.'s Figure 7. */
static int scene_ward_aniso(lumis_object o[3], lumis_camera *cam)
{
    memset(&o[0], 0, sizeof o[0]);
    o[0].type = LUMIS_OBJECT_SPHERE;
    o[0].radius = 1.0f;
    o[0].material =
        (lumis_bsdf){LUMIS_BSDF_WARD, {0.05f, 0.05f, 0.05f}, {0.5f, 0.5f, 0.5f}, 0.5f, 0.001f};
    *cam = (lumis_camera){{0, 0.5f, 4.0f}, {0, 0, 0}, {0, 1, 0}, 35.0f, 400, 400};
    return 1;
}

/* Three spheres of different materials side by side. */
static int scene_spheres(lumis_object o[3], lumis_camera *cam)
{
    const float xs[3] = {-2.3f, 0.0f, 2.3f};
    const lumis_bsdf mats[3] = {
        {LUMIS_BSDF_LAMBERT, {0.8f, 0.8f, 0.8f}, {0, 0, 0}, 0, 0},
        {LUMIS_BSDF_WARD, {0.1f, 0.1f, 0.1f}, {0.3f, 0.3f, 0.3f}, 0.1f, 0.1f},
        {LUMIS_BSDF_GGX_CONDUCTOR, {0, 0, 0}, {0.95f, 0.64f, 0.54f}, 0.15f, 0.15f},
    };
    for (int k = 0; k < 3; k++) {
        memset(&o[k], 0, sizeof o[k]);
        o[k].type = LUMIS_OBJECT_SPHERE;
        o[k].center = (lumis_vec3){xs[k], 0.0f, 0.0f};
        o[k].radius = 1.0f;
        o[k].material = mats[k];
    }
    *cam = (lumis_camera){{0, 0.6f, 8.0f}, {0, 0, 0}, {0, 1, 0}, 30.0f, 600, 240};
    return 3;
}

int cmd_render(int argc, char **argv)
{
    const char *scene_name = NULL, *scene_path = NULL, *envspec = NULL, *out = NULL, *png = NULL,
               *v;
    lumis_sampler_desc sd = {0};
    lumis_render_desc rd = {0};
    lumis_write_options pw = {0};
    int bsdf_only = 0, w = 0, h = 0;
    rd.seed = 1;
    for (int i = 1; i < argc; i++) {
        long x;
        double ev;
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--scene", &v)) {
            scene_name = v;
        } else if (tool_option(argc, argv, &i, "--env", &v)) {
            if (!v) return tool_usage_error("render", "--env needs a map");
            envspec = v;
        } else if (tool_option(argc, argv, &i, "--method", &v)) {
            if (v && strcmp(v, "bsdf") == 0)
                bsdf_only = 1;
            else if (!v || lumis_sampler_method_from_name(v, &sd.method) != LUMIS_OK)
                return tool_usage_error("render", "--method must be a sampler name or 'bsdf'");
        } else if (tool_option(argc, argv, &i, "--mis", &v)) {
            if (v && strcmp(v, "balance") == 0)
                rd.power_heuristic = 0;
            else if (v && strcmp(v, "power") == 0)
                rd.power_heuristic = 1;
            else if (v && strcmp(v, "none") == 0)
                rd.estimator = LUMIS_ESTIMATOR_LIGHT;
            else
                return tool_usage_error("render", "--mis must be balance, power or none");
        } else if (tool_option(argc, argv, &i, "--spp", &v)) {
            if (!tool_parse_int(v, 1, 1 << 20, &x))
                return tool_usage_error("render", "--spp needs a count");
            rd.spp = (int)x;
        } else if (tool_option(argc, argv, &i, "--seed", &v)) {
            if (!tool_parse_int(v, 0, 2147483647L, &x))
                return tool_usage_error("render", "--seed needs an integer");
            rd.seed = (unsigned long long)x;
        } else if (tool_option(argc, argv, &i, "--threads", &v)) {
            if (!tool_parse_int(v, 1, 4096, &x))
                return tool_usage_error("render", "--threads needs a count");
            rd.threads = (int)x;
        } else if (tool_option(argc, argv, &i, "--blocks", &v)) {
            if (!tool_parse_int(v, 1, 1 << 24, &x))
                return tool_usage_error("render", "--blocks needs a count");
            sd.kdtree_blocks = (int)x;
        } else if (tool_option(argc, argv, &i, "--size", &v)) {
            if (!tool_parse_size(v, &w, &h) || w > 16384 || h > 16384)
                return tool_usage_error("render", "--size needs WxH up to 16384x16384");
        } else if (tool_option(argc, argv, &i, "--output", &v) ||
                   tool_option(argc, argv, &i, "-o", &v)) {
            out = v;
        } else if (tool_option(argc, argv, &i, "--png", &v)) {
            png = v;
        } else if (tool_option(argc, argv, &i, "--exposure", &v)) {
            if (!tool_parse_double(v, &ev) || ev < -64 || ev > 64)
                return tool_usage_error("render", "--exposure needs stops");
            pw.exposure_ev = (float)ev;
        } else if (tool_option(argc, argv, &i, "--tonemap", &v)) {
            if (!v || lumis_tonemap_from_name(v, &pw.tonemap) != LUMIS_OK)
                return tool_usage_error("render", "--tonemap must be clamp, reinhard or aces");
        } else if (argv[i][0] != '-' && !scene_path) {
            scene_path = argv[i];
        } else {
            return tool_usage_error("render", "unknown argument '%s'", argv[i]);
        }
    }
    if (!scene_name == !scene_path)
        return tool_usage_error("render", "give one scene: SCENE.json or --scene NAME");
    if (scene_name && strcmp(scene_name, "spheres") != 0 && strcmp(scene_name, "ward-aniso") != 0)
        return tool_usage_error("render", "unknown scene '%s' (built in: spheres, ward-aniso)",
                                scene_name);
    if (!out) return tool_usage_error("render", "no output file (-o OUT.exr)");
    if (bsdf_only) rd.estimator = LUMIS_ESTIMATOR_BSDF;

    lumis_object builtin[3];
    const lumis_object *objs = builtin;
    lumis_camera cam;
    lumis_scene_file *file = NULL;
    float rotation = 0.0f, scale = 1.0f;
    int n;
    if (scene_path) {
        if (lumis_scene_file_read(scene_path, &tool_errors, &file) != LUMIS_OK) return EXIT_RUNTIME;
        objs = file->objects;
        n = file->object_count;
        cam = file->camera;
        if (!envspec && file->env_map[0]) envspec = file->env_map;
        rotation = file->env_rotation_deg;
        scale = file->env_scale;
    } else if (strcmp(scene_name, "ward-aniso") == 0) {
        n = scene_ward_aniso(builtin, &cam);
    } else {
        n = scene_spheres(builtin, &cam);
    }
    if (!envspec) envspec = "sky";
    if (w) cam.width = w, cam.height = h;
    lumis_envmap *env = NULL;
    lumis_sampler *smp = NULL;
    if (tool_make_sampler(envspec, rotation, scale, &sd, &env, &smp) != LUMIS_OK) {
        lumis_scene_file_destroy(file);
        return EXIT_RUNTIME;
    }
    lumis_scene *scene = NULL;
    int rc = EXIT_RUNTIME;
    if (lumis_scene_create(objs, n, &tool_errors, &scene) == LUMIS_OK) {
        rd.camera = &cam;
        rd.env = env;
        rd.sampler = smp;
        rd.errors = tool_errors;
        lumis_image *img = NULL;
        lumis_render_stats st;
        if (lumis_render(scene, &rd, &img, &st) == LUMIS_OK) {
            fprintf(stderr,
                    "lumis: rendered %dx%d at %d spp in %.3f s (%.3g shadow rays/s), sampler %s "
                    "built in %.2f ms\n",
                    cam.width, cam.height, rd.spp ? rd.spp : 16, st.seconds,
                    st.shadow_rays / st.seconds,
                    bsdf_only ? "bsdf" : lumis_sampler_method_name(lumis_sampler_get_method(smp)),
                    lumis_sampler_build_ms(smp));
            if (tool_write_image(out, img, NULL) == LUMIS_OK &&
                (!png || tool_write_image(png, img, &pw) == LUMIS_OK))
                rc = EXIT_OK;
        }
        lumis_image_destroy(img);
    }
    lumis_scene_destroy(scene);
    lumis_scene_file_destroy(file);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
    return rc;
}
