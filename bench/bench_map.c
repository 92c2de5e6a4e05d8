/* The map a benchmark program works on (bench_common.h): a file resized to w x h, or the
 * procedural sky at that size (sun at 35 degrees elevation, 60 azimuth). */
#include "bench_common.h"
#include "lumis/io.h"
#include "lumis/lumis.h"

int bench_load_map(const char *map, int w, int h, lumis_envmap **env)
{
    lumis_image *img = NULL;
    lumis_status st;
    if (map) {
        lumis_image *src = NULL;
        if ((st = lumis_image_read(map, NULL, &src, NULL)) != LUMIS_OK)
            return bench_fail("%s: %s", map, lumis_status_string(st));
        if ((st = lumis_image_create(w, h, &img)) == LUMIS_OK)
            st = lumis_equirect_resize(src->pixels, src->width, src->height, img->pixels, w, h);
        lumis_image_destroy(src);
        if (st != LUMIS_OK) {
            lumis_image_destroy(img);
            return bench_fail("cannot resize %s: %s", map, lumis_status_string(st));
        }
    } else {
        lumis_sky_desc sd = {0};
        sd.width = w;
        sd.height = h;
        sd.sun_elevation_deg = 35.0f;
        sd.sun_azimuth_deg = 60.0f;
        if ((st = lumis_sky_create(&sd, &img)) != LUMIS_OK)
            return bench_fail("lumis_sky_create: %s", lumis_status_string(st));
    }
    st = lumis_envmap_from_image(img, env);
    lumis_image_destroy(img);
    if (st != LUMIS_OK) return bench_fail("lumis_envmap_from_image: %s", lumis_status_string(st));
    return 0;
}
