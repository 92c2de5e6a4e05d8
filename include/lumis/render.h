/* lumis/render.h - the evaluation renderer (library lumis-render): a scene of spheres,
 * planes and (instanced) triangle meshes with BSDFs, traced with Embree, lit by an
 * environment map through any lumis_sampler, with light, BSDF or multiple importance
 * sampling.
 *
 * It exists to measure samplers: direct illumination from the environment (or, clearly
 * labelled, path-traced global illumination for references), exact estimators, and images
 * that depend on the seed and the sample count but never on the thread count or on how the
 * samples were split into passes. */
#ifndef LUMIS_RENDER_H
#define LUMIS_RENDER_H

/* The renderer's interface, one header per idea (scene, lighting, job, G-buffer, session,
 * scene files); this one includes them all, and the core and io headers they build on. */
#include "lumis/bsdf.h"
#include "lumis/envmap.h"
#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/io.h"
#include "lumis/lights.h"
#include "lumis/luminaire.h"
#include "lumis/photometry.h"
#include "lumis/rng.h"
#include "lumis/sampler.h"
#include "lumis/status.h"
#include "lumis/types.h"
#include "lumis/render_scene.h"
#include "lumis/render_lighting.h"
#include "lumis/render_job.h"
#include "lumis/render_gbuffer.h"
#include "lumis/render_session.h"
#include "lumis/render_scene_file.h"

#endif
