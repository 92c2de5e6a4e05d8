/* libFuzzer target: the photometric readers (lumis_photometric_read_memory) on arbitrary
 * bytes, one binary per corpus: fuzz_ies (IES LM-63 seeds) and fuzz_ldt (EULUMDAT seeds);
 * the content picks the reader either way.  The contract: a file exactly when the status is
 * LUMIS_OK; then its model's flux, beam angles and intensities are finite and >= 0, and
 * every tilt factor is >= 0; never a crash, a sanitizer report or a leak. */
#include "lumis/io.h"
#include "lumis/photometry.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lumis_photometric_file *f = NULL;
    const lumis_status st = lumis_photometric_read_memory(data, size, "fuzz", NULL, &f);
    if ((st == LUMIS_OK) != (f != NULL)) __builtin_trap();
    if (!f) return 0;
    if (!f->model) __builtin_trap();
    for (int k = 0; k < f->ntilt; k++)
        if (!(f->tilt_factor[k] >= 0)) __builtin_trap();
    lumis_photometric_info in;
    if (lumis_photometric_get_info(f->model, &in) != LUMIS_OK) __builtin_trap();
    /* the tables are small enough here for the info's scans (a huge one would only be slow) */
    if (!(in.flux >= 0) || !isfinite(in.flux) || !(in.max_candela >= 0)) __builtin_trap();
    for (int p = 0; p < 2; p++)
        if (!(in.beam_deg[p] >= 0 && in.beam_deg[p] <= 360.0001) || !(in.field_deg[p] >= 0))
            __builtin_trap();
    static const lumis_vec3 dirs[] = {{0, 0, -1}, {0, 0, 1}, {1, 0, 0}, {0.6f, 0.48f, -0.64f}};
    for (size_t k = 0; k < sizeof dirs / sizeof dirs[0]; k++) {
        const double i = lumis_photometric_intensity(f->model, dirs[k]);
        if (!(i >= 0) || !isfinite(i)) __builtin_trap();
    }
    lumis_photometric_file_destroy(f);
    return 0;
}
