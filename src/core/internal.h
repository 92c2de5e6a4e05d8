/* Internal helpers shared by the lumis libraries (lumis__ prefix: not public API).
 *
 * The one private header that crosses a library boundary (lumis-io and lumis-render include
 * it; scripts/check-includes.py allows no other): what they use of it is macros and static
 * inline functions, compiled into each library, never a symbol of the core's.  Its
 * functions that are defined in the core (lumis__simd_level, lumis__simd_force) are hidden
 * there: only the core and the tests (static libraries) may call them. */
#ifndef LUMIS_CORE_INTERNAL_H
#define LUMIS_CORE_INTERNAL_H

#include "lumis/status.h"

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#define LUMIS_PI   3.14159265358979323846
#define LUMIS_PI_F 3.14159265358979323846f

#if defined(__GNUC__) || defined(__clang__)
#define LUMIS_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define LUMIS_PRINTF(a, b)
#endif

/* Sends a formatted message to sink (if any) and returns status, so failures read
 *     return lumis__fail(sink, LUMIS_ERR_TRUNCATED, "%s: ...", name);
 * Inline: each library has its own copy, so no library calls another's private symbol. */
static inline LUMIS_PRINTF(3, 4) lumis_status
    lumis__fail(const lumis_error_sink *sink, lumis_status status, const char *fmt, ...)
{
    if (sink && sink->fn) {
        char message[512];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(message, sizeof message, fmt, ap);
        va_end(ap);
        sink->fn(sink->user, status, message);
    }
    return status;
}

/* ---- an enumeration's names, defined once -----------------------------------------------
 * Every public enumeration with a name / from-name pair keeps its names in one table indexed
 * by value (NULL: a value without a name), the way lumis_status keeps its own in
 * LUMIS_STATUS_TABLE, and defines the pair from it:
 *     static const char *const tonemap_names[] = {"clamp", "reinhard", "aces"};
 *     LUMIS__ENUM_NAMES(lumis_tonemap, LUMIS_TONEMAP_COUNT, tonemap_names, lumis_tonemap_name,
 *                       lumis_tonemap_from_name);
 * so a name and its value cannot drift apart and every pair behaves alike: the name of a
 * value outside the table is "unknown"; from-name refuses an unknown or NULL name and a
 * NULL out with LUMIS_ERR_INVALID_ARGUMENT, leaving *out untouched.  The table must have
 * exactly `count` entries (a compile-time check), so a value added to the enumeration
 * without a name does not build. */
#define LUMIS__COUNTOF(a) ((int)(sizeof(a) / sizeof((a)[0])))

static inline const char *lumis__enum_name(const char *const *names, int n, int value)
{
    return value >= 0 && value < n && names[value] ? names[value] : "unknown";
}

/* The value whose name is `name` (-1: none; NULL entries never match). */
static inline int lumis__enum_value(const char *const *names, int n, const char *name)
{
    for (int v = 0; name && v < n; v++)
        if (names[v] && strcmp(names[v], name) == 0) return v;
    return -1;
}

#define LUMIS__ENUM_NAME_FN(type, names, name_fn)                                                  \
    const char *name_fn(type value)                                                                \
    {                                                                                              \
        return lumis__enum_name(names, LUMIS__COUNTOF(names), (int)value);                         \
    }

#define LUMIS__ENUM_FROM_NAME_FN(type, names, from_name_fn)                                        \
    lumis_status from_name_fn(const char *name, type *out)                                         \
    {                                                                                              \
        const int v = lumis__enum_value(names, LUMIS__COUNTOF(names), name);                       \
        if (v < 0 || !out) return LUMIS_ERR_INVALID_ARGUMENT;                                      \
        *out = (type)v;                                                                            \
        return LUMIS_OK;                                                                           \
    }

/* The pair; the call ends with a semicolon (it closes the table's size check). */
#define LUMIS__ENUM_NAMES(type, count, names, name_fn, from_name_fn)                               \
    LUMIS__ENUM_NAME_FN(type, names, name_fn)                                                      \
    LUMIS__ENUM_FROM_NAME_FN(type, names, from_name_fn)                                            \
    _Static_assert(LUMIS__COUNTOF(names) == (count), #names ": one name per " #type)

/* The name function alone (an enumeration that is not read back by name). */
#define LUMIS__ENUM_NAME(type, count, names, name_fn)                                              \
    LUMIS__ENUM_NAME_FN(type, names, name_fn)                                                      \
    _Static_assert(LUMIS__COUNTOF(names) == (count), #names ": one name per " #type)

/* lumis's own SIMD variants (docs/lights.md, "Every CPU"): a hot pass is compiled once per
 * level with LUMIS__TARGET_AVX512 / LUMIS__TARGET_AVX2 wrappers around one always-inlined
 * body, and a call picks by lumis__simd_level(): the best the CPU has, lowered by the
 * environment variable LUMIS_SIMD (avx512, avx2, baseline) so that every variant can be
 * forced and compared on one machine.  GCC on x86-64 only (clang's contraction and
 * vectoriser differ; its builds run the baseline). */
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
#define LUMIS__MULTIVERSION  1
#define LUMIS__ALWAYS_INLINE __attribute__((always_inline))
#define LUMIS__TARGET_AVX2   __attribute__((target("avx2")))
#define LUMIS__TARGET_AVX512 __attribute__((target("avx512f")))
#else
#define LUMIS__MULTIVERSION 0
#define LUMIS__ALWAYS_INLINE
#define LUMIS__TARGET_AVX2
#define LUMIS__TARGET_AVX512
#endif
enum { LUMIS__SIMD_BASELINE = 0, LUMIS__SIMD_AVX2 = 1, LUMIS__SIMD_AVX512 = 2 };
int lumis__simd_level(void);
/* Tests: every later call runs `level` (capped at the CPU's); -1 returns to LUMIS_SIMD. */
void lumis__simd_force(int level);

/* splitmix64's finaliser: every bit of z spread over all 64 (seeds and hashes of the
 * sequences, PCG32 start states). */
static inline uint64_t lumis__mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static inline int lumis__clampi(int x, int lo, int hi)
{
    return x < lo ? lo : (x > hi ? hi : x);
}

/* a < b ? a : b and a > b ? a : b without a branch: GCC keeps these ternaries on doubles as
 * branches, which cost a misprediction each time the outcome is random (per sample). */
static inline double lumis__minsel(double a, double b)
{
#if defined(__SSE2__)
    return _mm_cvtsd_f64(_mm_min_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
    return a < b ? a : b;
#endif
}

static inline double lumis__maxsel(double a, double b)
{
#if defined(__SSE2__)
    return _mm_cvtsd_f64(_mm_max_sd(_mm_set_sd(a), _mm_set_sd(b)));
#else
    return a > b ? a : b;
#endif
}

/* qsort's comparison of doubles, ascending. */
static inline int lumis__cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

#endif
