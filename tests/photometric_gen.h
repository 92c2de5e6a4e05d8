/* Photometric files made from analytic distributions whose flux is known exactly, for the
 * tests (test_photometric.c, test_cli.c) and the fuzz corpus.  No test downloads a file. */
#ifndef LUMIS_TESTS_PHOTOMETRIC_GEN_H
#define LUMIS_TESTS_PHOTOMETRIC_GEN_H

#include <stddef.h>

typedef enum pg_dist {
    PG_LAMBERT, /* I0 cos g below the horizon (a downlight): flux pi I0 */
    PG_SPOT,    /* I0 cos^n g, n = param: flux 2 pi I0 / (n + 1) */
    PG_BATWING, /* I0 cos g (1 + a sin^2 g), a = param: flux 2 pi I0 (1/2 + a/4) */
    PG_ROAD,    /* I0 cos g (1 + b sin g cos C) (type C, no symmetry), b = param <= 1: pi I0 */
    PG_QUAD,    /* I0 cos g (1 + b sin g cos^2 C) (symmetric about both planes): pi I0 (1 + b/3) */
    PG_AIMED,   /* types A, B: I0 times the cosine to the aim (front hemisphere): pi I0 */
    PG_LINEAR,  /* I0 cos g (1 + b sin^2 g sin^2 C), wider across C90 and smooth at the aim
                   (a linear fixture): pi I0 (1 + b/4) */
    PG_FLOOD    /* types A, B: I0 cos H cos^n V, n = param (|H|, |V| <= 90): a floodlight
                   wide across (H, towards the lateral axis y), narrow up and down (V,
                   towards its top x); its flux depends on the type (pg_flux: 0) */
} pg_dist;

/* Intensity (cd, I0 = 1000) in the luminaire frame's angles: type C (C, gamma); for
 * PG_AIMED the cosine of the angle to -z whatever the angles' type (the caller passes the
 * direction's z); for PG_FLOOD the table's own (H, V) of type A or B. */
double pg_intensity(pg_dist d, double param, double c_deg, double g_deg);
double pg_flux(pg_dist d, double param);

typedef struct pg_ies_spec {
    pg_dist dist;
    double param;
    const char *first_line; /* "IESNA:LM-63-2002", "IESNA91", ...; NULL: 1986 (none) */
    int type;               /* 1 C, 2 B, 3 A */
    int nv;                 /* vertical angles from v0 to v1 */
    double v0, v1;
    int nh; /* horizontal angles from h0 to h1 (nh 1: h0 alone) */
    double h0, h1;
    double multiplier;
    int tilt_include;             /* TILT=INCLUDE with a 3-entry table */
    double width, length, height; /* as the file writes them (signs: the shape) */
    int units;                    /* 1 feet, 2 metres */
} pg_ies_spec;

/* The file's text (malloc'd; *size its length). */
char *pg_ies(const pg_ies_spec *s, size_t *size);

/* EULUMDAT of a type C distribution, symmetry isym (0 to 4), mc C-planes over 360
 * degrees, ng gamma angles from 0 to 180; lamp flux 1000 lm in set 1 (so cd/klm = cd),
 * nsets lamp sets. */
char *pg_ldt(pg_dist d, double param, int isym, int mc, int ng, int nsets, size_t *size);

#endif
