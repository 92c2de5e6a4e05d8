/* lumis/export.h - what each library exports.
 *
 * The libraries are built with hidden visibility (-fvisibility=hidden): a function is part
 * of a shared library's interface only when its declaration in a public header carries its
 * library's macro, and nothing else is (the lumis__ internals stay inside the library that
 * defines them).  scripts/check-exports.py checks that each library exports exactly the
 * functions its public headers declare.
 *
 *   LUMIS_API         the core, lumis (every header but io.h, render.h and bsdf.h)
 *   LUMIS_IO_API      lumis-io (io.h)
 *   LUMIS_RENDER_API  lumis-render (render.h, bsdf.h)
 *
 * The build defines LUMIS_BUILDING_LUMIS, LUMIS_BUILDING_IO or LUMIS_BUILDING_RENDER while
 * it compiles that library, and gives a static library's users LUMIS_STATIC; they matter on
 * Windows only (dllexport, dllimport, nothing), elsewhere the macros mean default
 * visibility. */
#ifndef LUMIS_EXPORT_H
#define LUMIS_EXPORT_H

#if defined(_WIN32) || defined(__CYGWIN__)
#if defined(LUMIS_STATIC)
#define LUMIS_API
#define LUMIS_IO_API
#define LUMIS_RENDER_API
#else
#if defined(LUMIS_BUILDING_LUMIS)
#define LUMIS_API __declspec(dllexport)
#else
#define LUMIS_API __declspec(dllimport)
#endif
#if defined(LUMIS_BUILDING_IO)
#define LUMIS_IO_API __declspec(dllexport)
#else
#define LUMIS_IO_API __declspec(dllimport)
#endif
#if defined(LUMIS_BUILDING_RENDER)
#define LUMIS_RENDER_API __declspec(dllexport)
#else
#define LUMIS_RENDER_API __declspec(dllimport)
#endif
#endif
#elif defined(__GNUC__) || defined(__clang__)
#define LUMIS_API        __attribute__((visibility("default")))
#define LUMIS_IO_API     __attribute__((visibility("default")))
#define LUMIS_RENDER_API __attribute__((visibility("default")))
#else
#define LUMIS_API
#define LUMIS_IO_API
#define LUMIS_RENDER_API
#endif

#endif
