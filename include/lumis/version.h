/* lumis/version.h - library version (CMake reads it from here). */
#ifndef LUMIS_VERSION_H
#define LUMIS_VERSION_H

#define LUMIS_VERSION_MAJOR  0
#define LUMIS_VERSION_MINOR  1
#define LUMIS_VERSION_PATCH  0
#define LUMIS_VERSION_STRING "0.1.0"

#ifdef __cplusplus
extern "C" {
#endif

/* Version of the library actually linked, e.g. "0.1.0". */
const char *lumis_version(void);

#ifdef __cplusplus
}
#endif
#endif
