/* lumis/render_lighting.h - how a render is lit: one value (lumis_lighting) of one kind (an
 * environment map, a light set, light-field luminaires, photometric fixtures), each kind's
 * fields, and the names of its choices (library lumis-render; lumis/render.h includes every
 * part). */
#ifndef LUMIS_RENDER_LIGHTING_H_PUBLIC
#define LUMIS_RENDER_LIGHTING_H_PUBLIC

#include "lumis/envmap.h"
#include "lumis/export.h"
#include "lumis/lights.h"
#include "lumis/luminaire.h"
#include "lumis/photometry.h"
#include "lumis/sampler.h"
#include "lumis/status.h"
#include "lumis/sun.h"
#include "lumis/types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lumis_estimator {
    LUMIS_ESTIMATOR_MIS = 0, /* light and BSDF samples combined (default) */
    LUMIS_ESTIMATOR_LIGHT,   /* light samples only */
    LUMIS_ESTIMATOR_BSDF     /* BSDF samples only */
} lumis_estimator;

/* How a light set lights a shading point (docs/lights.md, "Stratified mode"). */
typedef enum lumis_lights_mode {
    LUMIS_LIGHTS_POINT = 0,      /* each region as a point light at its centroid: every light
                                    of the pixel's interleaved set, deterministic, biased (the
                                    preview, and what the export writes) */
    LUMIS_LIGHTS_STRATIFIED = 1, /* each region as a stratum of the map: one direction drawn
                                    in every region per camera sample and vertex, weighted by
                                    radiance over pdf, combined with BSDF sampling by MIS:
                                    unbiased, error falling as 1 / samples */
    LUMIS_LIGHTS_MODE_COUNT
} lumis_lights_mode;

/* "point", "stratified". */
LUMIS_RENDER_API const char *lumis_lights_mode_name(lumis_lights_mode mode);
LUMIS_RENDER_API lumis_status lumis_lights_mode_from_name(const char *name, lumis_lights_mode *out);

/* ---- light-field luminaires in a scene (Lu et al.; lumis/luminaire.h) -------------------- */

/* A luminaire placed in a scene: world = R (scale local) + t.  Radiance is unchanged by the
 * scale (it only converts lengths: 0.001 puts a luminaire measured in millimetres into a scene
 * in metres), so irradiance is too. */
typedef struct lumis_luminaire_instance {
    const lumis_luminaire *luminaire;
    lumis_rigid placement; /* R a proper rotation (lumis_rigid_check); all zeros == identity */
    double scale;          /* world units per luminaire unit, > 0; 0 == 1 */
    float intensity;       /* radiance multiplier, >= 0; 0 == 1 */
} lumis_luminaire_instance;

/* How a luminaire sample's visibility is decided. */
typedef enum lumis_visibility {
    LUMIS_VISIBILITY_EXACT = 0,  /* one shadow ray per light sample, to its point on U */
    LUMIS_VISIBILITY_APPROX,     /* Lu et al. 6.2: per cell of the basis grid on U one ray to
                                    the cell's centre; a sample of image m is weighted by the
                                    mean visibility v_m(p) over the cells of Phi_m's support
                                    (rays here where the paper uses shadow maps) */
    LUMIS_VISIBILITY_NONE,       /* no shadows (the paper's irradiance, Eq. 2) */
    LUMIS_VISIBILITY_SHADOW_MAP, /* approx, with the visibility of each cell's centre read
                                   from a depth map rendered from it when the render starts
                                   (as the paper): no ray per shading point */
    LUMIS_VISIBILITY_COUNT
} lumis_visibility;

/* Where a render's numbers come from: lumis_sequence (lumis/rng.h, docs/sampling.md). */

/* "exact", "approx", "none", "shadowmap". */
LUMIS_RENDER_API const char *lumis_visibility_name(lumis_visibility visibility);
LUMIS_RENDER_API lumis_status lumis_visibility_from_name(const char *name, lumis_visibility *out);

/* Luminaires as the renderer's lights: every camera sample's hit is lit by each instance with
 * lumis_luminaire_sample_point (budget samples shared among its images) and the material's
 * BSDF.  The instances and their luminaires must outlive the render. */
typedef struct lumis_luminaire_lighting {
    const lumis_luminaire_instance *instances;
    int count;
    int budget;                        /* K per instance per camera sample; 0 == 32 */
    int k_max;                         /* most samples for one image; 0 == no cap */
    lumis_luminaire_strategy strategy; /* 0 == restricted (Lu et al.); LUMIS_LUM_AUTO:
                                          per instance, lumis_render_luminaire_choices */
    lumis_luminaire_search search;     /* 0 == the library's default */
    int depth;                         /* search depth; 0 == exact */
    lumis_visibility visibility;       /* 0 == exact */
    int auto_bands; /* with LUMIS_LUM_AUTO, nonzero: a band of distance may take its own
                       strategy (lumis_render_luminaire_choices); off by default, since a
                       band's choice also applies to what no probe saw in it */
    const lumis_luminaire_costs *auto_costs; /* with LUMIS_LUM_AUTO: the cost model (NULL ==
                                                lumis_luminaire_costs_default()) */
    /* NULL, or count entries: with LUMIS_LUM_AUTO the render writes there, as it prepares,
     * how it samples each luminaire (what lumis_render_luminaire_choices returns: the
     * caller need not predict again to report it). */
    struct lumis_luminaire_choice *chosen;
} lumis_luminaire_lighting;

/* ---- photometric fixtures in a scene (IES, EULUMDAT; lumis/photometry.h) --------------- */

/* A fixture's far-field table placed in a scene: world = R local + t, its aim (local -z)
 * R (0, 0, -1).  As a point at t; or, with `area`, as the file's luminous opening centred at
 * t: a flat disk or rectangle facing the aim (radiance I(d) / (A cos) towards d, zero
 * behind it), or a solid box, vertical cylinder or sphere (every surface point emits
 * I(d) / A_proj(d), A_proj the area the solid shows towards d), so that far away each is
 * the point; lumis_render refuses `area` for a point or an "other" shape.  White light:
 * the render's three channels are candela times the multiplier. */
typedef struct lumis_photometric_instance {
    const lumis_photometric *photometric;
    lumis_rigid placement; /* R a proper rotation; all zeros == identity */
    double multiplier;     /* >= 0; 0 == 1 */
    int area;              /* nonzero: the luminous opening, else a point */
    /* NULL, or the near-field fixture (lumis_photometric_near_irradiance): the light field
     * lumis_luminaire_from_photometric made of this table, placed with the fixture (its frame
     * the fixture's turned half a turn about x), and that call's report.  At distance D from
     * the fixture's position, with w = lumis_photometric_near_weight(report, D), a vertex
     * gets w times the field's samples (32 per vertex, Lu et al.'s restricted strategy, one
     * shadow ray each) and one point of intensity w I_residual + (1 - w) I_table: beyond
     * report->far_from exactly the point model.  Both together with `area`, a type A or B
     * table, or a report whose flux is not the table's: refused. */
    const lumis_luminaire *light_field;
    const lumis_photometric_light_field_report *light_field_report;
} lumis_photometric_instance;

/* Photometric fixtures as the renderer's lights: at every vertex each is sampled
 * light_samples times (a point: its one direction; an opening: points on it by area, with
 * the BSDF's samples and MIS as lighting.estimator says), one shadow ray each.  The
 * instances and their models must outlive the render. */
typedef struct lumis_photometric_lighting {
    const lumis_photometric_instance *instances;
    int count;
} lumis_photometric_lighting;

/* A fixture's rotation (world = R local, row-major) for a file of photometric `type`: local
 * -z along `aim` (a direction), local +x (C0 for type C; the fixture's top for types A and
 * B: lumis/photometry.h) chosen as follows, then turned `roll_deg` about the aim (+x towards
 * +y: counter-clockwise seen from behind the fixture).  With a = aim / |aim|:
 *  - `up` given: +x = up made perpendicular to the aim, (u - (u.a) a) / |...|.
 *  - type C: the hanging pose (aim -y, C0 +x, C90 -z) turned by the smallest rotation that
 *    takes -y to a (about (-a.z, 0, a.x)): C0 = (1 - a.x^2 / (1 - a.y), a.x,
 *    -a.x a.z / (1 - a.y)).  Continuous in the aim except at straight up (+y), where the
 *    frame is the half turn about x: C0 +x, C90 +z.
 *  - types A, B: a yoke.  The lateral axis (local +y) is horizontal, (a.z, 0, -a.x) / h with
 *    h = sqrt(a.x^2 + a.z^2), and +x (up) points above the aim, so a horizontal beam stays
 *    horizontal however the fixture is panned and tilted.  Continuous except at straight
 *    up and down (h < 1e-9): there +x is world +x.
 * Turning the aim and `up` about any axis turns R with them; without `up` so does any turn
 * of a floodlight (A, B) about y, while a type C fixture keeps its C0 as it tilts
 * (docs/photometric.md, "Aiming a fixture", has the figure).  LUMIS_ERR_INVALID_ARGUMENT
 * (R unchanged) for an unknown type, a zero or non-finite aim or roll, or an `up` that is
 * zero, not finite or within 1e-6 (sine) of the aim's line. */
LUMIS_RENDER_API lumis_status lumis_photometric_orient(lumis_photometric_type type, lumis_vec3 aim,
                                                       const lumis_vec3 *up, double roll_deg,
                                                       double R[9]);

/* ---- how a render is lit: one value ------------------------------------------------------
 *
 * A render is lit by exactly one kind of light.  Each kind needs some fields of
 * lumis_lighting and takes some of the render's (lumis_render_desc); every other lighting
 * field must be left at zero, and lumis_lighting_check refuses a field that a kind does not
 * use, naming it ("lighting.sampler", "max_bounces"...).  Zero is the environment map
 * sampled with MIS.
 *
 *   kind          needs                          also takes
 *   env           env; sampler (unless the       estimator, hide_environment, power_heuristic,
 *                 estimator is BSDF)             light_samples, bsdf_samples, max_bounces, sun
 *   light-set     env; light_set.set             light_set.kinds, hide_environment, sun; in
 *                                                stratified mode light_set.regions, estimator
 *                                                (light or MIS), power_heuristic, max_bounces
 *   luminaires    luminaires (count >= 1)        -- (camera rays that escape see black)
 *   photometric   photometric (count >= 1)       estimator, power_heuristic, light_samples,
 *                                                bsdf_samples, max_bounces (escaping: black)
 */
typedef enum lumis_lighting_kind {
    LUMIS_LIGHTING_ENV = 0,     /* the environment map, sampled per pixel through `sampler`
                                   with `estimator` (light, BSDF or MIS sampling) */
    LUMIS_LIGHTING_LIGHT_SET,   /* a light set (lumis/lights.h), as light_set.mode says */
    LUMIS_LIGHTING_LUMINAIRES,  /* light-field luminaires (lumis_luminaire_lighting) */
    LUMIS_LIGHTING_PHOTOMETRIC, /* photometric fixtures (lumis_photometric_lighting) */
    LUMIS_LIGHTING_KIND_COUNT
} lumis_lighting_kind;

/* "env", "light-set", "luminaires", "photometric". */
LUMIS_RENDER_API const char *lumis_lighting_kind_name(lumis_lighting_kind kind);
LUMIS_RENDER_API lumis_status lumis_lighting_kind_from_name(const char *name,
                                                            lumis_lighting_kind *out);

/* A light set as the renderer's lights (kind light-set).  The set (and regions) must outlive
 * the render. */
typedef struct lumis_light_set_lighting {
    /* Point mode: every light of the pixel's interleaved set (lumis_light_set_interleave_
     * index), one shadow ray each, traced 16 at a time; deterministic apart from the
     * camera's jitter; direct illumination only.  Stratified mode: the set's regions are
     * strata instead, one direction in each (the regions of `kinds`) per vertex, combined
     * with the BSDF's by `estimator` (MIS by default: each region's pdf against the
     * BSDF's), path tracing allowed; interleaving does not apply.  With draws = N > 0
     * (stratified mode only) each vertex draws N directions instead, over regions chosen in
     * proportion to a weight of their contribution there (power x the cosine at the
     * region's centroid plus a fifth of a bound over its cone x a BSDF weight), with the
     * selection probability in the estimator and in the MIS weights; regions wholly below
     * the horizon are never chosen (docs/lights.md, "Selected draws").  With region_draws =
     * N instead, every region keeps its draws and its place in the sum, but gets n_r >= 1
     * of them (averaged; n_r stratified points of its dimension), the N split before the
     * render in proportion to a bound of each region's noise (docs/lights.md, "Allocated
     * draws"). */
    const lumis_light_set *set;          /* required */
    unsigned kinds;                      /* lights of the set used: 0 == all, else a mask of bits
                                            1u << lumis_light_kind (e.g. EnvDirects only) */
    lumis_lights_mode mode;              /* 0 == point */
    const lumis_region_sampler *regions; /* stratified: made from this set and env; NULL ==
                                            the render makes them */
    int draws;                           /* stratified: 0 == one draw in every region; N in
                                            1 .. LUMIS_LIGHT_SET_MAX_DRAWS: N draws per
                                            vertex over regions chosen per shading point */
    int region_draws;                    /* stratified, draws 0: 0 == one draw in every
                                            region; N (regions lit .. LUMIS_LIGHT_SET_MAX_DRAWS):
                                            N draws per vertex, n_r >= 1 in region r, fixed
                                            before the render by Neyman allocation (the
                                            regions' luminous power x solid angle^(1/4));
                                            no region lit: nothing to allocate, rendered as
                                            with 0.  Refused: N < 0 or over the maximum, N
                                            with draws, N in point mode (all by
                                            lumis_lighting_check / lumis_session_check,
                                            before anything is built); N under the regions
                                            lit -- by the checks too when `regions` is
                                            given, else only once the render (or a
                                            session, which makes the set) has built its
                                            region samplers, which know which regions are
                                            empty: the lit count is not known before */
} lumis_light_set_lighting;

enum { LUMIS_LIGHT_SET_MAX_DRAWS = 4096 };

/* A sun split off the map (lumis/sun.h; kinds env and light-set).  At every vertex the sun
 * is drawn once by its sampler (its pixels by their power) and combined by `estimator` with
 * a BSDF sample of its own, each weighted against the sun's pdf alone (MIS: the balance, or
 * the power heuristic); the kind lights the point from the residual.  Since sun + residual
 * == map in every direction, the sum is the map's light, unbiased (docs/lights.md, "The
 * image sun"). */
typedef struct lumis_sun_lighting {
    const lumis_sun *sun;         /* NULL == no sun; else found by lumis_sun_find in env */
    const lumis_envmap *residual; /* with a sun, required: the map without it (lumis_sun_find's);
                                     the sampler (env), the light set and regions (light-set)
                                     must be made from it, while env stays the whole map */
    const lumis_sun_sampler *sampler; /* with a sun, required: lumis_sun_sampler_create(env,
                                         sun) */
} lumis_sun_lighting;

/* How a render is lit (the table above says which fields each kind uses; zero-init: the
 * environment map, sampled with MIS). */
typedef struct lumis_lighting {
    lumis_lighting_kind kind;           /* 0 == env */
    const lumis_envmap *env;            /* env, light-set: the light, also seen by camera rays that
                                           escape; required by them, refused by the others */
    const lumis_sampler *sampler;       /* env: the map's light sampler; NULL for the BSDF
                                           estimator */
    lumis_estimator estimator;          /* 0 == MIS (env, stratified light sets, fixtures) */
    int hide_environment;               /* env, light-set: nonzero: camera rays that escape see
                                           black (a layer added to another which shows the map) */
    lumis_light_set_lighting light_set; /* light-set */
    lumis_sun_lighting sun;             /* env, light-set: a sun split off env; zero == none */
    const lumis_luminaire_lighting *luminaires;    /* luminaires: NULL for another kind */
    const lumis_photometric_lighting *photometric; /* photometric: NULL for another kind */
} lumis_lighting;

#ifdef __cplusplus
}
#endif
#endif
