/* libFuzzer target: the JSON scene-file parser on arbitrary bytes.  Mesh files are refused
 * (the fuzzer must not open whatever path an input names), so this covers the JSON walk,
 * every field check, materials, transforms and instances.  The contract: a scene exactly
 * when the status is LUMIS_OK, with finite cameras and sane counts; never a crash, a
 * sanitizer report or a leak. */
#include "lumis/render.h"
#include "render/internal.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lumis_scene_file *f = NULL;
    lumis_status st = lumis__scene_file_parse((const char *)data, size, "fuzz.json",
                                              "/nonexistent/", 0, NULL, &f);
    if ((st == LUMIS_OK) != (f != NULL)) __builtin_trap();
    if (f) {
        if (f->object_count < 0 || (f->object_count > 0 && !f->objects)) __builtin_trap();
        if (!(f->camera.fov_deg > 0.0f && f->camera.fov_deg < 180.0f)) __builtin_trap();
        if (f->camera.width < 1 || f->camera.height < 1) __builtin_trap();
        for (int k = 0; k < f->object_count; k++)
            if (f->objects[k].type == LUMIS_OBJECT_MESH) __builtin_trap(); /* files refused */
    }
    lumis_scene_file_destroy(f);
    return 0;
}
