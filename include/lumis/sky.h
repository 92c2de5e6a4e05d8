/* lumis/sky.h - deterministic procedural environment maps: the embedded defaults.
 *
 * lumis works with no file at all: these build equirectangular maps (row 0 = zenith) at
 * any resolution.  Radiance is in units of 1000 cd/m^2 of luminance (kcd/m^2, Preetham's
 * unit), so a clear sky averages a few units and the sun disk about a million. */
#ifndef LUMIS_SKY_H
#define LUMIS_SKY_H

#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The sun's elevation a zero-initialised lumis_sky_desc gives (the CLI's default too). */
#define LUMIS_SKY_DEFAULT_ELEVATION_DEG 35.0

/* Clear sky after Preetham, Shirley and Smits (1999), with a sun disk and a diffuse ground.
 * Zero-initialised, it is a 1024 x 512 map, turbidity 2.5, the sun at 35 degrees elevation
 * (LUMIS_SKY_DEFAULT_ELEVATION_DEG) and azimuth 0, where it holds about 55 % of the power.
 * (Before 2026-11-25 zero put the sun on the horizon: sun_at_horizon asks for that now.) */
typedef struct lumis_sky_desc {
    int width;               /* 0 == default 1024 */
    int height;              /* 0 == default width / 2 */
    float sun_elevation_deg; /* degrees above the horizon, (0, 90]; 0 == default 35 */
    float sun_azimuth_deg;   /* degrees; 0 == +x, 90 == +z (increasing u) */
    float turbidity;         /* 0 == default 2.5 (a clear day); valid range [1.7, 10] */
    float ground_albedo;     /* 0 == default 0.1 (dark soil, asphalt); negative == black */
    int no_sun;              /* nonzero: the sky without the sun disk */
    int sun_at_horizon;      /* nonzero: the sun on the horizon (elevation 0; then
                                sun_elevation_deg must be 0) */
    lumis_error_sink errors;
} lumis_sky_desc;

/* Renders the clear sky into a new image. */
LUMIS_API lumis_status lumis_sky_create(const lumis_sky_desc *desc, lumis_image **out);

/* Studio map: a dark surround and a few bright rectangular soft boxes (key, fill, rim and
 * a top light).  Zero-initialised, it is 1024 x 512. */
typedef struct lumis_studio_desc {
    int width;       /* 0 == default 1024 */
    int height;      /* 0 == default width / 2 */
    float intensity; /* multiplier of the soft boxes' radiance; 0 == default 1 */
    lumis_error_sink errors;
} lumis_studio_desc;

LUMIS_API lumis_status lumis_studio_create(const lumis_studio_desc *desc, lumis_image **out);

#ifdef __cplusplus
}
#endif
#endif
