/* fuzz_make_corpus DIR: writes the fuzzers' seed files into DIR/exr, DIR/hdr and DIR/pfm,
 * all made from a small procedural sky (16 x 8): EXR in several compressions, half and
 * float, scanline and tiled; Radiance HDR; PFM in both byte orders; PNG; and DIR/scene, JSON
 * scene files. */
#include "lumis/io.h"
#include "lumis/lumis.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

static int make_dir(const char *path)
{
    if (mkdir(path, 0777) == 0 || errno == EEXIST) return 0;
    fprintf(stderr, "fuzz_make_corpus: cannot create %s: %s\n", path, strerror(errno));
    return 1;
}

static int write_seed(const char *dir, const char *sub, const char *name, const lumis_image *image,
                      const lumis_write_options *options)
{
    char path[4096];
    int n = snprintf(path, sizeof path, "%s/%s/%s", dir, sub, name);
    if (n < 0 || (size_t)n >= sizeof path) {
        fprintf(stderr, "fuzz_make_corpus: path too long: %s/%s/%s\n", dir, sub, name);
        return 1;
    }
    lumis_status st = lumis_image_write(path, image, options);
    if (st != LUMIS_OK) {
        fprintf(stderr, "fuzz_make_corpus: %s: %s\n", path, lumis_status_string(st));
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: fuzz_make_corpus DIR\n");
        return 2;
    }
    const char *dir = argv[1];
    static const char *const subs[] = {"exr", "hdr", "pfm", "png", "scene"};
    char path[4096];
    if (make_dir(dir)) return 1;
    for (size_t i = 0; i < sizeof subs / sizeof subs[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, subs[i]);
        if (make_dir(path)) return 1;
    }

    lumis_sky_desc desc = {0};
    desc.width = 16;
    desc.sun_elevation_deg = 35.0f;
    lumis_image *sky = NULL;
    lumis_status st = lumis_sky_create(&desc, &sky);
    if (st != LUMIS_OK) {
        fprintf(stderr, "fuzz_make_corpus: lumis_sky_create: %s\n", lumis_status_string(st));
        return 1;
    }

    static const struct {
        const char *name;
        lumis_exr_compression compression;
        int half, tile;
    } exrs[] = {
        {"zip.exr", LUMIS_EXR_ZIP, 0, 0},         {"zip-half.exr", LUMIS_EXR_ZIP, 1, 0},
        {"piz.exr", LUMIS_EXR_PIZ, 0, 0},         {"rle.exr", LUMIS_EXR_RLE, 0, 0},
        {"none.exr", LUMIS_EXR_NONE, 0, 0},       {"dwaa.exr", LUMIS_EXR_DWAA, 1, 0},
        {"b44-half.exr", LUMIS_EXR_B44, 1, 0},    {"tiled-zip.exr", LUMIS_EXR_ZIP, 0, 8},
        {"tiled-half.exr", LUMIS_EXR_NONE, 1, 8},
    };
    int failed = 0;
    for (size_t i = 0; i < sizeof exrs / sizeof exrs[0]; i++) {
        lumis_write_options o = {0};
        o.format = LUMIS_FORMAT_EXR;
        o.exr_compression = exrs[i].compression;
        o.exr_half = exrs[i].half;
        o.exr_tile_size = exrs[i].tile;
        failed |= write_seed(dir, "exr", exrs[i].name, sky, &o);
    }

    lumis_write_options hdr = {0};
    hdr.format = LUMIS_FORMAT_HDR;
    failed |= write_seed(dir, "hdr", "sky.hdr", sky, &hdr);

    lumis_write_options pfm = {0};
    pfm.format = LUMIS_FORMAT_PFM;
    failed |= write_seed(dir, "pfm", "little.pfm", sky, &pfm);
    pfm.pfm_big_endian = 1;
    failed |= write_seed(dir, "pfm", "big.pfm", sky, &pfm);

    lumis_write_options png = {0};
    png.format = LUMIS_FORMAT_PNG;
    png.exposure_ev = -10.0f;
    failed |= write_seed(dir, "png", "sky.png", sky, &png);

    /* Scene files: the documented schema, every material, transforms and instances (mesh
     * objects are refused by the fuzz target, which must not open files, but their fields
     * are parsed before that). */
    static const char *const scenes[] = {
        "{\"camera\": {\"eye\": [0,1,5], \"look_at\": [0,0.5,0], \"up\": [0,1,0],\n"
        " \"fov_deg\": 40, \"width\": 640, \"height\": 480},\n"
        " \"environment\": {\"map\": \"forest.exr\", \"rotation_deg\": 0, \"scale\": 1},\n"
        " \"objects\": [{\"type\": \"sphere\", \"center\": [0,1,0], \"radius\": 1,\n"
        "   \"material\": {\"type\": \"lambert\", \"albedo\": [0.8,0.8,0.8]}},\n"
        "  {\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,1,0], \"size\": 20,\n"
        "   \"material\": {\"type\": \"ward\", \"diffuse\": [0.1,0.1,0.1], \"specular\": "
        "[0.3,0.3,0.3], \"alpha_x\": 0.1, \"alpha_y\": 0.2}}]}\n",
        "{\"environment\": {\"map\": \"sky:64x32\"}, \"objects\": [{\"type\": \"sphere\", "
        "\"center\": [1,2,3], \"radius\": 0.5, \"material\": {\"type\": \"conductor\", \"f0\": "
        "[0.9,0.6,0.5], \"alpha\": 0.2}}, {\"type\": \"sphere\", \"center\": [0,0,0], "
        "\"radius\": 2, \"material\": {\"type\": \"plastic\", \"diffuse\": [0.5,0.1,0.1], "
        "\"alpha\": 0.3}}]}\n",
        "{\"objects\": [{\"type\": \"mesh\", \"file\": \"bunny.obj\", \"instances\": "
        "[{\"translate\": [1,0,0], \"rotate_deg\": [0,30,0], \"scale\": 0.5}, {\"scale\": "
        "[1,2,3]}], \"material\": {\"type\": \"lambert\"}}]}\n",
        "{\"objects\": []}\n",
    };
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        snprintf(path, sizeof path, "%s/scene/seed%zu.json", dir, i);
        FILE *f = fopen(path, "wb");
        if (!f || fputs(scenes[i], f) < 0 || fclose(f) != 0) {
            fprintf(stderr, "fuzz_make_corpus: cannot write %s\n", path);
            failed = 1;
        }
    }

    lumis_image_destroy(sky);
    if (!failed) printf("fuzz_make_corpus: seeds written to %s/{exr,hdr,pfm,png,scene}\n", dir);
    return failed ? 1 : 0;
}
