/* Internal to lumis-render: scene-file construction shared by the JSON reader and the
 * built-in scenes. */
#ifndef LUMIS_RENDER_INTERNAL_H
#define LUMIS_RENDER_INTERNAL_H

#include "lumis/render.h"

#include <stddef.h>

struct aiScene;

/* The process's CPU time, every thread's, in seconds (0 where the clock is missing). */
double lumis__cpu_now(void);

/* The automatic estimator's price of a sample (session_auto.c): from two passes of one job,
 * n_a samples taking t_a seconds then n_b > n_a taking t_b, the slope (t_b - t_a) / (n_b -
 * n_a), what a pass costs whatever its samples cancelling; kept within [AUTO_SLOPE_MIN, 1]
 * of the second pass's average t_b / n_b (that average when n_b <= n_a; 0 when t_b <= 0). */
double lumis__auto_price(double t_a, int n_a, double t_b, int n_b);
/* A candidate's pilot pair: n samples per pixel in the first half (0: not measured), 2n in
 * the second; the halves' CPU seconds (0 without the clock) and wall seconds. */
typedef struct lumis__pilot_times {
    int n;
    double cpu[2], wall[2];
} lumis__pilot_times;
/* The prices of `count` candidates' pairs t (lumis__auto_price of each, 0 where not
 * measured): by CPU time, or by wall time for every one when the CPU time priced some
 * measured pair at nothing (the clock missing, or a pass shorter than a coarse clock's
 * tick): they are compared with each other, so one clock for all (CPU seconds over all
 * threads are about the threads' count times the wall's).  Returns 1 when the wall priced
 * them. */
int lumis__auto_prices(const lumis__pilot_times *t, int count, double *price);
/* Its choice among the candidates a (LUMIS_AUTO_CANDIDATES of them, ranked where measured
 * and priced: pilot_spp > 0 and per_spp > 0): the least efficiency, another than the prior
 * only beyond the pilots' noise (docs/render.md); *held: 1 when that rule kept the prior. */
int lumis__auto_choose(const lumis_auto_candidate *a, int prior_measured, int *held);
/* The MIS pilot's samples per pixel a half: as many as take the prior's first half's time,
 * from one MIS sample's time -- CPU seconds when both are measured (> 0), else wall --
 * rounded, within [1, 64]. */
int lumis__auto_mis_n(double prior_cpu, double mis_cpu, double prior_wall, double mis_wall);
/* The prediction's measure (LUMIS_AUTO_PREDICT): rays through a grid of at most
 * LUMIS_AUTO_GRID cells per axis of camera's image; *share: of the reflectance they met
 * (the luminance of each surface's diffuse and glossy albedos), the diffuse part's share
 * (1 when they met nothing, or nothing that reflects); *rays: how many met a surface. */
lumis_status lumis__auto_diffuse_share(const lumis_scene *scene, const lumis_camera *camera,
                                       const lumis_error_sink *errors, double *share, int *rays);

/* An empty scene file (default camera, no map, no objects), or NULL. */
lumis_scene_file *lumis__scene_file_new(void);
/* Appends a copy of o (its mesh arrays must belong to f). */
lumis_status lumis__scene_file_push(lumis_scene_file *f, const lumis_object *o);
/* Copies an assimp scene's triangles into a mesh f owns, registered under name, and points
 * o's mesh fields at it.  LUMIS_ERR_CORRUPT: no triangles. */
lumis_status lumis__scene_file_add_mesh(lumis_scene_file *f, const char *name,
                                        const struct aiScene *sc, lumis_object *o);
/* Parses a scene file's text (lumis_scene_file_read after reading it).  name: for
 * messages; dir: prefix for relative paths ("" or ending in '/'); allow_files = 0 refuses
 * mesh files (for the fuzzer, which must not open arbitrary paths). */
lumis_status lumis__scene_file_parse(const char *text, size_t n, const char *name, const char *dir,
                                     int allow_files, const lumis_error_sink *errors,
                                     lumis_scene_file **out);
/* Places a luminaire in f; f takes ownership of `owned` (NULL: in->luminaire belongs to an
 * earlier instance of f), read from path (a file or "preset:NAME"; copied). */
lumis_status lumis__scene_file_add_luminaire(lumis_scene_file *f, lumis_luminaire *owned,
                                             const char *path, const lumis_luminaire_instance *in);
/* Loads the mesh file full (absolute, or relative to the working directory) into f once,
 * and points o's mesh fields at it; a failure's message starts "file: path.file:". */
lumis_status lumis__scene_file_load_mesh(lumis_scene_file *f, const char *full, const char *file,
                                         const char *path, const lumis_error_sink *errors,
                                         lumis_object *o);
/* The luminaire f already read from path (a file or "preset:NAME"), or NULL. */
lumis_luminaire *lumis__scene_file_luminaire(const lumis_scene_file *f, const char *path);
/* The photometric file read from path, read now once per file and owned by f; or NULL with
 * *st set (the reader's message to errors). */
lumis_photometric_file *lumis__scene_file_photometric(lumis_scene_file *f, const char *path,
                                                      const lumis_error_sink *errors,
                                                      lumis_status *st);
/* A luminaire instance's placement with its defaults: an all-zero rotation is the
 * identity, scale 0 is 1 (*scale) (light_luminaire.c). */
lumis_rigid lumis__instance_placement(const lumis_luminaire_instance *in, double *scale);
/* Rotation Rz Ry Rx (degrees r), row-major, in double precision (a luminaire's placement
 * must pass lumis_rigid_check). */
void lumis__rotation_deg(const float r[3], double m[9]);
/* Scale s, then rotation Rz Ry Rx (degrees r), then translation t: a row-major 3x4. */
void lumis__transform_matrix(const float t[3], const float r[3], const float s[3], float m[12]);

/* The map a light kind lights from: the residual when a sun is split off (lighting.sun),
 * else env. */
static inline const lumis_envmap *lumis__light_map(const lumis_render_desc *d)
{
    return d->lighting.sun.sun ? d->lighting.sun.residual : d->lighting.env;
}

/* lumis_lighting_check (lighting.c); set_to_come: a light set will be made (a session's)
 * and given. */
lumis_status lumis__lighting_check(const lumis_render_desc *d, int set_to_come);
/* lumis_render_session with desc->auto_estimator (session_auto.c): the pilots, the choice,
 * then the session with it into *out and *r; keep_set: the caller takes a set made here
 * (r->light_set), else it is destroyed. */
lumis_status lumis__session_auto(const lumis_scene *scene, const lumis_session_desc *s,
                                 lumis_image **out, lumis_session_result *r, int keep_set);
/* What lights the scene under lighting kind `kind` (known), for messages: "luminaires". */
const char *lumis__lighting_lit_by(lumis_lighting_kind kind);

/* Selected draws (light_set.c), for tests: the probability q[k] with which a shading point
 * of normal `normal`, seen along `view` (towards the point), of material m picks light k of
 * d's light set (d in stratified mode; q has a slot per light: 0 for a light that is no
 * stratum or whose region is below the horizon). */
lumis_status lumis__light_set_selection(const lumis_render_desc *d, lumis_vec3 normal,
                                        lumis_vec3 view, const lumis_bsdf *m, double *q);

/* Allocated draws (light_set.c), for tests: n[k] the draws light k's region gets per vertex
 * with d's light_set.region_draws (d in stratified mode; 0 for a light that is no stratum). */
lumis_status lumis__light_set_allocation(const lumis_render_desc *d, int *n);

/* lumis_render_gbuffer on `threads` threads (0: OpenMP's default): a session renders on
 * the threads its caller gave. */
lumis_status lumis__render_gbuffer(const lumis_scene *scene, const lumis_camera *camera,
                                   int threads, const lumis_error_sink *errors,
                                   lumis_gbuffer **out);

/* Benchmark hooks (bench/bench_render.c), not part of the public API. */
/* The top-level Embree scene (an RTCScene), for raw throughput on the same rays. */
/* The seconds n pilot renders (K lights k[i], per_spp[i] seconds a sample per pixel, once[i]
 * seconds once; sorted by K, n <= LUMIS_SESSION_PILOTS) predict for kq lights at spp. */
double lumis__pilots_predict(const int *k, const double *per_spp, const double *once, int n,
                             double kq, int spp);

/* A timed render's next pass, in samples per pixel (0: stop), from the seconds per sample so
 * far, the seconds left and the samples made; cap > 0: at most cap samples, one a pass. */
int lumis__timed_next_pass(double per, double left, int spp, int cap);

void *lumis__scene_rtc(const lumis_scene *scene);

#endif
