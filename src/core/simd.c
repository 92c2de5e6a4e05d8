/* Which SIMD variant lumis's own vectorised passes run: the best the CPU has, or a lower one
 * that LUMIS_SIMD names, so every variant can be tested on one machine (docs/formats.md is
 * not the place: docs/lights.md, "Every CPU"). */
#include "internal.h"

#include "lumis/version.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

static const char *const variant_names[] = {"baseline", "avx2", "avx512"};

/* -2: not read yet; -1: LUMIS_SIMD names no variant (the baseline runs); else the level. */
static _Atomic int chosen = -2;
static _Atomic int forced = -1;

static int cpu_level(void)
{
#if LUMIS__MULTIVERSION
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f")) return LUMIS__SIMD_AVX512;
    if (__builtin_cpu_supports("avx2")) return LUMIS__SIMD_AVX2;
#endif
    return LUMIS__SIMD_BASELINE;
}

static int environment_level(void)
{
    const int cpu = cpu_level();
    const char *want = getenv("LUMIS_SIMD");
    if (!want || !*want) return cpu;
    for (int k = 0; k <= LUMIS__SIMD_AVX512; k++)
        if (strcmp(want, variant_names[k]) == 0) return k < cpu ? k : cpu;
    return -1;
}

static int level_or_unknown(void)
{
    const int f = atomic_load_explicit(&forced, memory_order_relaxed);
    if (f >= 0) return f;
    int c = atomic_load_explicit(&chosen, memory_order_relaxed);
    if (c == -2) { /* two threads may both read the environment: they agree */
        c = environment_level();
        atomic_store_explicit(&chosen, c, memory_order_relaxed);
    }
    return c;
}

int lumis__simd_level(void)
{
    const int c = level_or_unknown();
    return c < 0 ? LUMIS__SIMD_BASELINE : c;
}

void lumis__simd_force(int level)
{
    const int cpu = cpu_level();
    atomic_store_explicit(&forced, level < 0 ? -1 : (level < cpu ? level : cpu),
                          memory_order_relaxed);
}

const char *lumis_simd_variant(void)
{
    const int c = level_or_unknown();
    return c < 0 ? NULL : variant_names[c];
}
