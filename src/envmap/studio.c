/* Studio environment map: a dark surround with rectangular soft boxes.  Each box is a
 * rectangle in (azimuth, polar angle), i.e. aligned with the pixel grid, so the share of
 * a pixel it covers is exact (a product of two 1D overlaps, measured in u and in
 * cos theta): the map is anti-aliased and its power is the same at every resolution. */
#include "lumis/envmap.h"
#include "lumis/sky.h"

#include "../core/internal.h"

#include <math.h>

typedef struct soft_box {
    double az0, az1;     /* azimuth range, degrees, az0 < az1 within [0, 360] */
    double elev0, elev1; /* elevation range, degrees above the horizon */
    double rgb[3];       /* radiance */
} soft_box;

/* A classic three-point setup plus an overhead light; radiance in the sky's units. */
static const soft_box boxes[] = {
    {20.0, 50.0, 15.0, 45.0, {40.0, 38.0, 35.0}},   /* key, warm */
    {195.0, 235.0, 0.0, 25.0, {7.0, 7.5, 8.0}},     /* fill, cool and dim */
    {120.0, 128.0, 10.0, 60.0, {25.0, 25.0, 25.0}}, /* rim strip */
    {280.0, 320.0, 65.0, 80.0, {15.0, 15.0, 15.0}}, /* overhead */
};

/* Surround: walls and floor of a dark studio. */
static const double wall_rgb[3] = {0.02, 0.02, 0.021};
static const double floor_rgb[3] = {0.035, 0.033, 0.03};

static double overlap(double a0, double a1, double b0, double b1)
{
    double lo = a0 > b0 ? a0 : b0, hi = a1 < b1 ? a1 : b1;
    return hi > lo ? hi - lo : 0.0;
}

lumis_status lumis_studio_create(const lumis_studio_desc *desc, lumis_image **out)
{
    static const lumis_studio_desc zero_desc;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!desc) desc = &zero_desc;
    int w = desc->width ? desc->width : 1024;
    int h = desc->height ? desc->height : (w / 2 > 0 ? w / 2 : 1);
    double k = desc->intensity == 0.0f ? 1.0 : desc->intensity;
    if (!(k > 0.0) || !isfinite(k))
        return lumis__fail(&desc->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "studio: intensity must be positive and finite");
    /* The key light's radiance is 40 k; past 1e30 a map's power, exposure and metrics
     * overflow float (at 1e37 the pixels themselves became infinite). */
    if (k > 1e30)
        return lumis__fail(&desc->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "studio: intensity %g is too large: at most 1e30 (the soft boxes' "
                           "radiance must stay far inside float's range)",
                           k);
    lumis_status st = lumis_image_create(w, h, out);
    if (st != LUMIS_OK)
        return lumis__fail(&desc->errors, st, "studio: %d x %d: %s", w, h, lumis_status_string(st));
    float *px = (*out)->pixels;
    const int nbox = (int)(sizeof boxes / sizeof boxes[0]);

    for (int j = 0; j < h; j++) {
        /* Row j in cos theta: [c1, c0] with c = cos(theta) = sin(elevation). */
        double c0 = cos(LUMIS_PI * j / h), c1 = cos(LUMIS_PI * (j + 1) / h);
        double row_measure = c0 - c1;
        double above = overlap(c1, c0, 0.0, 1.0) / row_measure;
        for (int i = 0; i < w; i++) {
            double u0 = (double)i / w, u1 = (double)(i + 1) / w;
            double rgb[3];
            for (int c = 0; c < 3; c++) rgb[c] = wall_rgb[c] * above + floor_rgb[c] * (1.0 - above);
            for (int b = 0; b < nbox; b++) {
                const soft_box *s = &boxes[b];
                double fu = overlap(u0, u1, s->az0 / 360.0, s->az1 / 360.0) * w;
                if (fu == 0.0) continue;
                double fc = overlap(c1, c0, sin(s->elev0 * LUMIS_PI / 180.0),
                                    sin(s->elev1 * LUMIS_PI / 180.0)) /
                            row_measure;
                for (int c = 0; c < 3; c++) rgb[c] += k * s->rgb[c] * fu * fc;
            }
            float *p = px + ((size_t)j * (size_t)w + (size_t)i) * 3;
            for (int c = 0; c < 3; c++) p[c] = (float)rgb[c];
        }
    }
    return LUMIS_OK;
}
