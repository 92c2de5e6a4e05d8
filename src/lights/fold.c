/* Folding the lights below a plane into the lights above it: a light set for a renderer or
 * a game engine whose scene has a ground, which would block (or double) the light the map
 * shows from below.  The power is kept, not dropped: each light below the plane goes to the
 * nearest light above it, so the set still adds up to the map's power. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double luminance(const double p[3])
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

lumis_status lumis_light_set_fold_below(lumis_light_set *set, lumis_vec3 up,
                                        const lumis_error_sink *errors, lumis_light_fold *report)
{
    const double len = sqrt((double)up.x * up.x + (double)up.y * up.y + (double)up.z * up.z);
    if (!set || !(len > 0.0) || !isfinite(len))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "fold: a light set and a nonzero, finite plane normal are needed");
    const double n[3] = {up.x / len, up.y / len, up.z / len};
    const int K = set->count;
    lumis_light *l = set->lights; /* set 0; set s at l + s K */
    int *into = malloc(sizeof *into * (size_t)(K > 0 ? K : 1));
    if (!into) return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "fold: out of memory");
    int above = 0;
    for (int k = 0; k < K; k++) {
        const double c = n[0] * l[k].dir.x + n[1] * l[k].dir.y + n[2] * l[k].dir.z;
        into[k] = c > 0.0 ? k : -1; /* on the plane counts as below: it lights no ground */
        above += c > 0.0;
    }
    if (above == 0) {
        free(into);
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "fold: none of the %d lights is above the plane: nothing to fold "
                           "them into",
                           K);
    }
    lumis_light_fold r;
    memset(&r, 0, sizeof r);
    double total = 0.0;
    for (int k = 0; k < K; k++) total += luminance(l[k].power);
    /* each light below: the light above whose direction is nearest (largest cosine; the
     * first of equals) */
    for (int k = 0; k < K; k++) {
        if (into[k] >= 0) continue;
        int best = -1;
        double bc = -2.0;
        for (int q = 0; q < K; q++) {
            if (into[q] != q) continue;
            const double c = (double)l[k].dir.x * l[q].dir.x + (double)l[k].dir.y * l[q].dir.y +
                             (double)l[k].dir.z * l[q].dir.z;
            if (c > bc) bc = c, best = q;
        }
        into[k] = best;
        lumis_light *t = &l[best];
        for (int c = 0; c < 3; c++) r.power[c] += l[k].power[c];
        r.folded++;
        /* the receiver's cone about its own direction must now hold the folded region too */
        const double ang = acos(bc > 1.0 ? 1.0 : bc < -1.0 ? -1.0 : bc) + l[k].extent;
        const float ext = (float)(ang < 3.14159265358979323846 ? ang : 3.14159265358979323846);
        for (int s = 0; s < set->sets; s++) {
            lumis_light *ts = t + (size_t)s * (size_t)K, *fs = &l[k] + (size_t)s * (size_t)K;
            for (int c = 0; c < 3; c++) ts->power[c] += fs->power[c];
            ts->solid_angle += fs->solid_angle;
            ts->pixels += fs->pixels;
            if (ext > ts->extent) ts->extent = ext;
        }
    }
    /* the lights left, in their order, in every set; their regions take the folded ones' */
    int *index = malloc(sizeof *index * (size_t)K);
    if (!index) {
        free(into);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "fold: out of memory");
    }
    int m = 0;
    for (int k = 0; k < K; k++) index[k] = into[k] == k ? m++ : -1;
    for (int s = 0; s < set->sets; s++) {
        const lumis_light *src = l + (size_t)s * (size_t)K;
        lumis_light *dst = l + (size_t)s * (size_t)m;
        for (int k = 0, o = 0; k < K; k++)
            if (into[k] == k) dst[o++] = src[k];
    }
    if (set->labels)
        for (size_t p = 0; p < (size_t)set->w * (size_t)set->h; p++) {
            const int32_t a = set->labels[p];
            if (a >= 0 && a < K) set->labels[p] = index[into[a]];
        }
    set->count = m;
    set->info.count = m;
    set->info.direct = set->info.indirect = 0;
    for (int q = 0; q < 3; q++) set->info.power[q] = 0.0;
    for (int k = 0; k < m; k++) {
        set->info.direct += l[k].kind == LUMIS_LIGHT_ENV_DIRECT;
        set->info.indirect += l[k].kind == LUMIS_LIGHT_ENV_INDIRECT;
        for (int q = 0; q < 3; q++) set->info.power[q] += l[k].power[q];
    }
    free(into);
    free(index);
    r.kept = m;
    r.share = total > 0.0 ? luminance(r.power) / total : 0.0;
    if (report) *report = r;
    return LUMIS_OK;
}
