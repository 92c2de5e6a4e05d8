/* The photometric table's representation, shared by the model (photometric.c: creation,
 * interpolation, flux, sampling) and what it implies (photometric_ratings.c: zonal flux,
 * ratings, the table beyond a cone).  Private to src/luminaire. */
#ifndef LUMIS_LUMINAIRE_PHOTOMETRIC_INTERNAL_H
#define LUMIS_LUMINAIRE_PHOTOMETRIC_INTERNAL_H

#include "lumis/photometry.h"

#include "../core/distrib.h"

#define DEG (LUMIS_PI / 180.0)

struct lumis_photometric {
    lumis_photometric_type type;
    lumis_photometric_symmetry sym;
    int v_mirror; /* A, B: V from 0 to 90, mirrored to -V */
    int nv, nh;
    double *v, *h, *cd;          /* cd[i * nv + j]: at h[i], v[j], multiplier applied */
    lumis_photometric_desc desc; /* the sizes and lumens (its arrays are not kept) */
    /* Sampling: the table's cells c = i (nv - 1) + j, [h_i, h_i+1] x [v_j, v_j+1], with the
     * wrap cells (i = nh - 1) when a full type C table stops short of 360, or the v
     * intervals of a rotational table; each chosen in proportion to its flux, then one of
     * its nrep replicas (the symmetry's images) at random, then a point inside from its
     * interpolant, exactly. */
    int ncells, nrep;
    double *cell_flux; /* [ncells]: the cell's own flux (one replica) */
    lumis__cdf cdf;
    double flux;                 /* all replicas of all cells */
    lumis_photometric_info info; /* lumis_photometric_get_info's, computed at creation */
};

/* The bilinear cell between horizontal angles h0, h1 and vertical v0, v1 (degrees), with
 * the values at its corners (iHV), integrated against the solid angle.  vmax clips the
 * vertical extent (type C: the part below it, for the downward flux). */
double lumis__phot_cell(const lumis_photometric *p, double h0, double h1, double v0, double v1,
                        double i00, double i01, double i10, double i11, double vmax);

/* Sampling cell c's angles (degrees) and corner values (iHV: at h0 or h1, v0 or v1). */
void lumis__phot_cell_corners(const lumis_photometric *p, int c, double *h0, double *h1, double *v0,
                              double *v1, double i[4]);

#endif
