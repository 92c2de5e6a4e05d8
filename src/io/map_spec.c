/* Maps named by a spec: an image file, or a procedural map ("sky", "sky:WxH", "studio",
 * "studio:WxH") made by the core library.  One way in for every tool and for scene files. */
#include "internal.h"

#include "../core/internal.h"

#include "lumis/io.h"
#include "lumis/lumis.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* "WxH" with both in [1, 65536]. */
static int parse_size(const char *s, int *w, int *h)
{
    char *end;
    long a = strtol(s, &end, 10);
    if (end == s || (*end != 'x' && *end != 'X')) return 0;
    const char *t = end + 1;
    long b = strtol(t, &end, 10);
    if (end == t || *end != '\0' || a < 1 || b < 1 || a > 65536 || b > 65536) return 0;
    *w = (int)a;
    *h = (int)b;
    return 1;
}

lumis_status lumis_map_read(const char *spec, const lumis_read_options *options, lumis_image **out,
                            lumis_read_info *info)
{
    const lumis_error_sink *errors = options ? &options->errors : NULL;
    lumis_read_info local;
    if (!info) info = &local;
    memset(info, 0, sizeof *info);
    if (!out) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "lumis_map_read: no output");
    *out = NULL;
    if (!spec || !*spec)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "lumis_map_read: empty map name");
    const char *colon = strchr(spec, ':');
    size_t name_len = colon ? (size_t)(colon - spec) : strlen(spec);
    int is_sky = name_len == 3 && strncmp(spec, "sky", 3) == 0;
    int is_studio = name_len == 6 && strncmp(spec, "studio", 6) == 0;
    if (!is_sky && !is_studio) return lumis_image_read(spec, options, out, info);
    int w = 0, h = 0;
    if (colon && !parse_size(colon + 1, &w, &h))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: expected %.*s:WxH with sizes in [1, 65536], e.g. %.*s:1024x512",
                           spec, (int)name_len, spec, (int)name_len, spec);
    if (is_sky) {
        lumis_sky_desc d = {0};
        d.width = w;
        d.height = h;
        d.sun_elevation_deg = (float)LUMIS_MAP_SKY_ELEVATION_DEG;
        d.sun_azimuth_deg = (float)LUMIS_MAP_SKY_AZIMUTH_DEG;
        if (errors) d.errors = *errors;
        return lumis_sky_create(&d, out);
    }
    lumis_studio_desc d = {0};
    d.width = w;
    d.height = h;
    if (errors) d.errors = *errors;
    return lumis_studio_create(&d, out);
}
