/* bench_info: wall-clock time of `lumis info FILE --json` on a large EXR map.
 *
 * usage: bench_info [--size WxH] [--runs N] [--json] [--lumis PATH]
 *
 * Renders the procedural sky at WxH (default 8192x4096), writes it as a float ZIP EXR in a
 * fresh temporary folder, runs `PATH info FILE --json > /dev/null` N times (default 5) and
 * prints the min, median and max seconds with the machine it ran on.  The time covers the
 * whole command: process start, EXR decoding and the statistics. */
#include "bench_common.h"
#include "lumis/io.h"
#include "lumis/lumis.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

const char bench_name[] = "bench_info";

#ifndef LUMIS_CLI
#define LUMIS_CLI "lumis"
#endif

static const char usage[] =
    "usage: bench_info [--size WxH] [--runs N] [--json] [--lumis PATH]\n\n"
    "Times `lumis info FILE --json` on a float ZIP EXR of the procedural sky.\n\n"
    "  --size WxH    map size (default 8192x4096)\n"
    "  --runs N      number of timed runs (default 5)\n"
    "  --json        print one JSON object instead of text\n"
    "  --lumis PATH  the lumis executable (default " LUMIS_CLI ")\n";

/* Appends s to the shell command cmd (capacity cap), single-quoted if quote is nonzero;
 * returns 0 if it does not fit. */
static int append(char *cmd, size_t cap, const char *s, int quote)
{
    size_t n = strlen(cmd);
    if (quote && n + 1 < cap) cmd[n++] = '\'';
    for (; *s && n + 5 < cap; s++) {
        if (quote && *s == '\'') { /* ' -> '\'' */
            memcpy(cmd + n, "'\\''", 4);
            n += 4;
        } else {
            cmd[n++] = *s;
        }
    }
    if (*s || n + 2 >= cap) return 0;
    if (quote) cmd[n++] = '\'';
    cmd[n] = '\0';
    return 1;
}

/* Prints s as a JSON string literal. */
static void print_json_string(const char *s)
{
    putchar('"');
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            printf("\\%c", c);
        else if (c < 0x20)
            printf("\\u%04x", c);
        else
            putchar(c);
    }
    putchar('"');
}

int main(int argc, char **argv)
{
    int width = 8192, height = 4096, runs = 5, json = 0;
    const char *lumis = LUMIS_CLI;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(usage, stdout);
            return 0;
        } else if (strcmp(a, "--json") == 0) {
            json = 1;
        } else if (strcmp(a, "--size") == 0 && i + 1 < argc) {
            if (!bench_parse_size(argv[++i], &width, &height))
                return bench_fail("--size wants WxH (each 1..65536), got '%s'", argv[i]);
        } else if (strcmp(a, "--runs") == 0 && i + 1 < argc) {
            if (!bench_parse_int(argv[++i], 1, 1000, &runs))
                return bench_fail("--runs wants a count in 1..1000, got '%s'", argv[i]);
        } else if (strcmp(a, "--lumis") == 0 && i + 1 < argc) {
            lumis = argv[++i];
        } else {
            fprintf(stderr, "bench_info: unknown or incomplete option '%s'\n\n%s", a, usage);
            return 2;
        }
    }
    if (access(lumis, X_OK) != 0) return bench_fail("cannot run the lumis executable '%s'", lumis);

    char size[64];
    snprintf(size, sizeof size, "%dx%d", width, height);
    lumis_sky_desc desc = {0};
    desc.width = width;
    desc.height = height;
    desc.sun_elevation_deg = 35.0f;
    desc.sun_azimuth_deg = 60.0f;
    lumis_image *sky = NULL;
    lumis_status st = lumis_sky_create(&desc, &sky);
    if (st != LUMIS_OK) return bench_fail("lumis_sky_create: %s", lumis_status_string(st));

    const char *tmp_root = getenv("TMPDIR");
    char dir[4096], file[4200];
    snprintf(dir, sizeof dir, "%s/bench_info.XXXXXX", tmp_root && *tmp_root ? tmp_root : "/tmp");
    if (!mkdtemp(dir)) {
        lumis_image_destroy(sky);
        return bench_fail("cannot create a temporary folder: %s", strerror(errno));
    }
    snprintf(file, sizeof file, "%s/sky.exr", dir);

    int rc = 0;
    double *times = calloc((size_t)runs, sizeof *times);
    lumis_write_options wo = {0};
    wo.format = LUMIS_FORMAT_EXR;
    wo.exr_compression = LUMIS_EXR_ZIP; /* float channels: exr_half stays 0 */
    st = lumis_image_write(file, sky, &wo);
    lumis_image_destroy(sky);
    char cmd[16384] = "";
    if (!times) {
        rc = bench_fail("out of memory");
    } else if (st != LUMIS_OK) {
        rc = bench_fail("cannot write the EXR: %s", lumis_status_string(st));
    } else if (!append(cmd, sizeof cmd, lumis, 1) || !append(cmd, sizeof cmd, " info ", 0) ||
               !append(cmd, sizeof cmd, file, 1) ||
               !append(cmd, sizeof cmd, " --json > /dev/null", 0)) {
        rc = bench_fail("command line too long");
    } else {
        if (!json) fprintf(stderr, "bench_info: %s, %d runs of: %s\n", size, runs, cmd);
        for (int r = 0; r < runs && rc == 0; r++) {
            fflush(NULL);
            double t0 = bench_now();
            int status = system(cmd);
            times[r] = bench_now() - t0;
            if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
                rc = bench_fail("'%s' failed", cmd);
        }
    }
    remove(file);
    if (rmdir(dir) != 0)
        fprintf(stderr, "bench_info: cannot remove %s: %s\n", dir, strerror(errno));
    if (rc != 0) {
        free(times);
        return rc;
    }

    qsort(times, (size_t)runs, sizeof *times, bench_cmp_double);
    double median = runs % 2 ? times[runs / 2] : 0.5 * (times[runs / 2 - 1] + times[runs / 2]);
    double min = times[0], max = times[runs - 1];
    free(times);
    char cpu[256];
    bench_cpu_model(cpu, sizeof cpu);
    long cores = sysconf(_SC_NPROCESSORS_ONLN);

    if (json) {
        printf("{\"bench\":\"info\",\"size\":\"%s\",\"runs\":%d,\"median_s\":%.6f,"
               "\"min_s\":%.6f,\"max_s\":%.6f,\"cpu\":",
               size, runs, median, min, max);
        print_json_string(cpu);
        printf(",\"cores\":%ld}\n", cores);
    } else {
        printf("lumis info --json, %s float ZIP EXR, %d runs\n", size, runs);
        printf("  min %.3f s   median %.3f s   max %.3f s\n", min, median, max);
        printf("  machine: %s, %ld cores\n", cpu, cores);
    }
    return 0;
}
