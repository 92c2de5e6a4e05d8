/* lumis/lumis.h - the core library: include this one header to embed lumis.
 * (Image files: lumis/io.h, in the lumis-io library.) */
#ifndef LUMIS_LUMIS_H
#define LUMIS_LUMIS_H

#include "lumis/envmap.h"
#include "lumis/image.h"
#include "lumis/lights.h"
#include "lumis/luminaire.h"
#include "lumis/metrics.h"
#include "lumis/photometry.h"
#include "lumis/rng.h"
#include "lumis/sampler.h"
#include "lumis/sky.h"
#include "lumis/status.h"
#include "lumis/sun.h"
#include "lumis/types.h"
#include "lumis/version.h"

#endif
