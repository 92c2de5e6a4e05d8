/* The hierarchical Penrose tiling of Ostromoukhov, Donohue & Jodoin (2004, "Fast
 * Hierarchical Importance Sampling with Blue Noise Properties"), as FHIS uses it (not
 * public API).  Six tile types: A and B are sampling tiles (a point, p1), C and D golden
 * triangles (36-72-72 degrees, sides s, phi s, phi s), E and F golden gnomons (36-36-108,
 * sides phi s, phi s, phi^2 s); C/D and E/F are mirror pairs.  A tile splits into children
 * of scale s / phi; every child appends two bits to its parent's F-code, and the C, E and F
 * splits create one new sampling tile each.  Rules, indices and sources: docs/lights.md. */
#ifndef LUMIS_LIGHTS_PENROSE_H
#define LUMIS_LIGHTS_PENROSE_H

#include <stdint.h>

enum { LUMIS__PT_A, LUMIS__PT_B, LUMIS__PT_C, LUMIS__PT_D, LUMIS__PT_E, LUMIS__PT_F };

/* Deepest level a tile may reach: its F-code holds two bits per level in 64 bits. */
enum { LUMIS__PENROSE_MAX_LEVEL = 31 };

/* Correction-vector table size: importance indices x structural indices. */
enum { LUMIS__PENROSE_LUT = 21 };

typedef struct lumis__ptile {
    int type;       /* LUMIS__PT_A .. LUMIS__PT_F */
    int dir;        /* orientation, steps of pi / 10 counter-clockwise from +y, 0 .. 19 */
    int level;      /* 0 for the root */
    uint64_t fcode; /* two bits per level, the newest lowest */
    double s;       /* scale (root: chosen by the caller; children: s / phi) */
    double p1[2];   /* reference vertex; the sample point of A and B */
} lumis__ptile;

/* Unit vector of orientation k (any integer; taken mod 20). */
void lumis__penrose_dir(int k, double v[2]);

/* The three vertices of a triangle tile (C .. F); p[0] == p1. */
void lumis__ptile_vertices(const lumis__ptile *t, double p[3][2]);

/* The children of t (1 to 4) into out; returns their number. */
int lumis__ptile_split(const lumis__ptile *t, lumis__ptile out[4]);

/* The root: a gnomon (F) of scale 2 max(w, h) placed so that it covers [0, w] x [0, h]. */
lumis__ptile lumis__penrose_root(double w, double h);

/* Value of the lowest nbits of code in the Fibonacci number system: bit i counted from
 * the most significant of the nbits weighs F(i + 2) (1, 2, 3, 5, 8, ...), so a tile's
 * bits keep their weights as deeper levels append bits below them. */
double lumis__fcode_value(uint64_t code, int nbits);

/* The level down to which a region of importance I must be subdivided:
 * ceil(max(1, floor(log_phi(sqrt5 I + 1)) - 1) / 2), 0 for I <= 0. */
int lumis__penrose_level_for(double importance);

/* Structural index 0 .. 20: the Fibonacci value of the F-code's last six bits. */
int lumis__penrose_structural_index(uint64_t fcode);

/* Importance index 0 .. 20: floor(21 frac(log_{phi^2}(1 + sqrt5 I))). */
int lumis__penrose_importance_index(double importance);

/* The sample position of a sampling tile moved by a correction vector (u, w) in the
 * tile's frame: p1 + s (u v[dir] + w v[dir + 5]). */
void lumis__ptile_point(const lumis__ptile *t, const float uw[2], double p[2]);

#endif
