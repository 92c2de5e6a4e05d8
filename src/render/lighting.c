/* How a render is lit: one value (lumis_lighting), its kinds' names, and the one check that
 * owns every incompatibility of a lighting with the rest of a render description.  Each
 * kind declares what it needs and takes (its inputs(), shade.h); the check refuses a
 * missing need and any field set that the kind does not take, one message per condition,
 * naming the field. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "internal.h"
#include "shade.h"

#include <string.h>

/* indexed by lumis_lighting_kind */
static const lumis__light_kind *const kinds[LUMIS_LIGHTING_KIND_COUNT] = {
    &lumis__light_env, &lumis__light_set_kind, &lumis__light_luminaires, &lumis__light_photometric};

static const char *const kind_names[] = {"env", "light-set", "luminaires", "photometric"};

LUMIS__ENUM_NAMES(lumis_lighting_kind, LUMIS_LIGHTING_KIND_COUNT, kind_names,
                  lumis_lighting_kind_name, lumis_lighting_kind_from_name);

const char *lumis__lighting_lit_by(lumis_lighting_kind kind)
{
    return kinds[kind]->name;
}

const lumis__light_kind *lumis__light_kind_of(const lumis_render_desc *d)
{
    return kinds[d->lighting.kind];
}

/* The inputs, in the order they are checked (the first wrong one is reported: a missing one
 * from the end, the map first; one given that does not apply from the start, the options
 * of the map's sampling before the map): what the field is called, what a kind that needs
 * it is missing, and why one that does not take it refuses it. */
static const struct {
    unsigned bit;
    const char *field, *need, *why;
} inputs[LUMIS__IN_COUNT] = {
    {LUMIS__IN_SAMPLER, "lighting.sampler", "a light sampler (NULL only with the BSDF estimator)",
     " (only the environment map is sampled through one)"},
    {LUMIS__IN_EST_LIGHT, "lighting.estimator", "", " (light sampling alone: nothing to combine)"},
    {LUMIS__IN_EST_BSDF, "lighting.estimator", "",
     " (BSDF sampling alone: every light or region is drawn)"},
    {LUMIS__IN_SET, "lighting.light_set.set", "a light set", ""},
    {LUMIS__IN_SET_KINDS, "lighting.light_set.kinds", "", ""},
    {LUMIS__IN_SET_MODE, "lighting.light_set.mode", "", ""},
    {LUMIS__IN_REGIONS, "lighting.light_set.regions", "", " (strata of the stratified mode)"},
    {LUMIS__IN_LUMINAIRES, "lighting.luminaires", "luminaires", ""},
    {LUMIS__IN_PHOTOMETRIC, "lighting.photometric", "photometric fixtures", ""},
    {LUMIS__IN_ENV, "lighting.env", "an environment map",
     " (it lights the scene alone; camera rays that escape see black)"},
    {LUMIS__IN_HIDE, "lighting.hide_environment", "", " (no map to hide)"},
    {LUMIS__IN_POWER, "power_heuristic", "", " (no light and BSDF samples combined)"},
    {LUMIS__IN_LIGHT_SAMPLES, "light_samples", "", ""},
    {LUMIS__IN_BSDF_SAMPLES, "bsdf_samples", "", ""},
    {LUMIS__IN_BOUNCES, "max_bounces", "", " (direct illumination only)"},
    {LUMIS__IN_SUN, "lighting.sun.sun", "", " (a sun is split off an environment map)"},
    {LUMIS__IN_SET_DRAWS, "lighting.light_set.draws", "",
     " (the point lights are all evaluated; draws chooses regions as strata)"},
    {LUMIS__IN_SET_ALLOC, "lighting.light_set.region_draws", "",
     " (the point lights are all evaluated; region_draws splits draws over regions as "
     "strata)"},
};

/* What a render description gives of the inputs. */
static unsigned given(const lumis_render_desc *d, int set_to_come)
{
    const lumis_lighting *l = &d->lighting;
    return (l->sampler ? LUMIS__IN_SAMPLER : 0u) |
           (l->estimator == LUMIS_ESTIMATOR_LIGHT ? LUMIS__IN_EST_LIGHT : 0u) |
           (l->estimator == LUMIS_ESTIMATOR_BSDF ? LUMIS__IN_EST_BSDF : 0u) |
           (l->light_set.set || set_to_come ? LUMIS__IN_SET : 0u) |
           (l->light_set.kinds ? LUMIS__IN_SET_KINDS : 0u) |
           (l->light_set.mode != LUMIS_LIGHTS_POINT ? LUMIS__IN_SET_MODE : 0u) |
           (l->light_set.regions ? LUMIS__IN_REGIONS : 0u) |
           (l->luminaires ? LUMIS__IN_LUMINAIRES : 0u) |
           (l->photometric ? LUMIS__IN_PHOTOMETRIC : 0u) | (l->env ? LUMIS__IN_ENV : 0u) |
           (l->hide_environment ? LUMIS__IN_HIDE : 0u) |
           (d->power_heuristic ? LUMIS__IN_POWER : 0u) |
           (d->light_samples ? LUMIS__IN_LIGHT_SAMPLES : 0u) |
           (d->bsdf_samples ? LUMIS__IN_BSDF_SAMPLES : 0u) |
           (d->max_bounces > 0 ? LUMIS__IN_BOUNCES : 0u) | (l->sun.sun ? LUMIS__IN_SUN : 0u) |
           (l->light_set.draws ? LUMIS__IN_SET_DRAWS : 0u) |
           (l->light_set.region_draws ? LUMIS__IN_SET_ALLOC : 0u);
}

/* A sun split off the map: found, with its residual, the same size as the map, and (env) the
 * sampler drawing from that residual. */
static lumis_status check_sun(const lumis_render_desc *d)
{
    const lumis_lighting *l = &d->lighting;
    const lumis_error_sink *errors = &d->errors;
    if (!l->sun.sun) {
        if (l->sun.residual || l->sun.sampler)
            return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "render: lighting.sun.%s: given without lighting.sun.sun",
                               l->sun.residual ? "residual" : "sampler");
        return LUMIS_OK;
    }
    if (!l->sun.sun->found)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.sun.sun: no sun (found 0): leave it NULL");
    if (!l->sun.residual)
        return lumis__fail(
            errors, LUMIS_ERR_INVALID_ARGUMENT,
            "render: lighting.sun.residual: missing: a sun needs the map without it");
    if (lumis_envmap_width(l->sun.residual) != lumis_envmap_width(l->env) ||
        lumis_envmap_height(l->sun.residual) != lumis_envmap_height(l->env) ||
        lumis_envmap_rotation_deg(l->sun.residual) != lumis_envmap_rotation_deg(l->env) ||
        lumis_envmap_scale(l->sun.residual) != lumis_envmap_scale(l->env))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.sun.residual: %dx%d, not lighting.env's %dx%d with "
                           "its rotation and scale",
                           lumis_envmap_width(l->sun.residual),
                           lumis_envmap_height(l->sun.residual), lumis_envmap_width(l->env),
                           lumis_envmap_height(l->env));
    if (l->kind == LUMIS_LIGHTING_ENV && l->sampler &&
        lumis_sampler_envmap(l->sampler) != l->sun.residual)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.sampler: must sample lighting.sun.residual (the map "
                           "without its sun), not another map");
    return LUMIS_OK;
}

/* Allocated draws (light_set.region_draws N > 0) need N >= the regions lit (those of `kinds`
 * that hold light: at least one draw each).  With the caller's region samplers that count
 * is known here, in O(K), before anything is built; without them it is not (a region's
 * emptiness is the samplers', and a session's set is made later), and the render's prepare
 * checks it once they exist (light_set.c), with the same message. */
static lumis_status check_region_draws(const lumis_render_desc *d)
{
    const lumis_light_set_lighting *ls = &d->lighting.light_set;
    if (d->lighting.kind != LUMIS_LIGHTING_LIGHT_SET || ls->mode != LUMIS_LIGHTS_STRATIFIED ||
        ls->region_draws <= 0 || !ls->regions)
        return LUMIS_OK;
    int lit = 0;
    for (int k = 0; k < lumis_region_sampler_count(ls->regions); k++)
        lit += lumis__region_lit(ls->regions, k, ls->kinds);
    if (ls->region_draws < lit)
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.light_set.region_draws %d: under the %d regions lit "
                           "(each draws at least once)",
                           ls->region_draws, lit);
    return LUMIS_OK;
}

lumis_status lumis__lighting_check(const lumis_render_desc *d, int set_to_come)
{
    if (!d) return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis_lighting *l = &d->lighting;
    const lumis_error_sink *errors = &d->errors;
    if ((unsigned)l->kind >= LUMIS_LIGHTING_KIND_COUNT)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.kind %d: unknown (env, light-set, luminaires or "
                           "photometric)",
                           (int)l->kind);
    if ((unsigned)l->light_set.mode >= LUMIS_LIGHTS_MODE_COUNT)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.light_set.mode %d: unknown (point or stratified)",
                           (int)l->light_set.mode);
    if (l->light_set.draws < 0 || l->light_set.draws > LUMIS_LIGHT_SET_MAX_DRAWS)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.light_set.draws %d: out of range (0: one draw in "
                           "every region, 1 .. %d draws chosen per shading point)",
                           l->light_set.draws, LUMIS_LIGHT_SET_MAX_DRAWS);
    if (l->light_set.region_draws < 0 || l->light_set.region_draws > LUMIS_LIGHT_SET_MAX_DRAWS)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.light_set.region_draws %d: out of range (0: one "
                           "draw in every region, else at least one per region, at most %d)",
                           l->light_set.region_draws, LUMIS_LIGHT_SET_MAX_DRAWS);
    if (l->light_set.region_draws && l->light_set.draws)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.light_set.region_draws %d with draws %d: one or the "
                           "other (draws chooses regions per vertex, region_draws draws in "
                           "every region)",
                           l->light_set.region_draws, l->light_set.draws);
    if ((unsigned)l->estimator > LUMIS_ESTIMATOR_BSDF)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.estimator %d: unknown (MIS, light or BSDF)",
                           (int)l->estimator);
    const lumis__light_kind *kind = kinds[l->kind];
    unsigned needs = 0, takes = 0;
    kind->inputs(l, &needs, &takes);
    const unsigned have = given(d, set_to_come);
    const char *mode = l->kind != LUMIS_LIGHTING_LIGHT_SET            ? ""
                       : l->light_set.mode == LUMIS_LIGHTS_STRATIFIED ? " in stratified mode"
                                                                      : " in point mode";
    /* what is missing first, the map before what is made from it */
    const unsigned missing = needs & ~have;
    for (int k = LUMIS__IN_COUNT - 1; missing && k >= 0; k--)
        if (missing & inputs[k].bit)
            return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "render: %s: missing: lighting by %s%s needs %s", inputs[k].field,
                               kind->name, mode, inputs[k].need);
    for (int k = 0; k < LUMIS__IN_COUNT; k++) {
        const unsigned bit = inputs[k].bit;
        if ((have & bit) && !((needs | takes) & bit))
            return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "render: %s: does not apply: the scene is lit by %s%s%s",
                               inputs[k].field, kind->name, mode, inputs[k].why);
    }
    const lumis_status ast = check_region_draws(d);
    return ast != LUMIS_OK ? ast : check_sun(d);
}

lumis_status lumis_lighting_check(const lumis_render_desc *d)
{
    return lumis__lighting_check(d, 0);
}
