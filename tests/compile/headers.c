/* Every public header, compiled as strict C11 (see tests/CMakeLists.txt). */
#include "lumis/io.h"
#include "lumis/lights.h"
#include "lumis/luminaire.h"
#include "lumis/lumis.h"
#include "lumis/render.h"

int lumis_headers_compile_as_c(void);
int lumis_headers_compile_as_c(void)
{
    lumis_envmap_desc d = {0};
    lumis_decomp_desc l = {0};
    lumis_luminaire_desc f = {0};
    lumis_luminaire_query q = {0};
    return d.width + l.count + f.width + q.budget + lumis_light_set_interleave_index(8, 1, 1) +
           (int)LUMIS_OK;
}
