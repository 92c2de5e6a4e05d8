/* The hierarchical Penrose tiling FHIS samples with (penrose.h; docs/lights.md). */
#include "penrose.h"

#include <math.h>

#define PHI   1.6180339887498948482
#define SQRT5 2.2360679774997896964

void lumis__penrose_dir(int k, double v[2])
{
    k %= 20;
    if (k < 0) k += 20;
    /* 0 points along +y, and k turns counter-clockwise by pi / 10 */
    static const double c[6] = {
        1.0, 0.95105651629515357, 0.80901699437494742, 0.58778525229247313, 0.30901699437494742,
        0.0};
    /* cos(k pi / 10) and sin(k pi / 10) from the first quadrant's table, exact symmetries */
    const int q = k / 5, r = k % 5;
    double cs = c[r], sn = c[5 - r];
    double x, y;
    switch (q) {
    case 0:
        y = cs, x = -sn;
        break;
    case 1:
        y = -sn, x = -cs;
        break;
    case 2:
        y = -cs, x = sn;
        break;
    default:
        y = sn, x = cs;
        break;
    }
    v[0] = x;
    v[1] = y;
}

void lumis__ptile_vertices(const lumis__ptile *t, double p[3][2])
{
    double a[2], b[2], la, lb;
    if (t->type == LUMIS__PT_C || t->type == LUMIS__PT_D) {
        lumis__penrose_dir(t->dir, a);
        lumis__penrose_dir(t->dir + 4, b);
        la = t->s;
        lb = PHI * t->s;
    } else {
        lumis__penrose_dir(t->dir, a);
        lumis__penrose_dir(t->dir + 2, b);
        la = PHI * PHI * t->s;
        lb = PHI * t->s;
    }
    p[0][0] = t->p1[0];
    p[0][1] = t->p1[1];
    p[1][0] = t->p1[0] + la * a[0];
    p[1][1] = t->p1[1] + la * a[1];
    p[2][0] = t->p1[0] + lb * b[0];
    p[2][1] = t->p1[1] + lb * b[1];
}

/* A child of t: its type, reference vertex, turn relative to t and the two new bits
 * (0, 1 or 2; the pair 11 never occurs, as in a Zeckendorf representation). */
static lumis__ptile child(const lumis__ptile *t, int type, const double at[2], int turn, int bits)
{
    lumis__ptile c;
    c.type = type;
    c.dir = (t->dir + turn) % 20;
    c.level = t->level + 1;
    c.fcode = (t->fcode << 2) | (uint64_t)bits;
    c.s = t->s / PHI;
    c.p1[0] = at[0];
    c.p1[1] = at[1];
    return c;
}

int lumis__ptile_split(const lumis__ptile *t, lumis__ptile out[4])
{
    double p[3][2], q[3][2];
    switch (t->type) {
    case LUMIS__PT_A:
        out[0] = child(t, LUMIS__PT_B, t->p1, 0, 0);
        return 1;
    case LUMIS__PT_B:
        out[0] = child(t, LUMIS__PT_A, t->p1, 10, 0);
        return 1;
    default:
        break;
    }
    lumis__ptile_vertices(t, p);
    switch (t->type) {
    case LUMIS__PT_C:
        out[0] = child(t, LUMIS__PT_F, p[2], 14, 0);
        out[1] = child(t, LUMIS__PT_C, p[1], 6, 1);
        lumis__ptile_vertices(&out[0], q);
        out[2] = child(t, LUMIS__PT_A, q[2], 1, 1);
        return 3;
    case LUMIS__PT_D:
        out[0] = child(t, LUMIS__PT_E, p[1], 6, 0);
        lumis__ptile_vertices(&out[0], q);
        out[1] = child(t, LUMIS__PT_D, q[2], 14, 1);
        return 2;
    case LUMIS__PT_E:
        out[0] = child(t, LUMIS__PT_C, p[2], 12, 1);
        out[1] = child(t, LUMIS__PT_E, p[1], 8, 2);
        out[2] = child(t, LUMIS__PT_F, p[0], 0, 0);
        lumis__ptile_vertices(&out[0], q);
        out[3] = child(t, LUMIS__PT_A, q[1], 7, 1);
        return 4;
    default: { /* F */
        double r[3][2];
        out[0] = child(t, LUMIS__PT_F, p[2], 12, 2);
        lumis__ptile_vertices(&out[0], q);
        out[1] = child(t, LUMIS__PT_E, q[2], 0, 0);
        lumis__ptile_vertices(&out[1], r);
        out[2] = child(t, LUMIS__PT_D, r[2], 8, 1);
        out[3] = child(t, LUMIS__PT_A, q[2], 15, 2);
        return 4;
    }
    }
}

lumis__ptile lumis__penrose_root(double w, double h)
{
    lumis__ptile t;
    const double s = 2.0 * (w > h ? w : h);
    t.type = LUMIS__PT_F;
    t.dir = 15;
    t.level = 0;
    t.fcode = 0;
    t.s = s;
    /* base along +x at y = -s / 8, apex above: covers [0, s / 2] x [0, s / 2] */
    t.p1[0] = -s * (0.5 * PHI * PHI - 0.25);
    t.p1[1] = -s * 0.125;
    return t;
}

double lumis__fcode_value(uint64_t code, int nbits)
{
    /* F(2), F(3), ... = 1, 2, 3, 5, ... */
    double f0 = 1.0, f1 = 2.0, v = 0.0;
    for (int i = 0; i < nbits; i++) {
        if ((code >> (nbits - 1 - i)) & 1u) v += f0;
        double f2 = f0 + f1;
        f0 = f1;
        f1 = f2;
    }
    return v;
}

int lumis__penrose_level_for(double importance)
{
    if (!(importance > 0.0)) return 0;
    double nb = floor(log(importance * SQRT5 + 1.0) / log(PHI)) - 1.0;
    if (nb < 1.0) nb = 1.0;
    double l = ceil(0.5 * nb);
    return l > LUMIS__PENROSE_MAX_LEVEL ? LUMIS__PENROSE_MAX_LEVEL : (int)l;
}

int lumis__penrose_structural_index(uint64_t fcode)
{
    return (int)lumis__fcode_value(fcode & 63u, 6);
}

int lumis__penrose_importance_index(double importance)
{
    if (!(importance > 0.0)) return 0;
    double t = log(1.0 + SQRT5 * importance) / log(PHI * PHI);
    t -= floor(t);
    int i = (int)(LUMIS__PENROSE_LUT * t);
    return i < LUMIS__PENROSE_LUT ? i : LUMIS__PENROSE_LUT - 1;
}

void lumis__ptile_point(const lumis__ptile *t, const float uw[2], double p[2])
{
    double a[2], b[2];
    lumis__penrose_dir(t->dir, a);
    lumis__penrose_dir(t->dir + 5, b);
    p[0] = t->p1[0] + t->s * ((double)uw[0] * a[0] + (double)uw[1] * b[0]);
    p[1] = t->p1[1] + t->s * ((double)uw[0] * a[1] + (double)uw[1] * b[1]);
}
