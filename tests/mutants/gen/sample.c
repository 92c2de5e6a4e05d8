/* The generator's own test (tests/mutants/test_mutagen.py): each construct below gives
 * the mutants listed in expected.txt, and the ones marked "none" give none. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>

#define TWICE(x) ((x) + (x)) /* none: inside a macro expansion */

static const int table[20] = {1,  2,  3,  4,  5,  6,  7,  8,  9,  10,
                              11, 12, 13, 14, 15, 16, 17, 18, 19, -20}; /* none: a table */
_Static_assert(sizeof(int) >= 2, "none: a static assertion");

typedef struct {
    float m[3];
} box; /* none: an array's size */

static float lerp(float a, float b, float t)
{
    return a + t * (b - a);
}
static float top(float a, float b)
{
    return fmaxf(a, b); /* no swap: fmaxf commutes */
}

static void clear(int *p, size_t n)
{
    if (!p) return;
    for (size_t i = 0; i < n; i++) p[i] = 0;
}

int count(const int *p, int n, float *out)
{
    int s = 0;
    for (int i = 0; i < n; ++i) {
        if (p[i] == 0x10 && !(p[i] & 1)) continue;
        if (p[i] > 1000) break;
        s += -p[i];
        s--;
    }
    *out = lerp(0.5f, 2.0f, 1e-3f);
    int *q = malloc(4 * sizeof *q);
    clear(q, 4);
    __builtin_prefetch(q); /* none: a hint */
    free(q);               /* none: a leak is the sanitizers' job */
    *out += (float)TWICE(s) + (float)(&p[1] - &p[0]) + (float)table[0];
    return s != 0 ? s : 0;
}

const char *name(int k)
{
    return k >= 2 ? "two" : NULL;
}

static const char *pick(const char *a, const char *b)
{
    return a ? a : b;
}

const char *label(const char *a, const char *b)
{
    if (!a) return pick("x", "y"); /* the literals are not swapped */
    return pick(a, b);
}
