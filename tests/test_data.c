/* Integration: `lumis info` on the 18 real CC0 maps in data/ (scripts/fetch-data.sh)
 * reproduces the measured table of shared/data/README.md to the digits it prints.
 * Skipped when data/ has not been fetched. */
/* Oracles:
 * lumis_image_read — external: 18 real CC0 maps reproduce the measured table of
 *     shared/data/README.md through lumis info (info_reproduces_the_data_table)
 * lumis_image_read_memory — consistency: DWA-compressed maps read the same from memory as from file
 *     (dwa_maps_read_the_same_from_file_and_memory)
 * lumis_light_set_irradiance — indirect: the set's irradiance within 3 % of the map's on real
 *     interiors (min_share_feeds_the_envindirects_of_a_hall); closed forms in test_lights
 */
#include "testutil.h"

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* file, w, h, avgY, maxY, powerY, top1%, top0.1%, replaced - as printed in the README. */
static const struct {
    const char *file;
    int w, h;
    const char *avg, *max, *power, *top1, *top01;
    int replaced;
} table[] = {
    {"blender-city.exr", 1024, 512, "0.9600", "31749.4", "12.0642", "0.310", "0.252", 506},
    {"blender-courtyard.exr", 1024, 512, "0.7663", "52.9", "9.6300", "0.296", "0.041", 1818},
    {"blender-forest.exr", 1024, 512, "0.5415", "953.9", "6.8053", "0.319", "0.145", 784},
    {"blender-interior.exr", 1024, 512, "1.0503", "32216.1", "13.1985", "0.544", "0.431", 8980},
    {"blender-night.exr", 1024, 512, "0.1959", "4219.6", "2.4621", "0.577", "0.517", 829},
    {"blender-studio.exr", 1024, 512, "0.3367", "110.9", "4.2315", "0.878", "0.457", 3},
    {"blender-sunrise.exr", 1024, 512, "0.6980", "32744.5", "8.7713", "0.691", "0.614", 596},
    {"blender-sunset.exr", 1024, 512, "0.4975", "2090.3", "6.2519", "0.120", "0.036", 5},
    {"pmndrs-apartment.exr", 512, 256, "0.7216", "14.1", "9.0682", "0.161", "0.024", 17},
    {"pmndrs-city.exr", 512, 256, "0.5584", "10.2", "7.0165", "0.063", "0.009", 342},
    {"pmndrs-dawn.exr", 512, 256, "0.8402", "45.9", "10.5577", "0.296", "0.065", 406},
    {"pmndrs-forest.exr", 512, 256, "0.4900", "39.5", "6.1577", "0.226", "0.050", 5270},
    {"pmndrs-lobby.exr", 512, 256, "0.8397", "740.7", "10.5523", "0.325", "0.170", 1566},
    {"pmndrs-night.exr", 512, 256, "0.0844", "15.5", "1.0601", "0.198", "0.037", 587},
    {"pmndrs-studio.exr", 512, 256, "2.2322", "3482.0", "28.0504", "0.886", "0.667", 2028},
    {"pmndrs-sunrise.exr", 512, 256, "0.3041", "1083.6", "3.8220", "0.293", "0.121", 220},
    {"pmndrs-sunset.exr", 512, 256, "0.4660", "244.7", "5.8556", "0.127", "0.025", 912},
    {"pmndrs-venice.exr", 512, 256, "0.6459", "6.8", "8.1169", "0.091", "0.013", 446},
};
enum { NMAPS = sizeof table / sizeof table[0] };

static const char *map_path(const char *file)
{
    static char p[1024];
    snprintf(p, sizeof p, "%s/hdri/%s", LUMIS_DATA_DIR, file);
    return p;
}

static int have_data(void)
{
    for (int k = 0; k < NMAPS; k++)
        if (access(map_path(table[k].file), R_OK) != 0) return 0;
    return 1;
}

/* Without data/ the tests skip on a developer's machine, and fail in CI (CI=true): CI
 * fetches the data, so missing data there is a broken fetch, not a reason to pass. */
static int data_or_skip(void)
{
    if (have_data()) return 1;
    const char *ci = getenv("CI");
    if (ci && *ci && strcmp(ci, "0") != 0 && strcmp(ci, "false") != 0)
        fail_msg("data/ is missing in CI (scripts/fetch-data.sh failed?)");
    print_message("data/ not fetched (scripts/fetch-data.sh): skipping\n");
    return 0;
}

static double num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!cJSON_IsNumber(v)) fail_msg("key %s missing", key);
    return v->valuedouble;
}

static void expect_printed(const char *file, const char *what, const char *fmt, double value,
                           const char *want)
{
    char got[64];
    snprintf(got, sizeof got, fmt, value);
    if (strcmp(got, want) != 0) fail_msg("%s %s: %s, table says %s", file, what, got, want);
}

static void info_reproduces_the_data_table(void **state)
{
    (void)state;
    if (!data_or_skip()) skip();
    for (int k = 0; k < NMAPS; k++) {
        char cmd[2048], *out = NULL, *err = NULL;
        snprintf(cmd, sizeof cmd, "'%s' info --json '%s'", LUMIS_CLI, map_path(table[k].file));
        int rc = tu_run(cmd, &out, &err);
        if (rc != 0) fail_msg("%s: exit %d: %s", table[k].file, rc, err);
        cJSON *o = cJSON_Parse(out);
        assert_non_null(o);
        assert_int_equal((int)num(o, "width"), table[k].w);
        assert_int_equal((int)num(o, "height"), table[k].h);
        expect_printed(table[k].file, "avgY", "%.4f", num(o, "avg_luminance"), table[k].avg);
        expect_printed(table[k].file, "maxY", "%.1f", num(o, "max_luminance"), table[k].max);
        expect_printed(table[k].file, "powerY", "%.4f", num(o, "power"), table[k].power);
        expect_printed(table[k].file, "top1%", "%.3f", num(o, "top1_share"), table[k].top1);
        expect_printed(table[k].file, "top0.1%", "%.3f", num(o, "top01_share"), table[k].top01);
        assert_int_equal((int)num(o, "replaced"), table[k].replaced);
        cJSON_Delete(o);
        free(out);
        free(err);
    }
}

static void dwa_maps_read_the_same_from_file_and_memory(void **state)
{
    (void)state;
    if (!data_or_skip()) skip();
    for (int k = 0; k < NMAPS; k += 5) {
        const char *path = map_path(table[k].file);
        lumis_image *a = NULL, *b = NULL;
        lumis_read_info ia, ib;
        assert_int_equal(lumis_image_read(path, NULL, &a, &ia), LUMIS_OK);
        size_t n;
        unsigned char *bytes = tu_read_file(path, &n);
        assert_int_equal(lumis_image_read_memory(bytes, n, LUMIS_FORMAT_AUTO, path, NULL, &b, &ib),
                         LUMIS_OK);
        assert_int_equal(a->width, table[k].w);
        assert_memory_equal(a->pixels, b->pixels, (size_t)a->width * a->height * 3 * sizeof(float));
        assert_int_equal(lumis_replaced_total(ia.replaced), (uint64_t)table[k].replaced);
        assert_int_equal(lumis_replaced_total(ib.replaced), (uint64_t)table[k].replaced);
        /* Every cut of a real DWA file is detected as truncated. */
        for (size_t cut = n / 7; cut < n; cut += n / 7) {
            lumis_image *c = NULL;
            lumis_status st =
                lumis_image_read_memory(bytes, cut, LUMIS_FORMAT_AUTO, path, NULL, &c, NULL);
            if (st != LUMIS_ERR_TRUNCATED)
                fail_msg("%s cut at %zu: %s", path, cut, lumis_status_name(st));
        }
        free(bytes);
        lumis_image_destroy(a);
        lumis_image_destroy(b);
    }
}

/* Wu's Eq. 2 starves the EnvIndirects of the interior maps (the lobby: 55 EnvDirects and 9
 * EnvIndirects of 64), and the point lights' diffuse irradiance is off by more than 10 % for
 * some normal; with min-share=1 every class gets its share of the lights by power, and the
 * lobby's irradiance is within 3 % of the map's at every elevation and azimuth (the
 * apartment's within 3.5 %; docs/lights.md). */
static void min_share_feeds_the_envindirects_of_a_hall(void **state)
{
    (void)state;
    if (!data_or_skip()) skip();
    static const char *const halls[] = {"pmndrs-lobby.exr", "pmndrs-apartment.exr"};
    for (int h = 0; h < 2; h++) {
        lumis_image *img = NULL;
        lumis_envmap *env = NULL;
        assert_int_equal(lumis_image_read(map_path(halls[h]), NULL, &img, NULL), LUMIS_OK);
        assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
        lumis_image_destroy(img);
        for (int share = 0; share < 2; share++) {
            lumis_light_params p;
            memset(&p, 0, sizeof p);
            if (share)
                assert_int_equal(lumis_light_params_parse(&p, "min-share=1", NULL), LUMIS_OK);
            lumis_light_set *set = NULL;
            assert_int_equal(lumis_lights_by_name(env, "wu", 64, 1, &p, NULL, &set), LUMIS_OK);
            const lumis_light_set_info *info = lumis_light_set_get_info(set);
            double worst = 0.0;
            for (int e = -90; e <= 90; e += 15)
                for (int a = 0; a < 8; a++) {
                    const double el = e * 3.14159265358979 / 180, phi = a * 3.14159265358979 / 4;
                    const lumis_vec3 n = {(float)(cos(el) * cos(phi)), (float)sin(el),
                                          (float)(cos(el) * sin(phi))};
                    double se, me;
                    assert_int_equal(lumis_light_set_irradiance(env, set, n, &se, &me), LUMIS_OK);
                    worst = fmax(worst, fabs(se / me - 1.0));
                }
            print_message("%s, %s: %d EnvDirects, %d EnvIndirects, worst irradiance error "
                          "%.2f %%\n",
                          halls[h], share ? "min-share=1" : "Eq. 2", info->direct, info->indirect,
                          100 * worst);
            /* the lobby (a hall) within 3 %; the apartment's worst normal at 3.5 % */
            const double bound = h == 0 ? 0.03 : 0.04;
            if (share && !(worst <= bound))
                fail_msg("%s with min-share=1: irradiance off by %.2f %% (> %.0f %%)", halls[h],
                         100 * worst, 100 * bound);
            if (!share && !(worst > 0.10 && info->indirect < 16))
                fail_msg("%s with Eq. 2: %d EnvIndirects, irradiance off by %.2f %%: the case "
                         "this test stands for is gone",
                         halls[h], info->indirect, 100 * worst);
            lumis_light_set_destroy(set);
        }
        lumis_envmap_destroy(env);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(info_reproduces_the_data_table),
        cmocka_unit_test(dwa_maps_read_the_same_from_file_and_memory),
        cmocka_unit_test(min_share_feeds_the_envindirects_of_a_hall),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
