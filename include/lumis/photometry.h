/* lumis/photometry.h - a luminaire's far-field photometry: luminous intensity (candela)
 * tabulated over two angles, as IES LM-63 and EULUMDAT files give it (their readers are in
 * lumis/io.h: lumis_photometric_read).  docs/photometric.md has the conventions.
 *
 * Frame: the luminaire's own.  Its aim (photometric zero for type C, the photometric
 * centre for types A and B) is -z; +x is the C0 direction (type C) and "up" (types A, B);
 * +y is C90 (type C, counter-clockwise seen from above) and the lateral axis (A, B).  A
 * scene places it by a rotation from lumis_photometric_orient (lumis/render.h): a type C
 * fixture hangs (C0 +x), a type A or B one sits on a yoke (its top above the aim).
 *
 *   type C: planes around the vertical axis.  gamma from -z (nadir, 0) to +z (180), C
 *           counter-clockwise from +x:   d = (sin g cos C, sin g sin C, -cos g)
 *   type B: planes around the lateral axis y.  V turns the plane (towards +x),
 *           H lies in it (towards +y):    d = (cos H sin V, sin H, -cos H cos V)
 *   type A: planes around the vertical axis x.  H turns the plane (towards +y),
 *           V lies in it (towards +x):    d = (sin V, cos V sin H, -cos V cos H)
 *
 * Interpolation (the convention: Cycles and pbrt-v4 differ from each other): bilinear in
 * the two angles, in degrees, on the table as the file gives it, after its symmetry maps a
 * direction into the table's range; zero outside the vertical range (a downlight's 0-90
 * table gives nothing upwards) and behind types A and B (|H| or |V| > 90).  The flux is
 * the exact integral of that interpolant over the sphere. */
#ifndef LUMIS_PHOTOMETRY_H
#define LUMIS_PHOTOMETRY_H

#include "lumis/export.h"
#include "lumis/luminaire.h"
#include "lumis/status.h"
#include "lumis/types.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lumis_photometric_type {
    LUMIS_PHOTOMETRIC_C = 1, /* IES's codes */
    LUMIS_PHOTOMETRIC_B = 2,
    LUMIS_PHOTOMETRIC_A = 3
} lumis_photometric_type;

/* How the horizontal angles cover the luminaire (from their first and last). */
typedef enum lumis_photometric_symmetry {
    LUMIS_SYMMETRY_NONE = 0,   /* C: 0 to 360 (or to less: wraps); A, B: H -90 to 90 */
    LUMIS_SYMMETRY_ROTATIONAL, /* C: one plane */
    LUMIS_SYMMETRY_C0_C180,    /* C: 0 to 180, mirrored about the C0-C180 plane */
    LUMIS_SYMMETRY_C90_C270,   /* C: 90 to 270, mirrored about the C90-C270 plane */
    LUMIS_SYMMETRY_QUADRANT,   /* C: 0 to 90, about both planes */
    LUMIS_SYMMETRY_LATERAL     /* A, B: H 0 to 90, mirrored to -H */
} lumis_photometric_symmetry;

/* The emitting shape (IES: from the signs of width, length and height; EULUMDAT: the
 * luminous area). */
typedef enum lumis_photometric_shape {
    LUMIS_SHAPE_POINT = 0, /* all sizes zero */
    LUMIS_SHAPE_RECTANGLE, /* width (y) x length (x), height (z) 0: a flat opening */
    LUMIS_SHAPE_BOX,       /* width x length x height */
    LUMIS_SHAPE_DISK,      /* diameter = width, height 0 */
    LUMIS_SHAPE_CYLINDER,  /* vertical: diameter = width, height */
    LUMIS_SHAPE_SPHERE,    /* diameter = width */
    LUMIS_SHAPE_OTHER      /* a combination the format allows but lumis does not model */
} lumis_photometric_shape;

/* A table as a reader (or a program) gives it.  The arrays are copied by create. */
typedef struct lumis_photometric_desc {
    lumis_photometric_type type;
    int nv, nh;              /* vertical and horizontal angles, >= 1 each (nv >= 2) */
    const double *v_deg;     /* [nv], strictly increasing */
    const double *h_deg;     /* [nh], strictly increasing */
    const double *candela;   /* [nh * nv]: for each horizontal angle, its nv values, >= 0 */
    double multiplier;       /* applied to every value (0 is taken as 1) */
    double lamp_lumens;      /* the file's rated lumens of its lamps, in all; <= 0: absolute
                                photometry (none given) */
    double luminaire_lumens; /* the file's luminaire flux when it says one (EULUMDAT: lamps'
                                flux x LOR); <= 0: none */
    lumis_photometric_shape shape;
    double width, length, height; /* metres, >= 0 */
} lumis_photometric_desc;

typedef struct lumis_photometric lumis_photometric;

/* Checks the table (angle ranges a symmetry can cover, increasing angles, finite
 * non-negative values; errors name the field) and makes the model.  errors may be NULL. */
LUMIS_API lumis_status lumis_photometric_create(const lumis_photometric_desc *desc,
                                                const lumis_error_sink *errors,
                                                lumis_photometric **out);
LUMIS_API void lumis_photometric_destroy(lumis_photometric *p);

/* Luminous intensity (cd, multiplier applied) towards the unit direction d, in the
 * luminaire's frame. */
LUMIS_API double lumis_photometric_intensity(const lumis_photometric *p, lumis_vec3 d);
/* The same at the table's own angles (degrees; type C: h = C, v = gamma). */
LUMIS_API double lumis_photometric_intensity_at(const lumis_photometric *p, double h_deg,
                                                double v_deg);
/* The unit direction of angles (h, v), and back (angles in the table's conventions:
 * C in [0, 360), gamma in [0, 180]; A, B: H and V in [-180, 180]). */
LUMIS_API lumis_vec3 lumis_photometric_direction(lumis_photometric_type type, double h_deg,
                                                 double v_deg);
LUMIS_API void lumis_photometric_angles(lumis_photometric_type type, lumis_vec3 d, double *h_deg,
                                        double *v_deg);

/* The intensity in principal plane k at signed angle t (degrees, -180 to 180), as a polar
 * plot draws it.  Type C: k 0 is the C0-C180 plane (t >= 0 on C0, t < 0 on C180, |t| =
 * gamma), k 1 the C90-C270 plane.  Types A, B: k 0 is the plane V = 0 (t = H), k 1 the
 * plane H = 0 (t = V); both pass through the aim, t = 0. */
LUMIS_API double lumis_photometric_plane_intensity(const lumis_photometric *p, int k, double t_deg);

/* Sampling in proportion to intensity: a direction (luminaire frame) from two numbers in
 * [0, 1), with its pdf per steradian, I(d) / flux up to the 2^-32 quantisation of the
 * cells' probabilities (the pdf returned is the one realised, exactly).  The table's cells
 * are chosen by an inversion table in proportion to their exact flux, a symmetry image at
 * random, then a point inside from the cell's interpolant by inverting its marginal (the
 * edge times sin or cos, Newton in a bisection's bracket) and its linear conditional
 * (docs/photometric.md).  A black table: LUMIS_ERR_INVALID_ARGUMENT, pdf 0. */
LUMIS_API lumis_status lumis_photometric_sample(const lumis_photometric *p, double u0, double u1,
                                                lumis_vec3 *d, double *pdf);
/* The pdf per steradian the sampler draws d with (0 where the table gives no light). */
LUMIS_API double lumis_photometric_pdf(const lumis_photometric *p, lumis_vec3 d);
/* Batches of the four calls above, for a host that evaluates whole arrays in one call (the
 * Python package): element k is bit for bit the single call's.  No allocation, no locks;
 * the model is only read, so threads may share it.  LUMIS_ERR_INVALID_ARGUMENT for a NULL
 * model, or a NULL array when n > 0 (n 0: nothing to do, LUMIS_OK).
 * intensity_n: I(dirs[k]) into out[k], k < n. */
LUMIS_API lumis_status lumis_photometric_intensity_n(const lumis_photometric *p,
                                                     const lumis_vec3 *dirs, size_t n, double *out);
/* The grid of the table's angles: out[i nv + j] = I(h_deg[i], v_deg[j]), nh x nv values
 * (row-major, h the rows). */
LUMIS_API lumis_status lumis_photometric_intensity_at_n(const lumis_photometric *p,
                                                        const double *h_deg, size_t nh,
                                                        const double *v_deg, size_t nv,
                                                        double *out);
/* pdf(dirs[k]) into out[k]. */
LUMIS_API lumis_status lumis_photometric_pdf_n(const lumis_photometric *p, const lumis_vec3 *dirs,
                                               size_t n, double *out);
/* n draws from the pairs u[2k], u[2k + 1] into dirs[k], pdf[k]; every k is drawn, and the
 * status is the first single call's that failed (a black table: all fail, pdf 0). */
LUMIS_API lumis_status lumis_photometric_sample_n(const lumis_photometric *p, const double *u,
                                                  size_t n, lumis_vec3 *dirs, double *pdf);
/* The flux (lm): lumis_photometric_info.flux without the rest of the info. */
LUMIS_API double lumis_photometric_flux(const lumis_photometric *p);
/* Type C: the flux within gamma_deg of the aim, exactly (the cells cut at gamma); types A
 * and B: all of it (their light lies in front). */
LUMIS_API double lumis_photometric_flux_within(const lumis_photometric *p, double gamma_deg);

typedef struct lumis_photometric_info {
    lumis_photometric_type type;
    lumis_photometric_symmetry symmetry;
    lumis_photometric_shape shape;
    double width, length, height;
    int nv, nh;
    double v_first, v_last, h_first, h_last;
    double flux;             /* lm: the exact integral of the interpolated table */
    double lamp_lumens;      /* as given (<= 0: absolute photometry) */
    double luminaire_lumens; /* as given (<= 0: none) */
    double max_candela;
    double max_h, max_v; /* where the table peaks */
    /* Beam (50 %) and field (10 %) angles in the two principal planes (type C: C0-C180 and
     * C90-C270; A, B: the planes V = 0 and H = 0, through the aim): the width, in degrees,
     * of the arc of the plane's whole circle (through nadir and zenith) around its peak where
     * the intensity stays at or above that share of the peak; 360 when all of it does, 0 for
     * a plane without light. */
    double beam_deg[2], field_deg[2];
    double downward_fraction; /* of the flux below the horizontal plane (z < 0) */
} lumis_photometric_info;

LUMIS_API lumis_status lumis_photometric_get_info(const lumis_photometric *p,
                                                  lumis_photometric_info *info);

/* The flux (lm) of the interpolated table within vertical angles [v0, v1] and horizontal
 * angles [h0, h1], exactly: every symmetry image of every cell cut at the range's edges (a
 * cut bilinear cell is bilinear) and integrated in closed form, as the flux is.  Angles in
 * degrees, the table's own: type C gamma (v) and C (h), the C range taken round the circle
 * (h0 <= h1, wider than 360 counts as 360: -90 to 90 is C270 through C0 to C90); types A
 * and B V and H (their light lies within -90 to 90).  LUMIS_ERR_INVALID_ARGUMENT for NULL,
 * a reversed or a non-finite range. */
LUMIS_API lumis_status lumis_photometric_zonal(const lumis_photometric *p, double v0_deg,
                                               double v1_deg, double h0_deg, double h1_deg,
                                               double *lm);

/* IES TM-15-11's luminaire classification system: the lumens (lm) in its ten secondary
 * solid angles.  Forward is TM-15's "270 to 90 degrees horizontal", the half through C0
 * (the corpus's one file that states its rating agrees), back C 90 to 270; low is gamma 0-30, mid
 * 30-60, high 60-80, very high 80-90; uplight low 90-100, high 100-180. */
typedef struct lumis_photometric_lcs {
    double fl, fm, fh, fvh; /* forward low, mid, high, very high */
    double bl, bm, bh, bvh; /* back */
    double ul, uh;          /* uplight low, high */
} lumis_photometric_lcs;

/* What a lighting designer reads off a photometric file beyond lumis_photometric_info
 * (docs/photometric.md has each definition and its source).  Computed on demand by
 * lumis_photometric_get_ratings: a few passes over the table's cells. */
typedef struct lumis_photometric_ratings {
    double lor;      /* light output ratio: the table's flux / the lamps' rated lumens
                        (relative photometry; an EULUMDAT file states its own); 0: absolute
                        photometry (no lamp lumens) */
    double efficacy; /* lm/W: the table's flux / the input watts; 0: no watts given */
    /* NEMA FL 11 beam type of the field angle (10 % of the peak, info.field_deg) in each
     * principal plane: 1 (10-18 deg), 2 (to 29), 3 (to 46), 4 (to 70), 5 (to 100), 6 (to
     * 130), 7 (over 130); 0 under 10 deg or no light.  A floodlight's (types A, B) are
     * horizontal x vertical; for type C they are the C0-C180 and C90-C270 planes'. */
    int nema[2];
    /* Type C only (types A and B: zonal 0, the codes and ratings -1). */
    double zonal_lm[6];   /* lm in gamma 0-30, 30-60, 60-90, 90-120, 120-150, 150-180 */
    int cie_flux_code[5]; /* CIE 52: N1, N2, N3 = 100 x the flux within 41.4, 60, 75.5 deg of
                             nadir (cones of pi/2, pi, 3 pi/2 sr) / the downward flux; N4 =
                             100 x downward / all; N5 = 100 x LOR; rounded.  -1: undefined
                             (N1-N3 without downward flux, N5 for absolute photometry) */
    lumis_photometric_lcs lcs;
    int bug[3]; /* TM-15-11 backlight, uplight and glare ratings, 0 to 5: lumis_photometric_bug */
    /* The spacing criterion (spacing / mounting height above the work plane) along the
     * C0-C180 and C90-C270 planes: lumis_photometric_spacing_criterion.  0: not applicable
     * (types A and B; under 40 % of the flux downward; no light at nadir). */
    double spacing[2];
} lumis_photometric_ratings;

/* The ratings of the model; input_watts from the file (lumis_photometric_file.input_watts;
 * <= 0: none). */
LUMIS_API lumis_status lumis_photometric_get_ratings(const lumis_photometric *p, double input_watts,
                                                     lumis_photometric_ratings *out);

/* The spacing criterion SC of a type C table along the plane through C = c_deg and
 * C = c_deg + 180 (docs/photometric.md, "spacing criterion"): the ratio s / h at which the
 * direct horizontal illuminance midway between two luminaires s apart along that plane,
 * both lighting it, falls to the illuminance straight under one of them from that one
 * alone.  With E(x) = I(gamma) cos^3(gamma) / h^2 at tan(gamma) = x / h, that is
 * SC = 2 tan(gamma*), gamma* the first angle from nadir where
 * (I(gamma, c) + I(gamma, c + 180)) cos^3(gamma) = I0, I0 the mean of I(0, c) and
 * I(0, c + 180).  A Lambertian's is 2 (sqrt 2 - 1)^(1/2) = 1.287, a cos^n distribution's
 * 2 (2^(2/(n+3)) - 1)^(1/2).  *sc = 0 when it does not apply: less than 40 % of the flux
 * goes downward (CIE's semi-indirect and indirect classes: uplights) or I0 is 0.
 * LUMIS_ERR_INVALID_ARGUMENT for NULL, a type A or B table (a floodlight: its spread on a
 * work plane depends on its installed aim) or a non-finite c_deg. */
LUMIS_API lumis_status lumis_photometric_spacing_criterion(const lumis_photometric *p, double c_deg,
                                                           double *sc);

/* The BUG rating of TM-15-11 Addendum A's Tables from the zone lumens: each of B,
 * U and G is the lowest rating whose every zone is at or under its maximum (B: BL, BM, BH;
 * U: UL, UH; G: FVH, BVH, FH, BH), 5 above them all.  type_v: a quadrilaterally symmetric
 * (type V) distribution, whose BH glare limits are FH's (lumis_photometric_get_ratings
 * passes the declared rotational symmetry). */
LUMIS_API lumis_status lumis_photometric_bug(const lumis_photometric_lcs *lcs, int type_v,
                                             int bug[3]);

/* The NEMA beam type (1 to 7; 0 under 10 deg) of a beam spread in degrees. */
LUMIS_API int lumis_photometric_nema_type(double spread_deg);

/* ---- the near field --------------------------------------------------------------------
 *
 * A fixture's luminous opening (its file's disk or rectangle, in the plane z = 0 of its frame,
 * facing the aim -z) whose every point emits the table's distribution: radiance I(d) /
 * (A cos) towards d, nothing behind it.  Far away it is the point; close, it is not. */

/* Illuminance at x (the fixture's frame) on a surface of normal n (towards the fixture for
 * light to arrive): the point's, I(x / |x|) cos / |x|^2 (opening 0), or the opening's, the
 * mean of that law over the opening's points (opening 1; Gauss-Legendre on panels x panels
 * pieces of order 6, 0 == 16; LUMIS_ERR_INVALID_ARGUMENT for a file without a disk or
 * rectangle). */
LUMIS_API lumis_status lumis_photometric_irradiance(const lumis_photometric *p, int opening,
                                                    lumis_vec3 x, lumis_vec3 n, int panels,
                                                    double *E);

/* The table beyond a cone about the aim (type C): its intensities times w(gamma), 0 before
 * from_deg rising linearly to 1 at to_deg (equal: a cut), as a table of its own (the ramp
 * sampled every 1/8 degree as vertical angles; a cut gets a sliver of 10^-6 degrees).  What
 * the light field of the opening leaves out (its report's ramp_from_deg, max_angle_deg),
 * rendered as a point.  Types A and B, from > to: LUMIS_ERR_INVALID_ARGUMENT. */
LUMIS_API lumis_status lumis_photometric_beyond(const lumis_photometric *p, double from_deg,
                                                double to_deg, const lumis_error_sink *errors,
                                                lumis_photometric **out);

/* The two-plane light field (lumis/luminaire.h) of the opening, so that Lu et al.'s
 * restricted sampling applies to a real fixture (docs/photometric.md, "Near field").  The
 * luminaire's frame is the fixture's turned half a turn about x: U the opening (z = 0),
 * light towards +z = the aim.
 * - It carries the directions within max_angle of the aim, the last 5 degrees (at most a
 *   quarter of the cone) fading linearly to 0: their flux, up to the quadrature of each
 *   pixel's.  The rest (a two-plane field cannot carry 90 degrees and more) is the far-field
 *   residual lumis_photometric_beyond(ramp_from_deg, max_angle_deg): field and residual
 *   together hold the table's flux, and a soft edge is one the images can hold.
 * - Its far field is the table's: the images are the directional distribution deconvolved
 *   by the bases' and the pixels' blur (every image the same array shifted by whole pixels,
 *   the pixels a whole fraction of the basis spacing), so far away it converges to the
 *   point law, not to a blurred one.
 * - Unless given, its resolution is chosen from error_target: the coarsest of a ladder of
 *   angular resolutions (basis spacing / delta) whose measured far-field error (the largest
 *   |I_field / I - 1| over the directions within the cone holding at least 10 % of the peak)
 *   is within it; and the bases and delta such that the basis blur's near-field error stays
 *   below the point model's out to 50 opening sizes. */
typedef struct lumis_photometric_light_field {
    int grid[2];                 /* bases across the opening (0: chosen, see above) */
    int width, height;           /* about this many pixels per image (0: chosen: 2 pixels per
                                    basis spacing); rounded to whole pixels per spacing */
    double delta;                /* U to S (0: chosen) */
    double max_angle_deg;        /* the directions S carries (0: where 99.9 % of the flux is,
                                    + 5 degrees, at most 80) */
    lumis_luminaire_basis basis; /* 0: quadratic */
    int supersample;             /* Gauss-Legendre points per pixel per axis for its flux
                                    (0: 4) */
    double error_target;         /* far-field relative error to reach (0: 0.005) */
} lumis_photometric_light_field;

/* What lumis_luminaire_from_photometric made and how close it is. */
typedef struct lumis_photometric_light_field_report {
    int grid[2], width, height, pixels_per_spacing[2];
    double delta, max_angle_deg, ramp_from_deg;
    double flux;             /* the table's (lm) */
    double light_field_flux; /* the light field's power (lm: lumis_luminaire_info.total_power) */
    double residual_flux;    /* what the light field leaves (lm): type C the residual table's
                                flux; A, B the table's less the light field's */
    double residual_share;   /* residual_flux / flux */
    double error_target;     /* as used */
    double far_field_error;  /* reached: the largest |I_field / I - 1| measured (1000 sizes
                                away, against the point law), over the directions within
                                max_angle with I >= 10 % of the peak */
    double far_field_error_mean; /* the mean of |I_field / I - 1| over them */
    int directions;              /* how many */
    int target_met;              /* 0: the finest resolution allowed (16 M pixels in all)
                                    did not reach error_target */
    /* Where the near-field fixture (lumis_photometric_near_irradiance) changes models,
     * measured as the field is made: on receivers facing the opening in every direction of
     * its field (gamma 0 to 85 by 5 degrees, C every 15, I >= 10 % of the peak) at 0.5 to 50
     * sizes, the largest |model / opening - 1| of the light field (+ residual) and of the
     * point model against the exact opening (lumis_photometric_irradiance, 8 panels). */
    double crossover_sizes; /* the first distance (sizes, interpolated in log-log) where the
                               field's error reaches the point's; 0: the point is closer
                               from 0.5 sizes on; beyond 50 extrapolated (the point's error
                               falling as its measured slope, the field's held) */
    double near_until;      /* the field (+ residual) up to this distance from the opening's
                               centre (the table's units: metres) */
    double far_from;        /* the point model from this distance on; blended between */
    double size;            /* the opening's largest dimension (m) */
} lumis_photometric_light_field_report;

/* report may be NULL.  A table without flux within max_angle, or a file without a disk or
 * rectangle opening: LUMIS_ERR_INVALID_ARGUMENT. */
LUMIS_API lumis_status lumis_luminaire_from_photometric(
    const lumis_photometric *p, const lumis_photometric_light_field *desc,
    const lumis_error_sink *errors, lumis_luminaire **out,
    lumis_photometric_light_field_report *report);

/* The near-field fixture (docs/photometric.md, "A fixture that converges to its far field"):
 * a light field made from the table (lumis_luminaire_from_photometric, report r) close to
 * the opening, the point model far from it, so that it is never worse than the point where
 * the point is the better model.  At distance D from the opening's centre, with
 * w = lumis_photometric_near_weight(r, D):
 *   E = w (E_field + E_residual) + (1 - w) E_point,
 * E_field the light field's irradiance (lumis_luminaire_irradiance, its frame the fixture's
 * turned half a turn about x), E_residual the point law of lumis_photometric_beyond(p,
 * r->ramp_from_deg, r->max_angle_deg) (none for types A and B), E_point the table's point
 * law.  x and n as lumis_photometric_irradiance's (the fixture's frame).  The renderer's
 * near-field fixtures (lumis_photometric_instance.light_field) estimate it without bias.
 * LUMIS_ERR_INVALID_ARGUMENT for NULL or a report whose flux is not the table's. */
LUMIS_API lumis_status lumis_photometric_near_irradiance(
    const lumis_photometric *p, const lumis_luminaire *light_field,
    const lumis_photometric_light_field_report *r, lumis_vec3 x, lumis_vec3 n, double *E);

/* The field's weight at distance D: 1 up to r->near_until, 0 from r->far_from on, linear in
 * log D between (0 for NULL, or a D that is not a number). */
LUMIS_API double lumis_photometric_near_weight(const lumis_photometric_light_field_report *r,
                                               double distance);

/* The names: "C", "B", "A"; "none", "rotational", "C0-C180", "C90-C270", "quadrant",
 * "lateral"; "point", "rectangle", "box", "disk", "cylinder", "sphere", "other". */
LUMIS_API const char *lumis_photometric_type_name(lumis_photometric_type t);
LUMIS_API const char *lumis_photometric_symmetry_name(lumis_photometric_symmetry s);
LUMIS_API const char *lumis_photometric_shape_name(lumis_photometric_shape s);
/* And back (LUMIS_ERR_INVALID_ARGUMENT for an unknown name or NULL; *out unchanged). */
LUMIS_API lumis_status lumis_photometric_type_from_name(const char *name,
                                                        lumis_photometric_type *out);
LUMIS_API lumis_status lumis_photometric_symmetry_from_name(const char *name,
                                                            lumis_photometric_symmetry *out);
LUMIS_API lumis_status lumis_photometric_shape_from_name(const char *name,
                                                         lumis_photometric_shape *out);

#ifdef __cplusplus
}
#endif
#endif
