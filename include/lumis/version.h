/* lumis/version.h - library version (CMake reads it from here). */
#ifndef LUMIS_VERSION_H
#define LUMIS_VERSION_H

#include "lumis/export.h"

#define LUMIS_VERSION_MAJOR  0
#define LUMIS_VERSION_MINOR  1
#define LUMIS_VERSION_PATCH  0
#define LUMIS_VERSION_STRING "0.1.0"

#ifdef __cplusplus
extern "C" {
#endif

/* Version of the library actually linked, e.g. "0.1.0". */
LUMIS_API const char *lumis_version(void);

/* The SIMD variant that lumis's own vectorised passes run (the light sets' pixel passes and
 * Wu's k-means): "avx512", "avx2" or "baseline", the best this CPU and build have, lowered
 * to the one the environment variable LUMIS_SIMD names (the same three names; a variant the
 * CPU lacks gives the best it has).  Every variant gives the same light sets, bit for bit.
 * Read once, at the first call of the library.  NULL when LUMIS_SIMD names none of them
 * (the baseline runs then, and a tool should refuse to go on). */
LUMIS_API const char *lumis_simd_variant(void);

#ifdef __cplusplus
}
#endif
#endif
