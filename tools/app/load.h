/* What a render reads (tools/app/load.c): maps (files or procedural specs), their envmaps
 * and samplers, luminaires, and the warnings about replaced values. */
#ifndef LUMIS_APP_LOAD_H
#define LUMIS_APP_LOAD_H

#include "lumis/io.h"
#include "lumis/lumis.h"
#include "lumis/render.h"

/* Sun of the default sky (`lumis sky`, the "sky" map spec, `lumis demo`). */
#define TOOL_SKY_ELEVATION_DEG LUMIS_MAP_SKY_ELEVATION_DEG
#define TOOL_SKY_AZIMUTH_DEG   LUMIS_MAP_SKY_AZIMUTH_DEG

/* Loads a map (tools/app/load.c): an image file, or a
 * procedural spec "sky", "sky:WxH", "studio", "studio:WxH".  Prints errors itself; returns a
 * lumis_status. */
lumis_status tool_load_image(const char *spec, lumis_image **out, lumis_read_info *info);
/* Loads a rendered image (compare, merge, the bench's renders and references): as
 * tool_load_image, but without the spike warning, which is about maps. */
lumis_status tool_load_render(const char *path, lumis_image **out, lumis_read_info *info);
/* Prints what was replaced in the map what (a file or spec): tiny negatives as a note
 * (LUMIS_NOTES=0 silences it), the rest as a warning naming the worst pixel; and img's
 * saturated spikes, by pixel (img may be NULL). */
void tool_warn_replaced(const char *what, lumis_replaced r, const lumis_image *img);

/* The envmap of a map (file or procedural spec), rotated and scaled; from preloaded (borrowed)
 * when given, spec then only names it.  Prints errors itself. */
lumis_status tool_make_envmap(const char *spec, const lumis_image *preloaded, float rotation,
                              float scale, lumis_envmap **env, lumis_replaced *replaced);

/* Loads a map (file or procedural spec), builds its envmap (rotated, scaled) and a
 * sampler; prints errors itself. */
lumis_status tool_make_sampler(const char *spec, float rotation, float scale,
                               const lumis_sampler_desc *desc, lumis_envmap **env,
                               lumis_sampler **sampler);

/* A luminaire manifest (lumis_luminaire_read) or preset:car|bike|small (acquired); errors
 * printed. */
lumis_status tool_load_luminaire(const char *spec, lumis_luminaire **out);
/* lumis_scene_read_options.load_preset: a preset a scene file names, through the cache of
 * tool_load_luminaire. */
lumis_status tool_scene_load_preset(void *user, const char *spec, lumis_luminaire **out);

/* "auto" exposure: the stops that bring an image's mean luminance to 0.18 (0 for a black
 * image).  The default of every PNG preview. */
float tool_auto_exposure(const lumis_image *image);

#endif
