/* Every public header, compiled as strict C11 (see tests/CMakeLists.txt). */
#include "lumis/io.h"
#include "lumis/lumis.h"
#include "lumis/render.h"

int lumis_headers_compile_as_c(void);
int lumis_headers_compile_as_c(void)
{
    lumis_envmap_desc d = {0};
    return d.width + (int)LUMIS_OK;
}
