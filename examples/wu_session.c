/* Renders the built-in wu-mixed scene under a procedural sky with Wu's light set, its
 * EnvIndirects at half resolution and joint-bilateral upsampled, for a 2-second budget
 * (K fitted to it), and writes wu.exr.  Usage: wu_session [SECONDS [OUT.exr]] */
#include <lumis/io.h>
#include <lumis/lumis.h>
#include <lumis/render.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv)
{
    const double budget = argc > 1 ? atof(argv[1]) : 2.0;
    const char *out = argc > 2 ? argv[2] : "wu.exr";
    lumis_sky_desc sky = {0};
    lumis_image *map = NULL, *image = NULL;
    lumis_envmap *env = NULL;
    lumis_scene_file *file = NULL;
    lumis_scene *scene = NULL;
    lumis_session_result r = {0};
    lumis_status st = lumis_sky_create(&sky, &map);
    if (st == LUMIS_OK) st = lumis_envmap_from_image(map, &env);
    if (st == LUMIS_OK) st = lumis_scene_builtin("wu-mixed", NULL, &file);
    if (st == LUMIS_OK) st = lumis_scene_create(file->objects, file->object_count, NULL, &scene);
    if (st == LUMIS_OK) {
        lumis_session_desc s = {0};
        s.render.camera = &file->camera;
        s.render.lighting.kind = LUMIS_LIGHTING_LIGHT_SET; /* made by the session: */
        s.render.lighting.env = env;
        s.lights = "wu";        /* K (0) is fitted to the budget */
        s.upsample = 2;         /* EnvIndirects at 1/2 resolution */
        s.time_budget = budget; /* wall time, the lights' making included */
        st = lumis_render_session(scene, &s, &image, &r);
    }
    if (st == LUMIS_OK) st = lumis_image_write(out, image, NULL);
    if (st == LUMIS_OK)
        printf("%s: %d lights, %d spp, %.3f s of %.3f s (%.3f s before the first sample)\n", out,
               r.lights_k, r.stats.spp, r.budget_used_seconds, budget, r.prep_seconds);
    else
        fprintf(stderr, "wu_session: %s\n", lumis_status_string(st));
    lumis_light_set_destroy(r.light_set);
    lumis_image_destroy(image);
    lumis_scene_destroy(scene);
    lumis_scene_file_destroy(file);
    lumis_envmap_destroy(env);
    lumis_image_destroy(map);
    return st == LUMIS_OK ? 0 : 1;
}
