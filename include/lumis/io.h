/* lumis/io.h - reading and writing images (lumis-io library).
 *
 * Formats: OpenEXR (.exr: read RGB(A) or Y, half/float/uint, scanline or tiled, every
 * compression OpenEXR 3.1 knows, DWA included; write float or half), Radiance RGBE
 * (.hdr/.pic: read flat, old and new RLE; write new RLE), PFM (.pfm: read and write both
 * byte orders, colour and grey), PNG (.png: write only, 8-bit sRGB with exposure and a
 * tone map).
 *
 * Every reader checks sizes against a pixel limit before it allocates, detects truncated
 * data, and reports each failure with its own status and a message naming the file and
 * the reason.  Non-finite and negative values are replaced by 0 and counted.  Writers
 * write a temporary file in the destination folder and rename it on success, so a failed
 * or interrupted write never leaves a half-written output. */
#ifndef LUMIS_IO_H
#define LUMIS_IO_H

#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/luminaire.h"
#include "lumis/photometry.h"
#include "lumis/status.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lumis_file_format {
    LUMIS_FORMAT_AUTO = 0, /* from the extension (writing) or the content (reading) */
    LUMIS_FORMAT_EXR,
    LUMIS_FORMAT_HDR,
    LUMIS_FORMAT_PFM,
    LUMIS_FORMAT_PNG,
    LUMIS_FORMAT_COUNT
} lumis_file_format;

/* Format named by a path's extension (case-insensitive); LUMIS_FORMAT_AUTO if unknown. */
LUMIS_IO_API lumis_file_format lumis_format_from_path(const char *path);

/* Format recognised from the first bytes of a file; LUMIS_FORMAT_AUTO if none. */
LUMIS_IO_API lumis_file_format lumis_format_from_magic(const void *data, size_t size);

/* "exr", "hdr", "pfm", "png" ("auto" for LUMIS_FORMAT_AUTO). */
LUMIS_IO_API const char *lumis_format_name(lumis_file_format format);

typedef struct lumis_read_options {
    uint64_t max_pixels; /* 0 == LUMIS_DEFAULT_MAX_PIXELS */
    int threads;         /* EXR decoding threads; 0 == one per core, 1 == the caller's only */
    lumis_error_sink errors;
} lumis_read_options;

/* What a reader did besides producing pixels. */
typedef struct lumis_read_info {
    lumis_file_format format;
    lumis_replaced replaced; /* channel values replaced by 0 */
    int had_alpha;           /* the file had an alpha channel, which was dropped */
    int grey;                /* the file had one channel, copied to R, G and B */
} lumis_read_info;

/* Reads an image file; the format comes from the content, not the extension.
 * options and info may be NULL.  On failure *out is NULL. */
LUMIS_IO_API lumis_status lumis_image_read(const char *path, const lumis_read_options *options,
                                           lumis_image **out, lumis_read_info *info);

/* The default sky of the "sky" spec: the sun's elevation and azimuth in degrees. */
#define LUMIS_MAP_SKY_ELEVATION_DEG 35.0
#define LUMIS_MAP_SKY_AZIMUTH_DEG   60.0

/* Reads a map named by a spec: an image file (as lumis_image_read), or a procedural map
 * made by the core library: "sky" (lumis_sky_create with the sun at
 * LUMIS_MAP_SKY_ELEVATION_DEG / _AZIMUTH_DEG, the other parameters default), "studio"
 * (lumis_studio_create), either with ":WxH" (sizes in [1, 65536]; default 1024x512).
 * A procedural map reports format LUMIS_FORMAT_AUTO in info.  The tool's MAP arguments and
 * scene files' "map" go through it.  options and info may be NULL. */
LUMIS_IO_API lumis_status lumis_map_read(const char *spec, const lumis_read_options *options,
                                         lumis_image **out, lumis_read_info *info);

/* Reads an image held in memory (borrowed for the call).  name is used in messages only
 * (NULL == "<memory>").  format AUTO detects it from the content. */
LUMIS_IO_API lumis_status lumis_image_read_memory(const void *data, size_t size,
                                                  lumis_file_format format, const char *name,
                                                  const lumis_read_options *options,
                                                  lumis_image **out, lumis_read_info *info);

typedef enum lumis_tonemap {
    LUMIS_TONEMAP_CLAMP = 0, /* default: linear, clipped at 1 */
    LUMIS_TONEMAP_REINHARD,  /* x / (1 + x) per channel */
    LUMIS_TONEMAP_ACES,      /* Narkowicz's fit of the ACES filmic curve */
    LUMIS_TONEMAP_COUNT
} lumis_tonemap;

/* "clamp", "reinhard", "aces". */
LUMIS_IO_API const char *lumis_tonemap_name(lumis_tonemap tonemap);

/* Tone map by name; returns LUMIS_ERR_INVALID_ARGUMENT for an unknown name. */
LUMIS_IO_API lumis_status lumis_tonemap_from_name(const char *name, lumis_tonemap *out);

/* Display value in [0,1] (before the sRGB curve) of linear radiance x after exposure. */
LUMIS_IO_API float lumis_tonemap_apply(lumis_tonemap tonemap, float x);

/* EXR compression; 0 == ZIP (lossless, 16 scanlines per block). */
typedef enum lumis_exr_compression {
    LUMIS_EXR_ZIP = 0,
    LUMIS_EXR_NONE,
    LUMIS_EXR_RLE,
    LUMIS_EXR_ZIPS,
    LUMIS_EXR_PIZ,
    LUMIS_EXR_PXR24, /* lossy for float channels (24-bit) */
    LUMIS_EXR_B44,   /* lossy, half channels only (float stays uncompressed) */
    LUMIS_EXR_B44A,
    LUMIS_EXR_DWAA, /* lossy */
    LUMIS_EXR_DWAB, /* lossy */
    LUMIS_EXR_COMPRESSION_COUNT
} lumis_exr_compression;

/* "zip", "none", "rle", "zips", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab". */
LUMIS_IO_API const char *lumis_exr_compression_name(lumis_exr_compression compression);
LUMIS_IO_API lumis_status lumis_exr_compression_from_name(const char *name,
                                                          lumis_exr_compression *out);

typedef struct lumis_write_options {
    lumis_file_format format; /* AUTO == from the extension */
    int exr_half;             /* nonzero: EXR channels as half floats (default float) */
    lumis_exr_compression exr_compression; /* 0 == ZIP */
    int exr_tile_size;                     /* 0 == scanline file; > 0: tiled, tiles of this size */
    int pfm_big_endian;                    /* nonzero: big-endian PFM (default little-endian) */
    float exposure_ev;                     /* PNG: radiance is multiplied by 2^exposure_ev first */
    lumis_tonemap tonemap;                 /* PNG: tone map before the sRGB curve */
    lumis_error_sink errors;
} lumis_write_options;

/* Writes an image through a temporary file in the same folder, renamed on success.
 * options may be NULL (format from the extension, defaults otherwise).  A path that names
 * a device or a FIFO (/dev/null, /dev/stdout, a named pipe) is written in place, never
 * replaced; a symbolic link's target is replaced and the link kept; a directory is an
 * error. */
LUMIS_IO_API lumis_status lumis_image_write(const char *path, const lumis_image *image,
                                            const lumis_write_options *options);

/* Where a write to path lands: path with its chain of symbolic links followed by their text
 * (a dangling link's target is created, the link kept), as lumis_image_write and
 * lumis_write_text do, into buf.  A path naming a descriptor (/dev/stdout, /dev/fd/N) is
 * written in place and is its own target.  LUMIS_ERR_INVALID_ARGUMENT when it does not fit
 * in cap bytes. */
LUMIS_IO_API lumis_status lumis_output_target(const char *path, char *buf, size_t cap);

/* Writes len bytes of text (a JSON sidecar, a report) the same crash-safe way. */
LUMIS_IO_API lumis_status lumis_write_text(const char *path, const char *text, size_t len,
                                           const lumis_error_sink *errors);

/* Removes the temporary files of the writes in progress (a hidden ".NAME.XXXXXX" beside
 * each destination).  Async-signal-safe: a program's SIGINT / SIGTERM handler calls it so
 * that an interrupted write leaves the old output and nothing else.  The library installs
 * no handler itself. */
LUMIS_IO_API void lumis_io_remove_partial_outputs(void);

/* ---- light sets (lumis/lights.h) as files ------------------------------------------------- */

struct lumis_light_set;
struct lumis_sun;

/* The frame of the directions a light-set file holds.  lumis's own frame puts column u = 0
 * of an equirectangular map at +x (docs/coordinates.md); three.js and Blender show column
 * u = 1/2 there.  A file for them must put each light where they show its
 * source, so the default turns every direction half a turn about +y.  Formulas and the
 * consumers checked: docs/lights-export.md, "Frames". */
typedef enum lumis_export_frame {
    LUMIS_EXPORT_FRAME_ENGINE = 0, /* default: map pixel (u, v) is seen along
                                      (sin t cos p, cos t, sin t sin p), p = 2 pi (u - 1/2),
                                      t = pi v (v = 0 the top row), as three.js's equirectUv
                                      and Blender (through its glTF importer) show the map */
    LUMIS_EXPORT_FRAME_LUMIS,      /* lumis's own: p = 2 pi u (u = 0 along +x) */
    LUMIS_EXPORT_FRAME_COUNT
} lumis_export_frame;

/* "engine", "lumis"; "unknown" for anything else. */
LUMIS_IO_API const char *lumis_export_frame_name(lumis_export_frame frame);

/* Frame by name; LUMIS_ERR_INVALID_ARGUMENT (and *out untouched) for an unknown name. */
LUMIS_IO_API lumis_status lumis_export_frame_from_name(const char *name, lumis_export_frame *out);

/* A direction of lumis's frame (a light's dir, docs/coordinates.md) as a file in `frame`
 * holds it: (-x, y, -z) for LUMIS_EXPORT_FRAME_ENGINE, unchanged for LUMIS_EXPORT_FRAME_LUMIS
 * (and for an unknown frame). */
LUMIS_IO_API lumis_vec3 lumis_export_frame_dir(lumis_export_frame frame, lumis_vec3 dir);

/* How lumis_light_set_write_gltf stores the file. */
typedef enum lumis_gltf_container {
    LUMIS_GLTF_AUTO = 0, /* default: from the path, .gltf JSON text, .glb binary; any other
                            name is refused (LUMIS_ERR_UNKNOWN_FORMAT) */
    LUMIS_GLTF_TEXT,     /* .gltf: the JSON document */
    LUMIS_GLTF_BINARY,   /* .glb: the binary container (a 12-byte header, one JSON chunk) */
    LUMIS_GLTF_COUNT
} lumis_gltf_container;

typedef struct lumis_light_export_options {
    int set_index;      /* which interleaved set; 0 == the original */
    int masks;          /* JSON: nonzero adds each light's region as pixel runs */
    const char *source; /* JSON: the map's name, recorded (may be NULL) */
    const char *method; /* the method's name, recorded (may be NULL) */
    lumis_error_sink errors;
    const char *parameters; /* the method's parameters as given ("name=value,..."), recorded
                               when not NULL or empty (JSON; glTF: the scene's extras) */
    /* the directions' frame, recorded in the file (JSON "frame", glTF asset.extras.frame);
       0 == LUMIS_EXPORT_FRAME_ENGINE */
    lumis_export_frame frame;
    /* glTF only: text or binary; 0 == from the path's extension */
    lumis_gltf_container container;
    /* NULL, or a sun split off the map (lumis/sun.h, found): written first, as a
       directional light of kind "sun" with its angular radius (the disk's and the cone's),
       before the set's lights, which should then be the residual's */
    const struct lumis_sun *sun;
} lumis_light_export_options;

/* JSON: per light its direction (in options->frame), power (RGB, sum of L x solid angle), colour
 * and intensity (colour x intensity == power, colour's largest channel 1), solid angle, directional
 * extent, pixel count and kind; the regions as runs [row, first column, length] on
 * request.  With options->sun, the sun comes first in "lights" (kind "sun", its extent the
 * sampled cone, plus angular_radius_rad: the disk, and share) and "sun_index" is 0.
 * Crash-safe write.  options may be NULL. */
LUMIS_IO_API lumis_status lumis_light_set_write_json(const char *path,
                                                     const struct lumis_light_set *set,
                                                     const lumis_light_export_options *options);

/* glTF 2.0, as JSON text (.gltf) or a binary container (.glb; options->container): one
 * KHR_lights_punctual directional light per light (with options->sun, first a light named
 * "sun" whose node's extras hold angular_radius_rad, extent_rad and share), each on a node whose
 * rotation turns -Z (a glTF light's direction of travel) into -dir, dir in options->frame (default:
 * where three.js and Blender show the light's source on the same map).  Colour and intensity as in
 * the JSON: intensity is the power's largest channel, which for a map calibrated in cd/m^2 is
 * illuminance in lux (docs/lights-export.md).  A path that is neither .gltf nor .glb with no
 * container given: LUMIS_ERR_UNKNOWN_FORMAT.  Crash-safe write. */
LUMIS_IO_API lumis_status lumis_light_set_write_gltf(const char *path,
                                                     const struct lumis_light_set *set,
                                                     const lumis_light_export_options *options);

/* ---- light-field luminaires (lumis/luminaire.h) as files ---------------------------------
 *
 * A luminaire is a JSON manifest ("format": "lumis-luminaire", "version": 1: the geometry
 * of lumis_luminaire_desc, the units, and the M = W H image file names relative to the
 * manifest's folder) plus M RGB float images (EXR or PFM) of the irradiance C_m on S.
 * Schema, conventions and limits: docs/formats.md, "Luminaire files".  Image row 0 of a
 * file (its top row as an image viewer shows it) is the row of the largest y on S, so an
 * image looks like S seen with x to the right and y up. */

struct lumis_luminaire;

/* The manifest version this library reads and writes. */
#define LUMIS_LUMINAIRE_FORMAT_VERSION 1

typedef struct lumis_luminaire_read_options {
    size_t max_pixels;       /* total pixels over all images; 0 == LUMIS_DEFAULT_MAX_PIXELS */
    lumis_error_sink errors; /* errors, and warnings (reported with status LUMIS_OK) */
} lumis_luminaire_read_options;

/* A parsed manifest: everything but the pixels. */
typedef struct lumis_luminaire_manifest {
    int version;               /* LUMIS_LUMINAIRE_FORMAT_VERSION */
    char units[32];            /* "units", e.g. "mm": the unit of every length */
    lumis_luminaire_desc desc; /* the geometry; pixels NULL, errors zero */
    int image_count;           /* M = W H */
    const char *const *images; /* M names as written in "images" (relative paths) */
    const char *const *paths;  /* M paths to open: base_dir joined with each name */
    /* "pixels_digest": FNV-1a (64-bit) of the images' float values as the luminaire holds
     * them (docs/formats.md); a read whose images do not give it fails, so a half-rewritten
     * set never loads as a mixture.  has_pixels_digest 0: a manifest without one (older). */
    int has_pixels_digest;
    uint64_t pixels_digest;
} lumis_luminaire_manifest;

/* Parses a manifest held in memory (borrowed for the call) and checks every field, the
 * total pixel count against options->max_pixels and each image name (relative, no ".."
 * component); opens no file.  name is used in messages (NULL == "<memory>"); base_dir
 * (NULL or "" == none) is joined with each image name to give paths.  options may be
 * NULL.  On failure *out is NULL; free the result with lumis_luminaire_manifest_destroy. */
LUMIS_IO_API lumis_status lumis_luminaire_manifest_parse(
    const char *text, size_t size, const char *name, const char *base_dir,
    const lumis_luminaire_read_options *options, lumis_luminaire_manifest **out);

/* Reads and parses the manifest at path (images resolved against its folder); opens no
 * image.  For a caller that wants the units or the file names. */
LUMIS_IO_API lumis_status lumis_luminaire_manifest_read(const char *manifest_path,
                                                        const lumis_luminaire_read_options *options,
                                                        lumis_luminaire_manifest **out);

/* Frees a manifest; NULL is accepted. */
LUMIS_IO_API void lumis_luminaire_manifest_destroy(lumis_luminaire_manifest *manifest);

/* Reads a manifest and its images (each checked against the manifest's size, a missing,
 * truncated or corrupt one failing with the image reader's status) and builds the
 * luminaire (lumis_luminaire_create).  Every message names the manifest and the JSON
 * field, e.g. "lamp.json: image.width: expected an integer in 1..16384, got -3".  Peak
 * memory: about twice the images' pixels.  options may be NULL.  On failure *out is
 * NULL. */
LUMIS_IO_API lumis_status lumis_luminaire_read(const char *manifest_path,
                                               const lumis_luminaire_read_options *options,
                                               struct lumis_luminaire **out);

typedef struct lumis_luminaire_write_options {
    lumis_file_format image_format; /* LUMIS_FORMAT_EXR (float, ZIP) or _PFM; 0 == EXR */
    const char *units;              /* "units" recorded; NULL == "mm" */
    lumis_error_sink errors;
} lumis_luminaire_write_options;

/* Writes the manifest at manifest_path and the images, bit-exact, into a folder beside it
 * named <stem>.images/ (<stem>: the manifest's file name without its extension), created
 * if needed, as a<a>_b<b>.exr (or .pfm) for grid position (a, b).  Every file goes through
 * a temporary file and a rename, the manifest last.  On failure the images this call
 * created are removed again, and the folder if this call created it; replacing an existing
 * luminaire is atomic per file only (docs/formats.md).  options may be NULL. */
LUMIS_IO_API lumis_status lumis_luminaire_write(const char *manifest_path,
                                                const struct lumis_luminaire *lum,
                                                const lumis_luminaire_write_options *options);

/* ---- photometric files ---------------------------------------------------------------- */

/* IES LM-63 (1986, 1991, 1995, 2002 and 2019 headers, [MORE] lines, TILT=NONE and
 * TILT=INCLUDE, photometric types C, B and A, every horizontal symmetry) and EULUMDAT
 * (.ldt: symmetry indicators 0 to 4, several lamp sets, the luminous area), told apart by
 * their content.  Intensities in candela: IES's values times its candela multiplier and
 * ballast factor (and, before LM-63-2002, its ballast-lamp factor); EULUMDAT's cd/klm
 * times the first lamp set's flux / 1000 and its conversion factor.  Sizes in metres.
 * Every failure names the file, the line and the field (docs/photometric.md). */
typedef enum lumis_photometric_format {
    LUMIS_PHOTOMETRIC_IES = 1,
    LUMIS_PHOTOMETRIC_LDT = 2
} lumis_photometric_format;

typedef struct lumis_photometric_file {
    lumis_photometric *model;
    lumis_photometric_format format;
    char standard[64]; /* "IESNA:LM-63-2002", "LM-63-1986" (no version line), "EULUMDAT" */
    /* IES's keywords [MANUFAC], [LUMINAIRE], [LUMCAT], [LAMP], [TEST] ([MORE] lines
     * joined); EULUMDAT's company, luminaire name and number, first lamp type, report */
    char manufacturer[256], luminaire[256], catalog[256], lamp[256], test[256];
    int lamps;              /* IES: < 0 for absolute photometry; EULUMDAT: set 1's */
    double lumens_per_lamp; /* as the file says (IES: -1 for absolute photometry) */
    double input_watts;
    int lamp_sets; /* EULUMDAT's n (IES: 0) */
    /* TILT=INCLUDE: the table, read and checked; lumis_photometric_tilt_factor gives its
     * factor at a fixture's aim (scene files and --fixture apply it) */
    int tilt, tilt_geometry, ntilt;
    double *tilt_deg, *tilt_factor;
    /* Empty, or what a reader of the file should be told although it was read: the
     * table's flux more than LUMIS_PHOTOMETRIC_FLUX_TOLERANCE off the flux the file
     * declares (EULUMDAT: the first lamp set's flux x LOR). */
    char warning[512];
} lumis_photometric_file;

/* The share by which a table's flux may differ from its file's declared flux before the
 * reader warns (manufacturers' files of the test corpus agree to 0.1-2.4 %). */
#define LUMIS_PHOTOMETRIC_FLUX_TOLERANCE 0.03

LUMIS_IO_API lumis_status lumis_photometric_read(const char *path, const lumis_error_sink *errors,
                                                 lumis_photometric_file **out);

/* The factor a TILT=INCLUDE table gives a fixture aimed along `aim` (any length; world y
 * up): LM-63's multiplying factor at the fixture's tilt from the pose it was measured in,
 * linear between the table's angles and held beyond its ends.  Type C is measured hanging
 * (aim straight down): its tilt is the aim's angle from -y, 0 to 180 degrees; types A
 * and B are measured aimed level: their tilt is the aim's angle above or below the
 * horizon, 0 to 90.  1 for TILT=NONE, a NULL file or a zero aim. */
LUMIS_IO_API double lumis_photometric_tilt_factor(const lumis_photometric_file *f,
                                                  lumis_photometric_type type, lumis_vec3 aim);
LUMIS_IO_API lumis_status lumis_photometric_read_memory(const void *data, size_t size,
                                                        const char *name,
                                                        const lumis_error_sink *errors,
                                                        lumis_photometric_file **out);
LUMIS_IO_API void lumis_photometric_file_destroy(lumis_photometric_file *f);

#ifdef __cplusplus
}
#endif
#endif
