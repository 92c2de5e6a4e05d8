/* fuzz_make_corpus DIR: writes the fuzzers' seed files into DIR/exr, DIR/hdr and DIR/pfm,
 * all made from a small procedural sky (16 x 8): EXR in several compressions, half and
 * float, scanline and tiled; Radiance HDR; PFM in both byte orders; PNG; DIR/scene, JSON
 * scene files; and DIR/luminaire, luminaire manifests (one written by lumis_luminaire_write
 * into DIR/luminaire-files/, outside the corpus, which libFuzzer reads recursively); DIR/ies
 * and DIR/ldt, photometric files of analytic distributions (tests/photometric_gen.c) in
 * every header year, type and symmetry form. */
#include "lumis/io.h"
#include "lumis/lumis.h"
#include "photometric_gen.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
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

static int write_text(const char *path, const char *text, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(text, 1, n, f) != n || fclose(f) != 0) {
        fprintf(stderr, "fuzz_make_corpus: cannot write %s\n", path);
        return 1;
    }
    return 0;
}

/* Luminaire manifests: the documented schema with both bases, the largest grid's names, and
 * one written by lumis_luminaire_write (its number formatting and escaping). */
static int write_luminaire_seeds(const char *dir)
{
    static const char *const manifests[] = {
        "{\n  \"format\": \"lumis-luminaire\",\n  \"version\": 1,\n  \"units\": \"mm\",\n"
        "  \"delta\": 100,\n  \"basis\": \"quadratic\",\n  \"grid\": [2, 2],\n"
        "  \"grid_origin\": [-5, -5],\n  \"grid_spacing\": [10, 10],\n"
        "  \"image\": {\"width\": 24, \"height\": 20, \"origin\": [-60, -50], \"size\": [120, "
        "100]},\n  \"images\": [\"lamp.images/a000_b000.exr\", \"lamp.images/a001_b000.exr\",\n"
        "    \"lamp.images/a000_b001.exr\", \"lamp.images/a001_b001.exr\"]\n}\n",
        "{\"format\":\"lumis-luminaire\",\"version\":1,\"units\":\"in\",\"delta\":0.25,"
        "\"basis\":\"bspline\",\"grid\":[3,1],\"grid_origin\":[-1e-3,0.5],\"grid_spacing\":"
        "[0.125,3.5e2],\"image\":{\"origin\":[-2,-2],\"size\":[4,4.5],\"width\":1,\"height\":"
        "7},\"images\":[\"a.pfm\",\"sub/dir/b.pfm\",\"./c d.pfm\"],\"comment\":\"ignored\"}",
    };
    char path[4096];
    int failed = 0;
    for (size_t i = 0; i < sizeof manifests / sizeof manifests[0]; i++) {
        snprintf(path, sizeof path, "%s/luminaire/seed%zu.json", dir, i);
        failed |= write_text(path, manifests[i], strlen(manifests[i]));
    }
    /* A written one: 4 x 3 black images of 2 x 2 pixels, odd numbers. */
    enum { W = 4, H = 3 };
    static const float black[2 * 2 * 3];
    const float *ptrs[W * H];
    for (int m = 0; m < W * H; m++) ptrs[m] = black;
    lumis_luminaire_desc d = {0};
    d.delta = 1.0 / 3.0;
    d.basis = LUMIS_BASIS_BSPLINE;
    d.grid[0] = W;
    d.grid[1] = H;
    d.grid_origin[0] = -0.1 - 0.2;
    d.grid_spacing[0] = d.grid_spacing[1] = 0.7;
    d.width = d.height = 2;
    d.image_origin[0] = d.image_origin[1] = -1e-7;
    d.image_size[0] = d.image_size[1] = 2.0 / 7.0;
    d.pixels = ptrs;
    lumis_luminaire *lum = NULL;
    lumis_status st = lumis_luminaire_create(&d, &lum);
    snprintf(path, sizeof path, "%s/luminaire-files/written.json", dir);
    lumis_luminaire_write_options wo = {0};
    wo.image_format = LUMIS_FORMAT_PFM;
    if (st == LUMIS_OK) st = lumis_luminaire_write(path, lum, &wo);
    lumis_luminaire_destroy(lum);
    if (st != LUMIS_OK) {
        fprintf(stderr, "fuzz_make_corpus: %s: %s\n", path, lumis_status_string(st));
        return 1;
    }
    FILE *f = fopen(path, "rb");
    char text[8192];
    size_t n = f ? fread(text, 1, sizeof text, f) : 0;
    if (f) fclose(f);
    snprintf(path, sizeof path, "%s/luminaire/written.json", dir);
    return failed | (n == 0) | write_text(path, text, n);
}

/* text's line ends as `eol` ("\n", "\r" or "\r\n"), after a UTF-8 byte-order mark if bom,
 * written to path: the forms real files come in (a lone BOM crashed the readers once). */
static int write_variant(const char *path, const char *text, size_t n, const char *eol, int bom)
{
    char *out = malloc(2 * n + 4);
    if (!out) return 1;
    size_t o = 0;
    if (bom) memcpy(out, "\xef\xbb\xbf", 3), o = 3;
    for (size_t k = 0; k < n; k++) {
        if (text[k] == '\r' && k + 1 < n && text[k + 1] == '\n') continue;
        if (text[k] == '\n' || text[k] == '\r') {
            memcpy(out + o, eol, strlen(eol));
            o += strlen(eol);
        } else {
            out[o++] = text[k];
        }
    }
    const int failed = write_text(path, out, o);
    free(out);
    return failed;
}

/* Each line-end form of text, with and without a BOM, as DIR/SUB/NAME-VARIANT.EXT. */
static int write_variants(const char *dir, const char *sub, const char *name, const char *text,
                          size_t n)
{
    static const char *const eols[] = {"\n", "\r", "\r\n"};
    static const char *const tags[] = {"lf", "cr", "crlf"};
    int failed = 0;
    char path[4200];
    for (int e = 0; e < 3; e++)
        for (int bom = 0; bom < 2; bom++) {
            snprintf(path, sizeof path, "%s/%s/%s-%s%s.%s", dir, sub, name, tags[e],
                     bom ? "-bom" : "", sub);
            failed |= write_variant(path, text, n, eols[e], bom);
        }
    snprintf(path, sizeof path, "%s/%s/%s-bom-only.%s", dir, sub, name, sub);
    failed |= write_text(path, "\xef\xbb\xbf", 3);
    return failed;
}

/* Photometric seeds: IES in every header year, types C, B and A, each horizontal form,
 * TILT=INCLUDE, every shape; EULUMDAT with every symmetry indicator; each line-end form
 * with and without a BOM, and a Latin-1 header.  The Makefile adds the real files of
 * tests/data/photometric/. */
static int write_photometric_seeds(const char *dir)
{
    static const char *const firsts[] = {NULL, "IESNA91", "IESNA:LM-63-1995", "IESNA:LM-63-2002",
                                         "IES:LM-63-2019"};
    static const double forms[][3] = {
        {0, 0, 1}, {0, 90, 4}, {0, 180, 5}, {90, 270, 5}, {0, 360, 9}};
    int failed = 0, k = 0;
    char path[4200];
    for (int y = 0; y < 5; y++)
        for (int h = 0; h < 5; h++) {
            pg_ies_spec s = {PG_QUAD,
                             0.5,
                             firsts[y],
                             1,
                             7,
                             0,
                             90,
                             (int)forms[h][2],
                             forms[h][0],
                             forms[h][1],
                             1,
                             (y + h) % 3 == 0,
                             h == 1 ? -0.3 : 0.5,
                             h == 1 ? -0.3 : 0.6,
                             0,
                             1 + y % 2};
            size_t n = 0;
            char *text = pg_ies(&s, &n);
            snprintf(path, sizeof path, "%s/ies/seed%d.ies", dir, k++);
            failed |= !text || write_text(path, text, n);
            free(text);
        }
    for (int type = 2; type <= 3; type++) {
        pg_ies_spec s = {PG_AIMED, 0, "IESNA:LM-63-2002",
                         type,     7, type == 2 ? -90 : 0,
                         90,       7, -90,
                         90,       1, 0,
                         0,        0, 0,
                         2};
        size_t n = 0;
        char *text = pg_ies(&s, &n);
        snprintf(path, sizeof path, "%s/ies/seed%d.ies", dir, k++);
        failed |= !text || write_text(path, text, n);
        free(text);
    }
    for (int isym = 0; isym <= 4; isym++) {
        size_t n = 0;
        char *text = pg_ldt(PG_QUAD, 0.5, isym, 8, 7, 1 + isym % 2, &n);
        snprintf(path, sizeof path, "%s/ldt/seed%d.ldt", dir, isym);
        failed |= !text || write_text(path, text, n);
        if (text && isym == 2) failed |= write_variants(dir, "ldt", "forms", text, n);
        free(text);
    }
    pg_ies_spec s = {PG_SPOT, 4, "IESNA:LM-63-1995", 1, 7, 0, 90, 1, 0, 0, 1, 0, -0.3, 0, 0, 2};
    size_t n = 0;
    char *text = pg_ies(&s, &n);
    failed |= !text || write_variants(dir, "ies", "forms", text, n);
    char *deg = text ? strstr(text, "[LAMP] none") : NULL;
    if (deg) {
        memcpy(deg, "[LAMP] 30\xb0 ", 11); /* a Latin-1 degree sign, as older files have */
        snprintf(path, sizeof path, "%s/ies/latin1.ies", dir);
        failed |= write_text(path, text, n);
    }
    free(text);
    return failed;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: fuzz_make_corpus DIR\n");
        return 2;
    }
    const char *dir = argv[1];
    static const char *const subs[] = {
        "exr", "hdr", "pfm", "png", "scene", "luminaire", "luminaire-files", "ies", "ldt"};
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

    failed |= write_luminaire_seeds(dir);
    failed |= write_photometric_seeds(dir);

    lumis_image_destroy(sky);
    if (!failed)
        printf("fuzz_make_corpus: seeds written to %s/{exr,hdr,pfm,png,scene,luminaire,ies,ldt}\n",
               dir);
    return failed ? 1 : 0;
}
