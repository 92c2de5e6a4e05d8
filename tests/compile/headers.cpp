// Every public header, compiled as C++17 (see tests/CMakeLists.txt).
#include "lumis/io.h"
#include "lumis/lights.h"
#include "lumis/luminaire.h"
#include "lumis/lumis.h"
#include "lumis/render.h"

int lumis_headers_compile_as_cxx();
int lumis_headers_compile_as_cxx()
{
    lumis_envmap_desc d{};
    lumis_median_cut_desc m{};
    lumis_luminaire_desc f{};
    lumis_luminaire_query q{};
    d.width += m.count + f.width + q.budget + lumis_light_set_interleave_index(8, 1, 1);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 1, 2);
    return d.width + static_cast<int>(lumis_pcg32_next(&rng) & 1u);
}
