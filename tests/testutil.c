#include "testutil.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static char tmpdir[256];

static void remove_tmpdir(void)
{
    if (!tmpdir[0]) return;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
}

const char *tu_tmpdir(void)
{
    if (!tmpdir[0]) {
        const char *base = getenv("TMPDIR");
        snprintf(tmpdir, sizeof tmpdir, "%s/lumis-test-XXXXXX", base ? base : "/tmp");
        if (!mkdtemp(tmpdir)) {
            fprintf(stderr, "mkdtemp failed\n");
            abort();
        }
        atexit(remove_tmpdir);
    }
    return tmpdir;
}

const char *tu_path(const char *name)
{
    static char bufs[8][512];
    static int k;
    char *b = bufs[k++ & 7];
    snprintf(b, 512, "%s/%s", tu_tmpdir(), name);
    return b;
}

void tu_write_file(const char *path, const void *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    if (size) assert_int_equal(fwrite(data, 1, size, f), size);
    assert_int_equal(fclose(f), 0);
}

unsigned char *tu_read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *d = malloc((size_t)n + 1);
    if (d && fread(d, 1, (size_t)n, f) != (size_t)n) {
        free(d);
        d = NULL;
    }
    fclose(f);
    if (d) d[n] = 0;
    *size = (size_t)n;
    return d;
}

static void keep_last(void *user, lumis_status status, const char *message)
{
    tu_sink *s = user;
    snprintf(s->last, sizeof s->last, "%s", message);
    s->status = status;
    s->count++;
}

void tu_sink_init(tu_sink *s)
{
    memset(s, 0, sizeof *s);
    s->sink.fn = keep_last;
    s->sink.user = s;
}

lumis_image *tu_image(int w, int h, float (*f)(int i, int j, int c))
{
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(w, h, &img), LUMIS_OK);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++)
            for (int c = 0; c < 3; c++)
                img->pixels[((size_t)j * (size_t)w + (size_t)i) * 3 + (size_t)c] = f(i, j, c);
    return img;
}

lumis_envmap *tu_envmap(int w, int h, float (*f)(int i, int j, int c), float rotation_deg,
                        float scale)
{
    lumis_image *img = NULL;
    if (f) {
        img = tu_image(w, h, f);
    } else { /* a sky with a sun */
        lumis_sky_desc d = {0};
        d.width = w;
        d.height = h;
        d.sun_elevation_deg = 30.0f;
        d.sun_azimuth_deg = 100.0f;
        assert_int_equal(lumis_sky_create(&d, &img), LUMIS_OK);
    }
    lumis_envmap *env = tu_envmap_of(img, rotation_deg, scale);
    lumis_image_destroy(img);
    return env;
}

lumis_envmap *tu_envmap_of(const lumis_image *img, float rotation_deg, float scale)
{
    lumis_envmap_desc d = {0};
    d.pixels = img->pixels;
    d.width = img->width;
    d.height = img->height;
    d.rotation_deg = rotation_deg;
    d.scale = scale;
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_create(&d, &env), LUMIS_OK);
    return env;
}

static char *slurp_and_remove(const char *path)
{
    size_t n;
    char *s = (char *)tu_read_file(path, &n);
    remove(path);
    return s;
}

int tu_run(const char *cmd, char **out, char **err)
{
    static int k;
    char o[512], e[512], full[4096];
    snprintf(o, sizeof o, "%s/run%d.out", tu_tmpdir(), k);
    snprintf(e, sizeof e, "%s/run%d.err", tu_tmpdir(), k++);
    snprintf(full, sizeof full, "%s >'%s' 2>'%s' </dev/null", cmd, o, e);
    int rc = system(full);
    char *so = slurp_and_remove(o), *se = slurp_and_remove(e);
    if (out)
        *out = so;
    else
        free(so);
    if (err)
        *err = se;
    else
        free(se);
    if (rc == -1 || !WIFEXITED(rc)) return -1;
    return WEXITSTATUS(rc);
}

int tu_count_entries(const char *dir, const char *prefix)
{
    DIR *d = opendir(dir);
    if (!d) return -1;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        if (strncmp(e->d_name, prefix, strlen(prefix)) == 0) n++;
    closedir(d);
    return n;
}

lumis_status tu_tiny_luminaire(lumis_luminaire **out)
{
    static const float px[12] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    const float *ptrs[4] = {px, px, px, px};
    lumis_luminaire_desc d = {0};
    d.delta = 1.0;
    d.grid[0] = d.grid[1] = 2;
    d.grid_origin[0] = d.grid_origin[1] = -0.5;
    d.grid_spacing[0] = d.grid_spacing[1] = 1.0;
    d.width = d.height = 2;
    d.image_origin[0] = d.image_origin[1] = -1.0;
    d.image_size[0] = d.image_size[1] = 2.0;
    d.pixels = ptrs;
    return lumis_luminaire_create(&d, out);
}
