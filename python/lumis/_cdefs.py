"""The C declarations the package calls, copied from include/lumis/*.h (cffi's ABI mode
reads them at import: no compiler needed).  Struct layouts must match the headers field for
field; tests/python/test_layout.py checks every size and offset against the C compiler's."""

CDEFS = r"""
typedef enum lumis_status {
    LUMIS_OK, LUMIS_ERR_INVALID_ARGUMENT, LUMIS_ERR_OUT_OF_MEMORY, LUMIS_ERR_OPEN,
    LUMIS_ERR_READ, LUMIS_ERR_WRITE, LUMIS_ERR_EMPTY_FILE, LUMIS_ERR_UNKNOWN_FORMAT,
    LUMIS_ERR_BAD_MAGIC, LUMIS_ERR_BAD_HEADER, LUMIS_ERR_BAD_DIMENSIONS, LUMIS_ERR_TOO_LARGE,
    LUMIS_ERR_TRUNCATED, LUMIS_ERR_CORRUPT, LUMIS_ERR_UNSUPPORTED, LUMIS_ERR_MISSING_CHANNELS,
    LUMIS_STATUS_COUNT
} lumis_status;
const char *lumis_status_name(lumis_status status);
const char *lumis_status_string(lumis_status status);
typedef void (*lumis_error_fn)(void *user, lumis_status status, const char *message);
typedef struct lumis_error_sink { lumis_error_fn fn; void *user; } lumis_error_sink;

const char *lumis_version(void);
const char *lumis_simd_variant(void);

typedef struct lumis_vec3 { float x, y, z; } lumis_vec3;
typedef struct lumis_rgb { float r, g, b; } lumis_rgb;

/* image.h */
typedef struct lumis_image { int width, height; float *pixels; } lumis_image;
typedef struct lumis_replaced {
    uint64_t nan, inf, negative;
    float negative_min;
    double negative_sum;
    uint64_t negative_min_at;
} lumis_replaced;
lumis_status lumis_image_create(int width, int height, lumis_image **out);
void lumis_image_destroy(lumis_image *image);

/* envmap.h */
typedef struct lumis_envmap lumis_envmap;
typedef struct lumis_envmap_desc {
    const float *pixels;
    int width, height;
    float rotation_deg;
    float scale;
    uint64_t max_pixels;
    lumis_error_sink errors;
} lumis_envmap_desc;
lumis_status lumis_envmap_create(const lumis_envmap_desc *desc, lumis_envmap **out);
void lumis_envmap_destroy(lumis_envmap *env);
int lumis_envmap_width(const lumis_envmap *env);
int lumis_envmap_height(const lumis_envmap *env);
float lumis_envmap_scale(const lumis_envmap *env);
float lumis_envmap_rotation_deg(const lumis_envmap *env);
const float *lumis_envmap_pixels(const lumis_envmap *env);
lumis_replaced lumis_envmap_replaced(const lumis_envmap *env);
typedef struct lumis_envmap_stats {
    int width, height;
    double min_luminance, max_luminance;
    double min_positive_luminance;
    double avg_luminance;
    double dynamic_range;
    double power;
    double power_rgb[3];
    double top1_share;
    double top01_share;
    uint64_t black_pixels;
} lumis_envmap_stats;
lumis_status lumis_envmap_stats_compute(const lumis_envmap *env, lumis_envmap_stats *out);

/* sampler.h */
typedef enum lumis_sampler_method {
    LUMIS_METHOD_DEFAULT = 0, LUMIS_METHOD_INVERSION, LUMIS_METHOD_INVERSION_GUIDED,
    LUMIS_METHOD_ALIAS, LUMIS_METHOD_KDTREE, LUMIS_METHOD_KDTREE_EXACT,
    LUMIS_METHOD_HIERARCHICAL, LUMIS_METHOD_UNIFORM, LUMIS_METHOD_COUNT
} lumis_sampler_method;
const char *lumis_sampler_method_name(lumis_sampler_method method);
lumis_status lumis_sampler_method_from_name(const char *name, lumis_sampler_method *out);
typedef enum lumis_importance {
    LUMIS_IMPORTANCE_DEFAULT = 0, LUMIS_IMPORTANCE_LUMINANCE, LUMIS_IMPORTANCE_AVERAGE,
    LUMIS_IMPORTANCE_MAX_CHANNEL, LUMIS_IMPORTANCE_COUNT
} lumis_importance;
typedef struct lumis_sampler_desc {
    lumis_sampler_method method;
    lumis_importance importance;
    int compensate;
    int kdtree_blocks;
    int kdtree_uniform_angles;
    lumis_error_sink errors;
} lumis_sampler_desc;
typedef struct lumis_sampler lumis_sampler;
typedef struct lumis_env_sample { lumis_vec3 dir; float pdf; lumis_rgb radiance; } lumis_env_sample;
lumis_status lumis_sampler_create(const lumis_envmap *env, const lumis_sampler_desc *desc,
                                  lumis_sampler **out);
void lumis_sampler_destroy(lumis_sampler *sampler);
void lumis_sampler_sample_n(const lumis_sampler *sampler, const double *u, size_t n,
                            lumis_env_sample *out);
void lumis_sampler_pdf_n(const lumis_sampler *sampler, const lumis_vec3 *dirs, size_t n,
                         float *pdf, lumis_rgb *radiance);
lumis_status lumis_sampler_invert_n(const lumis_sampler *sampler, const lumis_vec3 *dirs,
                                    size_t n, double *u, size_t *failed);
size_t lumis_sampler_table_bytes(const lumis_sampler *sampler);
size_t lumis_sampler_total_bytes(const lumis_sampler *sampler);
double lumis_sampler_build_ms(const lumis_sampler *sampler);
lumis_sampler_method lumis_sampler_get_method(const lumis_sampler *sampler);
int lumis_sampler_is_uniform_fallback(const lumis_sampler *sampler);
double lumis_sampler_kdtree_alpha(const lumis_sampler *sampler);
int lumis_sampler_kdtree_blocks(const lumis_sampler *sampler);

/* lights.h */
typedef enum lumis_light_kind {
    LUMIS_LIGHT_REGION = 0, LUMIS_LIGHT_ENV_DIRECT = 1, LUMIS_LIGHT_ENV_INDIRECT = 2
} lumis_light_kind;
typedef struct lumis_light {
    lumis_vec3 dir;
    float extent;
    double power[3];
    double solid_angle;
    int pixels;
    lumis_light_kind kind;
} lumis_light;
typedef struct lumis_light_set lumis_light_set;
typedef enum lumis_lights_method {
    LUMIS_LIGHTS_MEDIAN_CUT = 1, LUMIS_LIGHTS_VARIANCE_MIN = 2, LUMIS_LIGHTS_DECOMPOSITION = 3,
    LUMIS_LIGHTS_FHIS = 4, LUMIS_LIGHTS_TMMS = 5
} lumis_lights_method;
typedef enum lumis_decomp_variant {
    LUMIS_DECOMP_DEFAULT = 0, LUMIS_DECOMP_IS_ONLY, LUMIS_DECOMP_IS_MASK,
    LUMIS_DECOMP_IS_KMEANS, LUMIS_DECOMP_FULL, LUMIS_DECOMP_VARIANT_COUNT
} lumis_decomp_variant;
typedef enum lumis_cut_objective {
    LUMIS_CUT_DEFAULT = 0, LUMIS_CUT_MODIFIED, LUMIS_CUT_ORIGINAL, LUMIS_CUT_COUNT
} lumis_cut_objective;
typedef enum lumis_mask_radius {
    LUMIS_MASK_DEFAULT = 0, LUMIS_MASK_CAP_SOLID_ANGLE, LUMIS_MASK_RADIANS, LUMIS_MASK_COUNT
} lumis_mask_radius;
typedef struct lumis_decomp_desc {
    int count;
    int sets;
    float jitter;
    uint64_t seed;
    lumis_decomp_variant variant;
    float percentile;
    float lambda;
    float gamma;
    float threshold;
    float budget_a;
    float budget_b;
    float min_share;
    float mask_scale;
    lumis_mask_radius mask_radius;
    float return_factor;
    int kmeans_max_iterations;
    lumis_cut_objective cut;
    float w_v, w_d, w_e;
    lumis_error_sink errors;
} lumis_decomp_desc;
void lumis_light_set_destroy(lumis_light_set *set);
int lumis_light_set_sets(const lumis_light_set *set);
lumis_status lumis_light_set_get(const lumis_light_set *set, int index, const lumis_light **lights,
                                 int *count);
const int32_t *lumis_light_set_labels(const lumis_light_set *set, int *width, int *height);
typedef struct lumis_light_set_info {
    lumis_lights_method method;
    int requested;
    int count;
    int direct;
    int indirect;
    double build_ms;
    double power[3];
    double threshold;
    double percentile_luminance;
    double avg_luminance;
    double max_luminance;
    int emissive_pixels;
    int returned_pixels;
    double gamma_em, gamma_nem;
    int budget;
    double mask_radius;
    int seeds;
    int kmeans_iterations;
    int kmeans_converged;
    const double *kmeans_objective;
    int kmeans_objective_count;
} lumis_light_set_info;
const lumis_light_set_info *lumis_light_set_get_info(const lumis_light_set *set);
lumis_status lumis_light_set_irradiance(const lumis_envmap *env, const lumis_light_set *set,
                                        lumis_vec3 normal, double *set_e, double *map_e);
typedef struct lumis_light_fold {
    int folded;
    int kept;
    double power[3];
    double share;
} lumis_light_fold;
lumis_status lumis_light_set_fold_below(lumis_light_set *set, lumis_vec3 up,
                                        const lumis_error_sink *errors, lumis_light_fold *report);
const char *const *lumis_lights_method_names(void);
lumis_status lumis_lights_method_from_name(const char *name, lumis_lights_method *out);
typedef struct lumis_light_params {
    lumis_decomp_desc wu;
    float jitter;
    uint64_t seed;
    float key, bandwidth;
    unsigned given;
} lumis_light_params;
lumis_status lumis_light_params_parse(lumis_light_params *p, const char *text,
                                      const lumis_error_sink *errors);
lumis_status lumis_light_params_check(const lumis_light_params *p, const char *method,
                                      const lumis_error_sink *errors);
void lumis_light_params_format(const lumis_light_params *p, char *buf, size_t cap);
lumis_status lumis_lights_by_name(const lumis_envmap *env, const char *method, int count, int sets,
                                  const lumis_light_params *params, const lumis_error_sink *errors,
                                  lumis_light_set **out);

/* rng.h */
typedef struct lumis_pcg32 { uint64_t state; uint64_t inc; } lumis_pcg32;
void lumis_pcg32_seed(lumis_pcg32 *rng, uint64_t seed, uint64_t stream);
void lumis_pcg32_fill_doubles(lumis_pcg32 *rng, double *out, size_t n);
double lumis_radical_inverse(unsigned dimension, uint64_t index);
void lumis_sobol02(uint32_t index, uint64_t seed, double u[2]);
lumis_status lumis_pmj02_generate(uint32_t n, uint64_t seed, uint32_t *xy);

/* metrics.h */
typedef enum lumis_flip_tonemapper {
    LUMIS_FLIP_TONEMAP_DEFAULT = 0, LUMIS_FLIP_TONEMAP_ACES, LUMIS_FLIP_TONEMAP_REINHARD,
    LUMIS_FLIP_TONEMAP_HABLE
} lumis_flip_tonemapper;
typedef struct lumis_flip_options {
    double pixels_per_degree;
    int start_exposure_given;
    double start_exposure;
    int stop_exposure_given;
    double stop_exposure;
    int num_exposures;
    lumis_flip_tonemapper tonemapper;
    lumis_error_sink errors;
} lumis_flip_options;
typedef struct lumis_flip_hdr_result {
    double mean;
    double start_exposure;
    double stop_exposure;
    int num_exposures;
} lumis_flip_hdr_result;
lumis_status lumis_flip_ldr(const lumis_image *reference, const lumis_image *test,
                            const lumis_flip_options *options, float *error_map, double *mean);
lumis_status lumis_flip_hdr(const lumis_image *reference, const lumis_image *test,
                            const lumis_flip_options *options, float *error_map,
                            float *exposure_map, lumis_flip_hdr_result *result);
typedef struct lumis_metric_options {
    float exposure_ev;
    double relmse_epsilon;
    lumis_error_sink errors;
} lumis_metric_options;
typedef struct lumis_image_error_stats {
    double mse, rmse, relmse, relmse_epsilon, psnr, psnr_peak;
} lumis_image_error_stats;
lumis_status lumis_image_errors(const lumis_image *reference, const lumis_image *test,
                                const lumis_metric_options *options, lumis_image_error_stats *out);
lumis_status lumis_lab_delta_e(const lumis_image *reference, const lumis_image *test,
                               const lumis_metric_options *options, float *map, double *mean);

/* photometry.h */
typedef enum lumis_photometric_type {
    LUMIS_PHOTOMETRIC_C = 1, LUMIS_PHOTOMETRIC_B = 2, LUMIS_PHOTOMETRIC_A = 3
} lumis_photometric_type;
typedef enum lumis_photometric_symmetry {
    LUMIS_SYMMETRY_NONE = 0, LUMIS_SYMMETRY_ROTATIONAL, LUMIS_SYMMETRY_C0_C180,
    LUMIS_SYMMETRY_C90_C270, LUMIS_SYMMETRY_QUADRANT, LUMIS_SYMMETRY_LATERAL
} lumis_photometric_symmetry;
typedef enum lumis_photometric_shape {
    LUMIS_SHAPE_POINT = 0, LUMIS_SHAPE_RECTANGLE, LUMIS_SHAPE_BOX, LUMIS_SHAPE_DISK,
    LUMIS_SHAPE_CYLINDER, LUMIS_SHAPE_SPHERE, LUMIS_SHAPE_OTHER
} lumis_photometric_shape;
typedef struct lumis_photometric lumis_photometric;
void lumis_photometric_destroy(lumis_photometric *p);
double lumis_photometric_intensity(const lumis_photometric *p, lumis_vec3 d);
double lumis_photometric_intensity_at(const lumis_photometric *p, double h_deg, double v_deg);
lumis_vec3 lumis_photometric_direction(lumis_photometric_type type, double h_deg, double v_deg);
lumis_status lumis_photometric_sample(const lumis_photometric *p, double u0, double u1,
                                      lumis_vec3 *d, double *pdf);
double lumis_photometric_pdf(const lumis_photometric *p, lumis_vec3 d);
double lumis_photometric_flux(const lumis_photometric *p);
lumis_status lumis_photometric_intensity_n(const lumis_photometric *p, const lumis_vec3 *dirs,
                                           size_t n, double *out);
lumis_status lumis_photometric_intensity_at_n(const lumis_photometric *p, const double *h_deg,
                                              size_t nh, const double *v_deg, size_t nv,
                                              double *out);
lumis_status lumis_photometric_pdf_n(const lumis_photometric *p, const lumis_vec3 *dirs, size_t n,
                                     double *out);
lumis_status lumis_photometric_sample_n(const lumis_photometric *p, const double *u, size_t n,
                                        lumis_vec3 *dirs, double *pdf);
typedef struct lumis_photometric_info {
    lumis_photometric_type type;
    lumis_photometric_symmetry symmetry;
    lumis_photometric_shape shape;
    double width, length, height;
    int nv, nh;
    double v_first, v_last, h_first, h_last;
    double flux;
    double lamp_lumens;
    double luminaire_lumens;
    double max_candela;
    double max_h, max_v;
    double beam_deg[2], field_deg[2];
    double downward_fraction;
} lumis_photometric_info;
lumis_status lumis_photometric_get_info(const lumis_photometric *p, lumis_photometric_info *info);
const char *lumis_photometric_type_name(lumis_photometric_type t);
const char *lumis_photometric_symmetry_name(lumis_photometric_symmetry s);
const char *lumis_photometric_shape_name(lumis_photometric_shape s);
"""

IO_CDEFS = r"""
typedef enum lumis_file_format {
    LUMIS_FORMAT_AUTO = 0, LUMIS_FORMAT_EXR, LUMIS_FORMAT_HDR, LUMIS_FORMAT_PFM,
    LUMIS_FORMAT_PNG, LUMIS_FORMAT_COUNT
} lumis_file_format;
const char *lumis_format_name(lumis_file_format format);
typedef struct lumis_read_options {
    uint64_t max_pixels;
    int threads;
    lumis_error_sink errors;
} lumis_read_options;
typedef struct lumis_read_info {
    lumis_file_format format;
    lumis_replaced replaced;
    int had_alpha;
    int grey;
} lumis_read_info;
lumis_status lumis_image_read(const char *path, const lumis_read_options *options,
                              lumis_image **out, lumis_read_info *info);
lumis_status lumis_map_read(const char *spec, const lumis_read_options *options, lumis_image **out,
                            lumis_read_info *info);
typedef enum lumis_tonemap {
    LUMIS_TONEMAP_CLAMP = 0, LUMIS_TONEMAP_REINHARD, LUMIS_TONEMAP_ACES, LUMIS_TONEMAP_COUNT
} lumis_tonemap;
lumis_status lumis_tonemap_from_name(const char *name, lumis_tonemap *out);
typedef enum lumis_exr_compression {
    LUMIS_EXR_ZIP = 0, LUMIS_EXR_NONE, LUMIS_EXR_RLE, LUMIS_EXR_ZIPS, LUMIS_EXR_PIZ,
    LUMIS_EXR_PXR24, LUMIS_EXR_B44, LUMIS_EXR_B44A, LUMIS_EXR_DWAA, LUMIS_EXR_DWAB,
    LUMIS_EXR_COMPRESSION_COUNT
} lumis_exr_compression;
lumis_status lumis_exr_compression_from_name(const char *name, lumis_exr_compression *out);
typedef struct lumis_write_options {
    lumis_file_format format;
    int exr_half;
    lumis_exr_compression exr_compression;
    int exr_tile_size;
    int pfm_big_endian;
    float exposure_ev;
    lumis_tonemap tonemap;
    lumis_error_sink errors;
} lumis_write_options;
lumis_status lumis_image_write(const char *path, const lumis_image *image,
                               const lumis_write_options *options);
typedef enum lumis_export_frame {
    LUMIS_EXPORT_FRAME_ENGINE = 0, LUMIS_EXPORT_FRAME_LUMIS, LUMIS_EXPORT_FRAME_COUNT
} lumis_export_frame;
lumis_status lumis_export_frame_from_name(const char *name, lumis_export_frame *out);
typedef enum lumis_gltf_container {
    LUMIS_GLTF_AUTO = 0, LUMIS_GLTF_TEXT, LUMIS_GLTF_BINARY, LUMIS_GLTF_COUNT
} lumis_gltf_container;
typedef struct lumis_light_export_options {
    int set_index;
    int masks;
    const char *source;
    const char *method;
    lumis_error_sink errors;
    const char *parameters;
    lumis_export_frame frame;
    lumis_gltf_container container;
    const struct lumis_sun *sun;
} lumis_light_export_options;
lumis_status lumis_light_set_write_json(const char *path, const struct lumis_light_set *set,
                                        const lumis_light_export_options *options);
lumis_status lumis_light_set_write_gltf(const char *path, const struct lumis_light_set *set,
                                        const lumis_light_export_options *options);
typedef enum lumis_photometric_format {
    LUMIS_PHOTOMETRIC_IES = 1, LUMIS_PHOTOMETRIC_LDT = 2
} lumis_photometric_format;
typedef struct lumis_photometric_file {
    lumis_photometric *model;
    lumis_photometric_format format;
    char standard[64];
    char manufacturer[256], luminaire[256], catalog[256], lamp[256], test[256];
    int lamps;
    double lumens_per_lamp;
    double input_watts;
    int lamp_sets;
    int tilt, tilt_geometry, ntilt;
    double *tilt_deg, *tilt_factor;
    char warning[512];
} lumis_photometric_file;
lumis_status lumis_photometric_read(const char *path, const lumis_error_sink *errors,
                                    lumis_photometric_file **out);
void lumis_photometric_file_destroy(lumis_photometric_file *f);
"""

# Every struct the package lays out itself, for the layout test (name -> fields checked).
STRUCTS = {
    "lumis_error_sink": ["fn", "user"],
    "lumis_image": ["width", "height", "pixels"],
    "lumis_replaced": ["nan", "inf", "negative", "negative_min", "negative_sum",
                       "negative_min_at"],
    "lumis_envmap_desc": ["pixels", "width", "height", "rotation_deg", "scale", "max_pixels",
                          "errors"],
    "lumis_envmap_stats": ["width", "height", "min_luminance", "max_luminance",
                           "min_positive_luminance", "avg_luminance", "dynamic_range", "power",
                           "power_rgb", "top1_share", "top01_share", "black_pixels"],
    "lumis_sampler_desc": ["method", "importance", "compensate", "kdtree_blocks",
                           "kdtree_uniform_angles", "errors"],
    "lumis_env_sample": ["dir", "pdf", "radiance"],
    "lumis_light": ["dir", "extent", "power", "solid_angle", "pixels", "kind"],
    "lumis_decomp_desc": ["count", "sets", "jitter", "seed", "variant", "percentile", "lambda",
                          "gamma", "threshold", "budget_a", "budget_b", "min_share",
                          "mask_scale", "mask_radius", "return_factor",
                          "kmeans_max_iterations", "cut", "w_v", "w_d", "w_e", "errors"],
    "lumis_light_set_info": ["method", "requested", "count", "direct", "indirect", "build_ms",
                             "power", "threshold", "percentile_luminance", "avg_luminance",
                             "max_luminance", "emissive_pixels", "returned_pixels", "gamma_em",
                             "gamma_nem", "budget", "mask_radius", "seeds",
                             "kmeans_iterations", "kmeans_converged", "kmeans_objective",
                             "kmeans_objective_count"],
    "lumis_light_fold": ["folded", "kept", "power", "share"],
    "lumis_light_params": ["wu", "jitter", "seed", "key", "bandwidth", "given"],
    "lumis_pcg32": ["state", "inc"],
    "lumis_flip_options": ["pixels_per_degree", "start_exposure_given", "start_exposure",
                           "stop_exposure_given", "stop_exposure", "num_exposures",
                           "tonemapper", "errors"],
    "lumis_flip_hdr_result": ["mean", "start_exposure", "stop_exposure", "num_exposures"],
    "lumis_metric_options": ["exposure_ev", "relmse_epsilon", "errors"],
    "lumis_image_error_stats": ["mse", "rmse", "relmse", "relmse_epsilon", "psnr", "psnr_peak"],
    "lumis_photometric_info": ["type", "symmetry", "shape", "width", "length", "height", "nv",
                               "nh", "v_first", "v_last", "h_first", "h_last", "flux",
                               "lamp_lumens", "luminaire_lumens", "max_candela", "max_h",
                               "max_v", "beam_deg", "field_deg", "downward_fraction"],
    "lumis_read_options": ["max_pixels", "threads", "errors"],
    "lumis_read_info": ["format", "replaced", "had_alpha", "grey"],
    "lumis_write_options": ["format", "exr_half", "exr_compression", "exr_tile_size",
                            "pfm_big_endian", "exposure_ev", "tonemap", "errors"],
    "lumis_light_export_options": ["set_index", "masks", "source", "method", "errors",
                                   "parameters", "frame", "container", "sun"],
    "lumis_photometric_file": ["model", "format", "standard", "manufacturer", "luminaire",
                               "catalog", "lamp", "test", "lamps", "lumens_per_lamp",
                               "input_watts", "lamp_sets", "tilt", "tilt_geometry", "ntilt",
                               "tilt_deg", "tilt_factor", "warning"],
}

# lumis/render.h (liblumis-render.so): the scene, the one lighting value and the session.
# Enums are declared as int (their size); structs the package never reads are opaque.
RENDER_CDEFS = r"""
typedef int lumis_sequence;
lumis_status lumis_sequence_from_name(const char *name, lumis_sequence *out);
typedef struct lumis_sequence_desc {
    lumis_sequence sequence;
    unsigned long long seed;
    int planned_spp;
    int width;
    int x, y;
    int dimension;
    int per_sample;
    lumis_error_sink errors;
} lumis_sequence_desc;
lumis_status lumis_sequence_fill(const lumis_sequence_desc *desc, int first_sample, int samples,
                                 double *out);
typedef int lumis_estimator;
typedef int lumis_lights_mode;
typedef int lumis_lighting_kind;
typedef struct lumis_camera {
    lumis_vec3 eye, look_at, up;
    float fov_deg;
    int width, height;
} lumis_camera;
typedef struct lumis_object lumis_object;
typedef struct lumis_scene lumis_scene;
typedef struct lumis_luminaire lumis_luminaire;
typedef struct lumis_rigid {
    double r[9];
    double t[3];
} lumis_rigid;
typedef struct lumis_luminaire_instance {
    const lumis_luminaire *luminaire;
    lumis_rigid placement;
    double scale;
    float intensity;
} lumis_luminaire_instance;
typedef struct lumis_photometric_instance {
    const lumis_photometric *photometric;
    lumis_rigid placement;
    double multiplier;
    int area;
    const lumis_luminaire *light_field;
    const void *light_field_report;
} lumis_photometric_instance;
typedef struct lumis_region_sampler lumis_region_sampler;
typedef int lumis_luminaire_preset;
lumis_status lumis_luminaire_preset_from_name(const char *name, lumis_luminaire_preset *out);
lumis_status lumis_luminaire_preset_create(lumis_luminaire_preset preset, int basis,
                                           const lumis_error_sink *errors, lumis_luminaire **out);
void lumis_luminaire_destroy(lumis_luminaire *lum);
typedef struct lumis_luminaire_read_options {
    size_t max_pixels;
    lumis_error_sink errors;
} lumis_luminaire_read_options;
lumis_status lumis_luminaire_read(const char *manifest_path,
                                  const lumis_luminaire_read_options *options,
                                  lumis_luminaire **out);
double lumis_photometric_tilt_factor(const lumis_photometric_file *f, lumis_photometric_type type,
                                     lumis_vec3 aim);
lumis_status lumis_scene_create(const lumis_object *objects, int count,
                                const lumis_error_sink *errors, lumis_scene **out);
void lumis_scene_destroy(lumis_scene *scene);
typedef struct lumis_luminaire_lighting {
    const lumis_luminaire_instance *instances;
    int count;
    int budget;
    int k_max;
    int strategy;
    int search;
    int depth;
    int visibility;
    int auto_bands;
    const void *auto_costs;
    void *chosen;
} lumis_luminaire_lighting;
typedef struct lumis_photometric_lighting {
    const lumis_photometric_instance *instances;
    int count;
} lumis_photometric_lighting;
typedef struct lumis_light_set_lighting {
    const lumis_light_set *set;
    unsigned kinds;
    lumis_lights_mode mode;
    const lumis_region_sampler *regions;
    int draws;
    int region_draws;
} lumis_light_set_lighting;
typedef struct lumis_sun {
    int found;
    lumis_vec3 dir;
    double radius;
    double sample_radius;
    lumis_rgb radiance;
    double power[3];
    double solid_angle;
    double share;
    double threshold;
    int pixels;
} lumis_sun;
typedef struct lumis_sun_sampler lumis_sun_sampler;
typedef struct lumis_sun_lighting {
    const lumis_sun *sun;
    const lumis_envmap *residual;
    const lumis_sun_sampler *sampler;
} lumis_sun_lighting;
typedef struct lumis_lighting {
    lumis_lighting_kind kind;
    const lumis_envmap *env;
    const lumis_sampler *sampler;
    lumis_estimator estimator;
    int hide_environment;
    lumis_light_set_lighting light_set;
    lumis_sun_lighting sun;
    const lumis_luminaire_lighting *luminaires;
    const lumis_photometric_lighting *photometric;
} lumis_lighting;
typedef struct lumis_render_desc {
    const lumis_camera *camera;
    lumis_lighting lighting;
    int pixel_centers;
    int power_heuristic;
    int spp;
    int light_samples;
    int bsdf_samples;
    unsigned long long seed;
    lumis_sequence sequence;
    int first_sample;
    int threads;
    int max_bounces;
    void (*progress)(void *user, int done, int total);
    void *progress_user;
    void (*shadow_ray)(void *user, const float org[3], const float dir[3]);
    void *shadow_ray_user;
    lumis_error_sink errors;
} lumis_render_desc;
typedef struct lumis_render_stats {
    int spp;
    int passes;
    int threads;
    double seconds;
    double camera_rays;
    double shadow_rays;
    double bounce_rays;
    double light_samples;
} lumis_render_stats;
const char *lumis_lighting_kind_name(lumis_lighting_kind kind);
lumis_status lumis_lights_mode_from_name(const char *name, lumis_lights_mode *out);
typedef struct lumis_session_desc {
    lumis_render_desc render;
    const char *lights;
    int lights_k;
    int interleave;
    const lumis_light_params *lights_params;
    int upsample;
    double time_budget;
    double spent;
    int timed_spp;
    int share_spp;
    int auto_estimator;
    int auto_pilot_spp;
    void (*pass_done)(void *user, int spp);
    void *pass_done_user;
} lumis_session_desc;
typedef struct lumis_auto_candidate {
    double error_per_spp;
    double per_spp;
    double efficiency;
    double once;
    double error_se;
    int pilot_spp;
    int lights_k;
    int sun;
} lumis_auto_candidate;
typedef struct lumis_session_result {
    lumis_render_stats stats;
    double prep_seconds;
    double budget_used_seconds;
    int lights_k;
    int upsample;
    double lights_build_ms;
    size_t lights_bytes;
    double pilot_seconds, pilot_per_spp[3], pilot_once[3];
    int pilot_k[3], pilot_count, pilot_chosen;
    double pilot_scale;
    double pilot_predicted;
    int k_floor;
    int spp_planned;
    int k_limit;
    int retried;
    double regions_build_ms;
    size_t regions_bytes;
    lumis_light_set *light_set;
    double wall_seconds, cpu_seconds;
    double render_wall_seconds, render_cpu_seconds, cpu_share;
    int threads_busy;
    int auto_count, auto_chosen, auto_prior, auto_held;
    lumis_auto_candidate auto_candidates[6];
    double auto_seconds, auto_cap, auto_pilot_seconds, auto_pilot_cpu;
    lumis_sun auto_sun;
    int auto_mode, auto_rays;
    double auto_diffuse_share;
} lumis_session_result;
lumis_status lumis_session_check(const lumis_session_desc *desc);
lumis_status lumis_render_session(const lumis_scene *scene, const lumis_session_desc *desc,
                                  lumis_image **out, lumis_session_result *result);
const char *lumis_auto_candidate_name(int candidate);
typedef struct lumis_scene_file {
    lumis_camera camera;
    char env_map[4096];
    lumis_image *env_image;
    lumis_read_info env_info;
    float env_rotation_deg, env_scale;
    lumis_object *objects;
    int object_count;
    lumis_luminaire_instance *luminaires;
    int luminaire_count;
    int luminaires_listed;
    lumis_photometric_instance *photometrics;
    int photometric_count;
} lumis_scene_file;
typedef struct lumis_scene_read_options {
    int skip_env_map;
    lumis_read_options map;
    lumis_error_sink errors;
    lumis_status (*load_preset)(void *user, const char *spec, lumis_luminaire **out);
    void *load_preset_user;
} lumis_scene_read_options;
lumis_status lumis_scene_file_read(const char *path, const lumis_scene_read_options *options,
                                   lumis_scene_file **out);
lumis_status lumis_scene_builtin(const char *name, const lumis_error_sink *errors,
                                 lumis_scene_file **out);
lumis_status lumis_scene_builtin_with_luminaire(const char *name, const lumis_luminaire *luminaire,
                                                const lumis_error_sink *errors,
                                                lumis_scene_file **out);
const char *const *lumis_scene_builtin_names(void);
void lumis_scene_file_destroy(lumis_scene_file *file);
lumis_status lumis_photometric_orient(lumis_photometric_type type, lumis_vec3 aim,
                                      const lumis_vec3 *up, double roll_deg, double R[9]);
"""

RENDER_STRUCTS = {
    "lumis_camera": ["eye", "look_at", "up", "fov_deg", "width", "height"],
    "lumis_luminaire_lighting": ["instances", "count", "budget", "k_max", "strategy", "search",
                                 "depth", "visibility", "auto_bands", "auto_costs", "chosen"],
    "lumis_photometric_lighting": ["instances", "count"],
    "lumis_light_set_lighting": ["set", "kinds", "mode", "regions"],
    "lumis_sun": ["found", "dir", "radius", "sample_radius", "radiance", "power", "solid_angle",
                  "share", "threshold", "pixels"],
    "lumis_sun_lighting": ["sun", "residual", "sampler"],
    "lumis_lighting": ["kind", "env", "sampler", "estimator", "hide_environment", "light_set",
                       "sun", "luminaires", "photometric"],
    "lumis_render_desc": ["camera", "lighting", "pixel_centers", "power_heuristic", "spp",
                          "light_samples", "bsdf_samples", "seed", "sequence", "first_sample",
                          "threads", "max_bounces", "progress", "progress_user", "shadow_ray",
                          "shadow_ray_user", "errors"],
    "lumis_sequence_desc": ["sequence", "seed", "planned_spp", "width", "x", "y", "dimension",
                            "per_sample", "errors"],
    "lumis_rigid": ["r", "t"],
    "lumis_luminaire_instance": ["luminaire", "placement", "scale", "intensity"],
    "lumis_photometric_instance": ["photometric", "placement", "multiplier", "area"],
    "lumis_luminaire_read_options": ["max_pixels", "errors"],
    "lumis_render_stats": ["spp", "passes", "threads", "seconds", "camera_rays", "shadow_rays",
                           "bounce_rays", "light_samples"],
    "lumis_session_desc": ["render", "lights", "lights_k", "interleave", "lights_params",
                           "upsample", "time_budget", "spent", "timed_spp", "share_spp",
                           "pass_done", "pass_done_user"],
    "lumis_session_result": ["stats", "prep_seconds", "budget_used_seconds", "lights_k",
                             "upsample", "lights_build_ms", "lights_bytes", "pilot_seconds",
                             "pilot_per_spp", "pilot_once", "pilot_k", "pilot_count",
                             "pilot_chosen", "pilot_scale", "pilot_predicted", "k_floor",
                             "spp_planned", "k_limit", "retried", "regions_build_ms",
                             "regions_bytes", "light_set", "wall_seconds", "cpu_seconds",
                             "render_wall_seconds", "render_cpu_seconds", "cpu_share",
                             "threads_busy"],
    "lumis_scene_file": ["camera", "env_map", "env_image", "env_info", "env_rotation_deg",
                         "env_scale", "objects", "object_count", "luminaires",
                         "luminaire_count", "luminaires_listed", "photometrics",
                         "photometric_count"],
    "lumis_scene_read_options": ["skip_env_map", "map", "errors", "load_preset",
                                 "load_preset_user"],
}
