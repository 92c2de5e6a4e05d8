/* libFuzzer target: one image reader on arbitrary bytes.  Built once per format, with
 * LUMIS_FUZZ_FORMAT set to LUMIS_FORMAT_EXR, _HDR, _PFM or _PNG.  A reader
 * may reject the input with any status; what must never happen is a crash, a sanitizer
 * report, a leak or an allocation past the pixel limit. */
#include "lumis/io.h"

#include <stddef.h>
#include <stdint.h>

#ifndef LUMIS_FUZZ_FORMAT
#error                                                                                             \
    "define LUMIS_FUZZ_FORMAT (LUMIS_FORMAT_EXR, LUMIS_FORMAT_HDR, LUMIS_FORMAT_PFM or LUMIS_FORMAT_PNG)"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lumis_read_options opts = {0};
    opts.max_pixels = 1 << 22; /* 4 Mpixels, 48 MiB as float RGB: keeps RSS bounded */
    lumis_image *img = NULL;
    lumis_read_info info;
    lumis_status st =
        lumis_image_read_memory(data, size, LUMIS_FUZZ_FORMAT, "fuzz", &opts, &img, &info);
    /* The contract: an image exactly when the status is LUMIS_OK. */
    if ((st == LUMIS_OK) != (img != NULL)) __builtin_trap();
    if (img && (img->width < 1 || img->height < 1 ||
                (uint64_t)img->width * (uint64_t)img->height > opts.max_pixels))
        __builtin_trap();
    lumis_image_destroy(img);
    return 0;
}
