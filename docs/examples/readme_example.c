#include <lumis/io.h>
#include <lumis/lumis.h>
#include <stdio.h>

int main(int argc, char **argv)
{
    const char *map = argc > 1 ? argv[1] : "sky:256x128"; /* a file, or sky / studio */
    lumis_image *img = NULL;
    lumis_envmap *env = NULL;
    lumis_sampler *smp = NULL;
    lumis_light_set *set = NULL;
    lumis_status s = lumis_map_read(map, NULL, &img, NULL);
    if (!s) s = lumis_envmap_from_image(img, &env);
    lumis_sampler_desc sd = {.method = LUMIS_METHOD_KDTREE}; /* zeroed: the defaults */
    if (!s) s = lumis_sampler_create(env, &sd, &smp);
    lumis_median_cut_desc md = {.count = 16};
    if (!s) s = lumis_lights_median_cut(env, &md, &set);
    if (s) return fprintf(stderr, "%s: %s\n", map, lumis_status_string(s)), 1;

    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 1, 0);
    int bad = 0;
    for (int i = 0; i < 4; i++) { /* a direction, its density per steradian, its radiance */
        double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
        lumis_env_sample e = lumis_sampler_sample(smp, u1, u2);
        printf("(%+.3f %+.3f %+.3f) pdf %.4g L %.4g\n", e.dir.x, e.dir.y, e.dir.z, e.pdf,
               e.radiance.g);
        bad |= !(e.pdf > 0) || lumis_sampler_pdf(smp, e.dir) != e.pdf;
    }
    const lumis_light *l = NULL; /* 16 directional lights whose powers add up to the map's */
    int k = 0;
    lumis_light_set_get(set, 0, &l, &k);
    for (int i = 0; i < k; i++)
        printf("light %2d (%+.3f %+.3f %+.3f) power %.4g\n", i, l[i].dir.x, l[i].dir.y, l[i].dir.z,
               l[i].power[1]);

    lumis_light_set_destroy(set);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
    return bad || k != 16;
}
