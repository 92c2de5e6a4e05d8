/* FLIP (Andersson et al. 2020) and HDR-FLIP (Andersson et al. 2021): perceptual difference
 * maps between a reference and a test image, matching NVIDIA's reference implementation
 * (NVlabs/flip v1.6).  docs/metrics.md gives the pipeline with every constant and the
 * validation against the reference tool.
 *
 * Arithmetic is single precision in the reference's order of operations (including the
 * order of the taps of every convolution), so the maps agree with it to about 1e-6; the
 * exposure range of HDR-FLIP is also computed in single precision so that
 * ceil(stop - start), the default number of exposures, agrees even near an integer. */
#include "lumis/metrics.h"

#include "../core/internal.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- constants of the paper ---------------------------------------------------------- */

#define FLIP_QC 0.7f   /* exponent applied to the HyAB colour difference */
#define FLIP_PC 0.4f   /* fraction of cmax below which differences get most of [0, 1] */
#define FLIP_PT 0.95f  /* ... namely [0, pt] */
#define FLIP_W  0.082f /* width of the edge and point detectors, in degrees */
#define FLIP_QF 0.5f   /* exponent applied to the feature difference */

/* Contrast sensitivity functions as sums of Gaussians a sqrt(pi/b) exp(-pi^2 x^2 / b), x in
 * degrees: achromatic (Y), red-green (Cx) and the two terms of blue-yellow (Cz). */
static const float CSF_A_Y = 1.0f, CSF_B_Y = 0.0047f;
static const float CSF_A_CX = 1.0f, CSF_B_CX = 0.0053f;
static const float CSF_A1_CZ = 34.1f, CSF_B1_CZ = 0.04f;
static const float CSF_A2_CZ = 13.5f, CSF_B2_CZ = 0.025f;
static const float FLIP_PI = 3.14159265358979f; /* the reference's value, in float */

/* D65 white in XYZ, and its inverse. */
static const float WHITE[3] = {0.950428545f, 1.000000000f, 1.088900371f};
static const float INV_WHITE[3] = {1.052156925f, 1.000000000f, 0.918357670f};

/* ---- colour spaces --------------------------------------------------------------------- */

/* Linear Rec. 709 RGB to CIE XYZ (D65), the exact rational sRGB matrix. */
static inline void rgb_to_xyz(float r, float g, float b, float xyz[3])
{
    xyz[0] = (10135552.0f / 24577794.0f) * r + (8788810.0f / 24577794.0f) * g +
             (4435075.0f / 24577794.0f) * b;
    xyz[1] = (2613072.0f / 12288897.0f) * r + (8788810.0f / 12288897.0f) * g +
             (887015.0f / 12288897.0f) * b;
    xyz[2] = (1425312.0f / 73733382.0f) * r + (8788810.0f / 73733382.0f) * g +
             (70074185.0f / 73733382.0f) * b;
}

static inline float clamp01(float v)
{
    /* NaN goes to 0, as with the reference's max-then-min. */
    float lo = v > 0.0f ? v : 0.0f;
    return lo > 1.0f ? 1.0f : lo;
}

static inline float lab_f(float t)
{
    const float delta = 6.0f / 29.0f;
    const float delta2 = delta * delta;
    const float delta3 = delta * delta2;
    return t > delta3 ? powf(t, 1.0f / 3.0f) : (1.0f / (3.0f * delta2)) * t + 4.0f / 29.0f;
}

/* Linear RGB to CIELAB with the Hunt adjustment (a and b scaled by L / 100). */
static inline void rgb_to_hunt_lab(float r, float g, float b, float lab[3])
{
    float xyz[3];
    rgb_to_xyz(r, g, b, xyz);
    float fx = lab_f(xyz[0] * INV_WHITE[0]);
    float fy = lab_f(xyz[1] * INV_WHITE[1]);
    float fz = lab_f(xyz[2] * INV_WHITE[2]);
    float L = 116.0f * fy - 16.0f;
    lab[0] = L;
    lab[1] = 0.01f * L * (500.0f * (fx - fy));
    lab[2] = 0.01f * L * (200.0f * (fy - fz));
}

/* The opponent space YCxCz of the CSF filtering (a linear transform of XYZ). */
static inline void rgb_to_ycxcz(float r, float g, float b, float out[3])
{
    float xyz[3];
    rgb_to_xyz(r, g, b, xyz);
    float x = xyz[0] * INV_WHITE[0], y = xyz[1] * INV_WHITE[1], z = xyz[2] * INV_WHITE[2];
    out[0] = 116.0f * y - 16.0f;
    out[1] = 500.0f * (x - y);
    out[2] = 200.0f * (y - z);
}

/* Filtered YCxCz back to linear RGB, clamped to [0, 1], then to Hunt-adjusted CIELAB. */
static inline void ycxcz_to_hunt_lab(float Y, float Cx, float Cz, float lab[3])
{
    float yn = (Y + 16.0f) / 116.0f;
    float X = (yn + Cx / 500.0f) * WHITE[0];
    float Yv = yn * WHITE[1];
    float Z = (yn - Cz / 200.0f) * WHITE[2];
    float r = clamp01(3.241003275f * X + -1.537398934f * Yv + -0.498615861f * Z);
    float g = clamp01(-0.969224334f * X + 1.875930071f * Yv + 0.041554224f * Z);
    float b = clamp01(0.055639423f * X + -0.204011202f * Yv + 1.057148933f * Z);
    rgb_to_hunt_lab(r, g, b, lab);
}

/* HyAB distance: city block on L, Euclidean on (a, b). */
static inline float hyab(const float p[3], const float q[3])
{
    float da = p[1] - q[1], db = p[2] - q[2];
    return fabsf(p[0] - q[0]) + sqrtf(da * da + db * db);
}

/* ---- tone mappers of HDR-FLIP ------------------------------------------------------------ */

/* (c^2 k0 + c k1 + k2) / (c^2 k3 + c k4 + k5) per channel, indexed by lumis_flip_tonemapper.
 * ACES is Narkowicz's fit applied to 0.6 c (his pre-exposure folded into the coefficients).
 * Reinhard's row serves only to find the exposure range: its image operator divides by
 * 1 + luminance (display_rgb), as the reference's does. */
static const float TONEMAP_COEF[4][6] = {
    {0.6f * 0.6f * 2.51f, 0.6f * 0.03f, 0.0f, 0.6f * 0.6f * 2.43f, 0.6f * 0.59f, 0.14f}, /* dflt */
    {0.6f * 0.6f * 2.51f, 0.6f * 0.03f, 0.0f, 0.6f * 0.6f * 2.43f, 0.6f * 0.59f, 0.14f}, /* ACES */
    {0.0f, 1.0f, 0.0f, 0.0f, 1.0f, 1.0f},              /* Reinhard */
    {0.231683f, 0.013791f, 0.0f, 0.18f, 0.3f, 0.018f}, /* Hable */
};

/* ---- the source of one LDR-FLIP evaluation ------------------------------------------------ */

typedef struct flip_src {
    const float *px; /* linear RGB, 3 floats a pixel */
    int hdr;         /* 0: clamp only; 1: scale, tone map, clamp */
    float scale;     /* 2^exposure */
    int tonemapper;  /* index into TONEMAP_COEF */
} flip_src;

static inline float clean(float v)
{
    return isfinite(v) && v > 0.0f ? v : 0.0f;
}

static inline float tonemap_channel(float c, const float *k)
{
    return ((c * c) * k[0] + c * k[1] + k[2]) / (c * c * k[3] + c * k[4] + k[5]);
}

/* The display-referred [0, 1] linear RGB that LDR-FLIP sees at pixel i. */
static inline void display_rgb(const flip_src *s, size_t i, float c[3])
{
    const float *p = s->px + 3 * i;
    c[0] = clean(p[0]);
    c[1] = clean(p[1]);
    c[2] = clean(p[2]);
    if (s->hdr) {
        c[0] *= s->scale;
        c[1] *= s->scale;
        c[2] *= s->scale;
        if (s->tonemapper == LUMIS_FLIP_TONEMAP_REINHARD) {
            float lum = 0.2126f * c[0] + 0.7152f * c[1] + 0.0722f * c[2];
            float f = 1.0f / (1.0f + lum);
            c[0] *= f;
            c[1] *= f;
            c[2] *= f;
        } else {
            const float *k = TONEMAP_COEF[s->tonemapper];
            c[0] = tonemap_channel(c[0], k);
            c[1] = tonemap_channel(c[1], k);
            c[2] = tonemap_channel(c[2], k);
        }
    }
    c[0] = clamp01(c[0]);
    c[1] = clamp01(c[1]);
    c[2] = clamp01(c[2]);
}

/* ---- filters --------------------------------------------------------------------------------- */

#define FLIP_MAX_PPD 100000.0

typedef struct flip_filters {
    int rs, rf;          /* radii of the CSF and feature filters */
    float *y, *cx;       /* CSF of Y and Cx, each normalised to sum 1 */
    float *cz1, *cz2;    /* the two separated Gaussians of Cz (see docs/metrics.md) */
    float *g, *dg, *ddg; /* feature detector: Gaussian, 1st and 2nd derivative */
    float cmax, pccmax;  /* colour-difference remapping */
} flip_filters;

static float csf_gauss(float x2, float a, float b)
{
    return a * sqrtf(FLIP_PI / b) * expf(-(FLIP_PI * FLIP_PI) * x2 / b);
}

/* The square root of the amplitude goes to each of the two 1-D passes. */
static float csf_gauss_sqrt(float x2, float a, float b)
{
    return sqrtf(a * sqrtf(FLIP_PI / b)) * expf(-(FLIP_PI * FLIP_PI) * x2 / b);
}

static void filters_free(flip_filters *f)
{
    free(f->y);
    memset(f, 0, sizeof *f);
}

static lumis_status filters_make(float ppd, flip_filters *f)
{
    memset(f, 0, sizeof *f);
    /* Radius: three standard deviations of the widest Gaussian (b = 0.04: sigma^2 = b / 2pi^2). */
    const float bmax = CSF_B1_CZ;
    f->rs = (int)ceilf(3.0f * sqrtf(bmax / (2.0f * (FLIP_PI * FLIP_PI))) * ppd);
    const float sd = 0.5f * FLIP_W * ppd;
    f->rf = (int)ceilf(3.0f * sd);
    const size_t ns = (size_t)(2 * f->rs + 1), nf = (size_t)(2 * f->rf + 1);
    float *all = malloc((4 * ns + 3 * nf) * sizeof(float));
    if (!all) return LUMIS_ERR_OUT_OF_MEMORY;
    f->y = all;
    f->cx = all + ns;
    f->cz1 = all + 2 * ns;
    f->cz2 = all + 3 * ns;
    f->g = all + 4 * ns;
    f->dg = f->g + nf;
    f->ddg = f->dg + nf;

    const float dx = 1.0f / ppd;
    float sy = 0.0f, scx = 0.0f, s1 = 0.0f, s2 = 0.0f;
    for (int i = 0; i < (int)ns; i++) {
        float x = (float)(i - f->rs) * dx, x2 = x * x;
        f->y[i] = csf_gauss(x2, CSF_A_Y, CSF_B_Y);
        f->cx[i] = csf_gauss(x2, CSF_A_CX, CSF_B_CX);
        f->cz1[i] = csf_gauss_sqrt(x2, CSF_A1_CZ, CSF_B1_CZ);
        f->cz2[i] = csf_gauss_sqrt(x2, CSF_A2_CZ, CSF_B2_CZ);
        sy += f->y[i];
        scx += f->cx[i];
        s1 += f->cz1[i];
        s2 += f->cz2[i];
    }
    /* Y and Cx sum to 1 in 1-D (so their 2-D kernels do); the 2-D Cz kernel is the sum of
     * the outer products of cz1 and of cz2, which sums to 1 with this common factor. */
    const float ny = 1.0f / sy, ncx = 1.0f / scx, ncz = 1.0f / sqrtf(s1 * s1 + s2 * s2);
    for (size_t i = 0; i < ns; i++) {
        f->y[i] *= ny;
        f->cx[i] *= ncx;
        f->cz1[i] *= ncz;
        f->cz2[i] *= ncz;
    }

    float gsum = 0.0f, dpos = 0.0f, dneg = 0.0f, ddpos = 0.0f, ddneg = 0.0f;
    for (int i = 0; i < (int)nf; i++) {
        float x = (float)(i - f->rf);
        float g = expf(-(x * x) / (2.0f * sd * sd));
        float d = -x * g;
        float dd = (x * x / (sd * sd) - 1.0f) * g;
        f->g[i] = g;
        f->dg[i] = d;
        f->ddg[i] = dd;
        gsum += g;
        if (d > 0.0f)
            dpos += d;
        else
            dneg -= d;
        if (dd > 0.0f)
            ddpos += dd;
        else
            ddneg -= dd;
    }
    /* Gaussian to sum 1; positive and negative lobes of the derivatives to +1 and -1. */
    for (size_t i = 0; i < nf; i++) {
        f->g[i] /= gsum;
        f->dg[i] /= f->dg[i] > 0.0f ? dpos : dneg;
        f->ddg[i] /= f->ddg[i] > 0.0f ? ddpos : ddneg;
    }

    /* cmax: the HyAB distance between green and blue, the largest between two colours of
     * the gamut, raised to qc. */
    float green[3], blue[3];
    rgb_to_hunt_lab(0.0f, 1.0f, 0.0f, green);
    rgb_to_hunt_lab(0.0f, 0.0f, 1.0f, blue);
    f->cmax = powf(hyab(green, blue), FLIP_QC);
    f->pccmax = FLIP_PC * f->cmax;
    return LUMIS_OK;
}

/* ---- convolutions -------------------------------------------------------------------------- */

/* The convolutions work on blocks of FLIP_BLOCK pixels with the sums in a fixed-size local
 * array, a shape every compiler vectorises (GCC at -O2 too) while each pixel still sums its
 * taps in order, from 0, as the reference does. */
#define FLIP_BLOCK 8

/* out[x] = sum_k w[k] pad[x + k] (a row padded with r pixels each side). */
static void conv_row(const float *restrict pad, const float *restrict w, int taps, int width,
                     float *restrict out)
{
    int x = 0;
    for (; x + FLIP_BLOCK <= width; x += FLIP_BLOCK) {
        float acc[FLIP_BLOCK] = {0.0f};
        for (int k = 0; k < taps; k++) {
            const float wk = w[k];
            const float *restrict p = pad + x + k;
            for (int j = 0; j < FLIP_BLOCK; j++) acc[j] += wk * p[j];
        }
        for (int j = 0; j < FLIP_BLOCK; j++) out[x + j] = acc[j];
    }
    for (; x < width; x++) {
        float acc = 0.0f;
        for (int k = 0; k < taps; k++) acc += w[k] * pad[x + k];
        out[x] = acc;
    }
}

/* out[x] = sum_k w[k] plane[off[k] + x]: the vertical pass, off[k] the start of the k-th
 * (border-clamped) row. */
static void conv_col(const float *restrict plane, const size_t *restrict off,
                     const float *restrict w, int taps, int width, float *restrict out)
{
    int x = 0;
    for (; x + FLIP_BLOCK <= width; x += FLIP_BLOCK) {
        float acc[FLIP_BLOCK] = {0.0f};
        for (int k = 0; k < taps; k++) {
            const float wk = w[k];
            const float *restrict p = plane + off[k] + x;
            for (int j = 0; j < FLIP_BLOCK; j++) acc[j] += wk * p[j];
        }
        for (int j = 0; j < FLIP_BLOCK; j++) out[x + j] = acc[j];
    }
    for (; x < width; x++) {
        float acc = 0.0f;
        for (int k = 0; k < taps; k++) acc += w[k] * plane[off[k] + (size_t)x];
        out[x] = acc;
    }
}

/* Border handling: clamp to edge (the nearest row or column is repeated), in both passes. */
static void pad_edges(float *pad, int width, int r)
{
    for (int k = 0; k < r; k++) {
        pad[k] = pad[r];
        pad[r + width + k] = pad[r + width - 1];
    }
}

typedef struct flip_work {
    int w, h;
    float *planes; /* 8 planes of w * h floats */
    float *rows;   /* 8 rows of w floats + 3 padded rows */
    float *pad[3];
    size_t pad_len;
    size_t *off; /* row offsets of the taps of the vertical pass */
} flip_work;

static lumis_status work_make(int w, int h, int rmax, flip_work *wk)
{
    memset(wk, 0, sizeof *wk);
    wk->w = w;
    wk->h = h;
    const size_t n = (size_t)w * (size_t)h;
    if (n > SIZE_MAX / sizeof(float) / 8) return LUMIS_ERR_OUT_OF_MEMORY;
    wk->planes = malloc(8 * n * sizeof(float));
    wk->pad_len = (size_t)w + 2 * (size_t)rmax;
    wk->rows = malloc((8 * (size_t)w + 3 * wk->pad_len) * sizeof(float));
    wk->off = malloc((2 * (size_t)rmax + 1) * sizeof(size_t));
    if (!wk->planes || !wk->rows || !wk->off) {
        free(wk->planes);
        free(wk->rows);
        free(wk->off);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    for (int c = 0; c < 3; c++) wk->pad[c] = wk->rows + 8 * (size_t)w + (size_t)c * wk->pad_len;
    return LUMIS_OK;
}

static void work_free(flip_work *wk)
{
    free(wk->planes);
    free(wk->rows);
    free(wk->off);
}

/* Offsets of rows y - r .. y + r, clamped to the image (border: the edge row repeats). */
static void row_offsets(const flip_work *wk, int y, int r)
{
    for (int k = 0; k <= 2 * r; k++)
        wk->off[k] = (size_t)lumis__clampi(y + k - r, 0, wk->h - 1) * (size_t)wk->w;
}

/* ---- LDR-FLIP -------------------------------------------------------------------------------- */

/* Horizontal CSF pass of one image into planes[0..3]: Y, Cx, Cz1, Cz2. */
static void csf_horizontal(const flip_src *s, const flip_filters *f, flip_work *wk, float *planes)
{
    const int w = wk->w, r = f->rs, taps = 2 * f->rs + 1;
    const size_t n = (size_t)w * (size_t)wk->h;
    for (int y = 0; y < wk->h; y++) {
        for (int x = 0; x < w; x++) {
            float c[3], o[3];
            display_rgb(s, (size_t)y * (size_t)w + (size_t)x, c);
            rgb_to_ycxcz(c[0], c[1], c[2], o);
            wk->pad[0][r + x] = o[0];
            wk->pad[1][r + x] = o[1];
            wk->pad[2][r + x] = o[2];
        }
        for (int c = 0; c < 3; c++) pad_edges(wk->pad[c], w, r);
        const size_t off = (size_t)y * (size_t)w;
        conv_row(wk->pad[0], f->y, taps, w, planes + off);
        conv_row(wk->pad[1], f->cx, taps, w, planes + n + off);
        conv_row(wk->pad[2], f->cz1, taps, w, planes + 2 * n + off);
        conv_row(wk->pad[2], f->cz2, taps, w, planes + 3 * n + off);
    }
}

/* Vertical CSF pass of both images and the remapped colour difference into cdiff. */
static void color_difference(const flip_filters *f, flip_work *wk, float *cdiff)
{
    const int w = wk->w, h = wk->h, r = f->rs, taps = 2 * f->rs + 1;
    const size_t n = (size_t)w * (size_t)h;
    float *acc = wk->rows; /* 8 rows: ref Y Cx Cz1 Cz2, test Y Cx Cz1 Cz2 */
    const float *wts[4] = {f->y, f->cx, f->cz1, f->cz2};
    for (int y = 0; y < h; y++) {
        row_offsets(wk, y, r);
        for (int p = 0; p < 8; p++)
            conv_col(wk->planes + (size_t)p * n, wk->off, wts[p & 3], taps, w,
                     acc + (size_t)p * (size_t)w);
        for (int x = 0; x < w; x++) {
            float lr[3], lt[3];
            ycxcz_to_hunt_lab(acc[x], acc[w + x], acc[2 * w + x] + acc[3 * w + x], lr);
            ycxcz_to_hunt_lab(acc[4 * w + x], acc[5 * w + x], acc[6 * w + x] + acc[7 * w + x], lt);
            float d = powf(hyab(lr, lt), FLIP_QC);
            /* [0, pccmax) goes to [0, pt), [pccmax, cmax] to [pt, 1]. */
            if (d < f->pccmax)
                d *= FLIP_PT / f->pccmax;
            else
                d = FLIP_PT + ((d - f->pccmax) / (f->cmax - f->pccmax)) * (1.0f - FLIP_PT);
            cdiff[(size_t)y * (size_t)w + (size_t)x] = d;
        }
    }
}

/* Horizontal feature pass of one image into planes[0..2]: dG*y, ddG*y, G*y, with y the
 * luminance Y/Yw in [0, 1]. */
static void feature_horizontal(const flip_src *s, const flip_filters *f, flip_work *wk,
                               float *planes)
{
    const int w = wk->w, r = f->rf, taps = 2 * f->rf + 1;
    const size_t n = (size_t)w * (size_t)wk->h;
    const float inv116 = 1.0f / 116.0f, sixteen116 = 16.0f / 116.0f;
    for (int y = 0; y < wk->h; y++) {
        for (int x = 0; x < w; x++) {
            float c[3], o[3];
            display_rgb(s, (size_t)y * (size_t)w + (size_t)x, c);
            rgb_to_ycxcz(c[0], c[1], c[2], o);
            wk->pad[0][r + x] = o[0] * inv116 + sixteen116;
        }
        pad_edges(wk->pad[0], w, r);
        const size_t off = (size_t)y * (size_t)w;
        conv_row(wk->pad[0], f->dg, taps, w, planes + off);
        conv_row(wk->pad[0], f->ddg, taps, w, planes + n + off);
        conv_row(wk->pad[0], f->g, taps, w, planes + 2 * n + off);
    }
}

/* Vertical feature pass of both images, the feature difference, and the final FLIP value
 * cdiff^(1 - fdiff) written over cdiff. */
static void feature_difference(const flip_filters *f, flip_work *wk, float *cdiff)
{
    const int w = wk->w, h = wk->h, r = f->rf, taps = 2 * f->rf + 1;
    const size_t n = (size_t)w * (size_t)h;
    const float norm = 1.0f / sqrtf(2.0f);
    float *acc = wk->rows; /* per image: dx, ddx, dy, ddy */
    for (int y = 0; y < h; y++) {
        row_offsets(wk, y, r);
        for (int im = 0; im < 2; im++) {
            const float *pl = wk->planes + (size_t)(3 * im) * n;
            float *a = acc + (size_t)(4 * im) * (size_t)w;
            conv_col(pl, wk->off, f->g, taps, w, a);                           /* dx = G_y dG_x   */
            conv_col(pl + n, wk->off, f->g, taps, w, a + w);                   /* ddx = G_y ddG_x */
            conv_col(pl + 2 * n, wk->off, f->dg, taps, w, a + 2 * (size_t)w);  /* dy = dG_y G_x  */
            conv_col(pl + 2 * n, wk->off, f->ddg, taps, w, a + 3 * (size_t)w); /* ddy = ddG_y G_x */
        }
        for (int x = 0; x < w; x++) {
            const float *a = acc + x, *b = acc + 4 * (size_t)w + x;
            float edge_r = sqrtf(a[0] * a[0] + a[2 * w] * a[2 * w]);
            float edge_t = sqrtf(b[0] * b[0] + b[2 * w] * b[2 * w]);
            float point_r = sqrtf(a[w] * a[w] + a[3 * w] * a[3 * w]);
            float point_t = sqrtf(b[w] * b[w] + b[3 * w] * b[3 * w]);
            float de = fabsf(edge_r - edge_t), dp = fabsf(point_r - point_t);
            float fdiff = powf(norm * (de > dp ? de : dp), FLIP_QF);
            float *e = cdiff + (size_t)y * (size_t)w + (size_t)x;
            *e = powf(*e, 1.0f - fdiff);
        }
    }
}

/* One LDR-FLIP evaluation of two sources into map. */
static void ldr_flip(const flip_src *ref, const flip_src *test, const flip_filters *f,
                     flip_work *wk, float *map)
{
    const size_t n = (size_t)wk->w * (size_t)wk->h;
    csf_horizontal(ref, f, wk, wk->planes);
    csf_horizontal(test, f, wk, wk->planes + 4 * n);
    color_difference(f, wk, map);
    feature_horizontal(ref, f, wk, wk->planes);
    feature_horizontal(test, f, wk, wk->planes + 3 * n);
    feature_difference(f, wk, map);
}

/* ---- public entry points --------------------------------------------------------------------- */

static lumis_status check_args(const lumis_image *ref, const lumis_image *test,
                               const lumis_flip_options *o, const char *what, float *ppd)
{
    const lumis_error_sink *errors = o ? &o->errors : NULL;
    *ppd = 0.0f; /* written on every path, the failures included */
    if (!ref || !test)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "%s: needs two images", what);
    if (!ref->pixels || !test->pixels || ref->width < 1 || ref->height < 1 || test->width < 1 ||
        test->height < 1)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "%s: an image is empty", what);
    if (ref->width != test->width || ref->height != test->height)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: the images differ in size (%d x %d and %d x %d)", what, ref->width,
                           ref->height, test->width, test->height);
    const double p = o ? o->pixels_per_degree : 0.0;
    if (p == 0.0) {
        /* LUMIS_FLIP_DEFAULT_PPD, evaluated in single precision as the reference does. */
        *ppd = 0.7f * (3840.0f / 0.7f) * (FLIP_PI / 180.0f);
        return LUMIS_OK;
    }
    if (!(p > 0.0 && p <= FLIP_MAX_PPD))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: pixels_per_degree must be in (0, %g], not %g", what, FLIP_MAX_PPD,
                           p);
    *ppd = (float)p;
    return LUMIS_OK;
}

static double map_mean(const float *map, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i < n; i++) s += map[i];
    return s / (double)n;
}

lumis_status lumis_flip_ldr(const lumis_image *reference, const lumis_image *test,
                            const lumis_flip_options *options, float *error_map, double *mean)
{
    const lumis_error_sink *errors = options ? &options->errors : NULL;
    float ppd;
    lumis_status st = check_args(reference, test, options, "flip-ldr", &ppd);
    if (st != LUMIS_OK) return st;
    const int w = reference->width, h = reference->height;
    const size_t n = (size_t)w * (size_t)h;

    flip_filters f;
    flip_work wk;
    float *own = NULL;
    if ((st = filters_make(ppd, &f)) != LUMIS_OK) goto oom;
    if ((st = work_make(w, h, f.rs > f.rf ? f.rs : f.rf, &wk)) != LUMIS_OK) {
        filters_free(&f);
        goto oom;
    }
    float *map = error_map;
    if (!map && !(map = own = malloc(n * sizeof(float)))) {
        work_free(&wk);
        filters_free(&f);
        st = LUMIS_ERR_OUT_OF_MEMORY;
        goto oom;
    }
    flip_src r = {reference->pixels, 0, 1.0f, 0}, t = {test->pixels, 0, 1.0f, 0};
    ldr_flip(&r, &t, &f, &wk, map);
    if (mean) *mean = map_mean(map, n);
    free(own);
    work_free(&wk);
    filters_free(&f);
    return LUMIS_OK;
oom:
    return lumis__fail(errors, st, "flip-ldr: out of memory for a %d x %d image", w, h);
}

/* The k-th smallest of v[0..n) (v is reordered); the value is what std::nth_element gives. */
static float select_nth(float *v, size_t n, size_t k)
{
    ptrdiff_t lo = 0, hi = (ptrdiff_t)n - 1, kk = (ptrdiff_t)k;
    while (lo < hi) {
        const float pivot = v[lo + (hi - lo) / 2];
        ptrdiff_t i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot) i++;
            while (v[j] > pivot) j--;
            if (i <= j) {
                float tmp = v[i];
                v[i++] = v[j];
                v[j--] = tmp;
            }
        }
        /* Now v[lo..j] <= pivot, v[i..hi] >= pivot and anything between equals pivot. */
        if (kk <= j)
            hi = j;
        else if (kk >= i)
            lo = i;
        else
            break;
    }
    return v[kk];
}

/* start = log2(x / Ymax), stop = log2(x / Ymedian), x solving tonemap(x) = 0.85 (in single
 * precision, as the reference). */
static lumis_status compute_exposures(const lumis_image *ref, int tm,
                                      const lumis_error_sink *errors, float *start, float *stop)
{
    const float *k = TONEMAP_COEF[tm];
    const float t = 0.85f;
    const float a = k[0] - t * k[3], b = k[1] - t * k[4], c = k[2] - t * k[5];
    float xmax;
    if (a == 0.0f) {
        xmax = -c / b;
    } else {
        float d1 = -0.5f * (b / a);
        float d2 = sqrtf(d1 * d1 - c / a);
        xmax = d1 + d2;
    }
    const size_t n = (size_t)ref->width * (size_t)ref->height;
    float *lum = malloc(n * sizeof(float));
    if (!lum) return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "flip-hdr: out of memory");
    float ymax = 0.0f;
    for (size_t i = 0; i < n; i++) {
        const float *p = ref->pixels + 3 * i;
        float y = 0.2126f * clean(p[0]) + 0.7152f * clean(p[1]) + 0.0722f * clean(p[2]);
        lum[i] = y;
        if (y > ymax) ymax = y;
    }
    float ymedian = select_nth(lum, n, n / 2);
    free(lum);
    if (!(ymedian > 0.0f))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "flip-hdr: the median luminance of the reference is 0 (max %g), so "
                           "the exposure range cannot be computed; give start and stop exposures",
                           (double)ymax);
    *start = (float)log2((double)(xmax / ymax));
    *stop = (float)log2((double)(xmax / ymedian));
    return LUMIS_OK;
}

lumis_status lumis_flip_hdr(const lumis_image *reference, const lumis_image *test,
                            const lumis_flip_options *options, float *error_map,
                            float *exposure_map, lumis_flip_hdr_result *result)
{
    static const lumis_flip_options zero = {0};
    const lumis_flip_options *o = options ? options : &zero;
    const lumis_error_sink *errors = &o->errors;
    float ppd;
    lumis_status st = check_args(reference, test, o, "flip-hdr", &ppd);
    if (st != LUMIS_OK) return st;
    int tm = (int)o->tonemapper;
    if (tm < LUMIS_FLIP_TONEMAP_DEFAULT || tm > LUMIS_FLIP_TONEMAP_HABLE)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "flip-hdr: unknown tone mapper %d",
                           tm);
    if (tm == LUMIS_FLIP_TONEMAP_DEFAULT) tm = LUMIS_FLIP_TONEMAP_ACES;
    /* Checked as floats: the exposures are used in single precision. */
    if ((o->start_exposure_given && !isfinite((float)o->start_exposure)) ||
        (o->stop_exposure_given && !isfinite((float)o->stop_exposure)))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "flip-hdr: non-finite exposure");
    if (o->num_exposures < 0)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "flip-hdr: num_exposures must be >= 0, not %d", o->num_exposures);

    float start = (float)o->start_exposure, stop = (float)o->stop_exposure;
    if (!o->start_exposure_given || !o->stop_exposure_given) {
        float s0 = 0.0f, s1 = 0.0f;
        if ((st = compute_exposures(reference, tm, errors, &s0, &s1)) != LUMIS_OK) return st;
        if (!o->start_exposure_given) start = s0;
        if (!o->stop_exposure_given) stop = s1;
    }
    if (start > stop)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "flip-hdr: start exposure %g is above stop exposure %g", (double)start,
                           (double)stop);
    int num = o->num_exposures;
    if (num == 0) { /* the reference's default, capped at 10^6 for absurd given ranges */
        float c = ceilf(stop - start);
        num = c > 2.0f ? (c < 1e6f ? (int)c : 1000000) : 2;
    }

    const int w = reference->width, h = reference->height;
    const size_t n = (size_t)w * (size_t)h;
    flip_filters f;
    flip_work wk;
    float *tmp = NULL, *own = NULL;
    if ((st = filters_make(ppd, &f)) != LUMIS_OK) goto oom;
    if ((st = work_make(w, h, f.rs > f.rf ? f.rs : f.rf, &wk)) != LUMIS_OK) {
        filters_free(&f);
        goto oom;
    }
    float *map = error_map;
    tmp = malloc(n * sizeof(float));
    if (!map) map = own = malloc(n * sizeof(float));
    if (!tmp || !map) {
        free(tmp);
        free(own);
        work_free(&wk);
        filters_free(&f);
        st = LUMIS_ERR_OUT_OF_MEMORY;
        goto oom;
    }
    memset(map, 0, n * sizeof(float));
    if (exposure_map) memset(exposure_map, 0, n * sizeof(float));

    const float step = num > 1 ? (stop - start) / (float)(num - 1) : 0.0f;
    for (int i = 0; i < num; i++) {
        const float exposure = start + (float)i * step;
        const float scale = powf(2.0f, exposure);
        flip_src r = {reference->pixels, 1, scale, tm}, t = {test->pixels, 1, scale, tm};
        ldr_flip(&r, &t, &f, &wk, tmp);
        const float level = num > 1 ? (float)i / (float)(num - 1) : 0.0f;
        for (size_t k = 0; k < n; k++) {
            if (tmp[k] > map[k]) {
                map[k] = tmp[k];
                if (exposure_map) exposure_map[k] = level;
            }
        }
    }
    if (result) {
        result->mean = map_mean(map, n);
        result->start_exposure = start;
        result->stop_exposure = stop;
        result->num_exposures = num;
    }
    free(tmp);
    free(own);
    work_free(&wk);
    filters_free(&f);
    return LUMIS_OK;
oom:
    return lumis__fail(errors, st, "flip-hdr: out of memory for a %d x %d image", w, h);
}

/* ---- magma ------------------------------------------------------------------------------------
 */

/* matplotlib's magma colour map (sRGB values; by Nathaniel J. Smith and Stefan van der Walt,
 * CC0), the map the reference tool uses. */
static const float MAGMA[256][3] = {
    {0.001462f, 0.000466f, 0.013866f}, {0.002258f, 0.001295f, 0.018331f},
    {0.003279f, 0.002305f, 0.023708f}, {0.004512f, 0.003490f, 0.029965f},
    {0.005950f, 0.004843f, 0.037130f}, {0.007588f, 0.006356f, 0.044973f},
    {0.009426f, 0.008022f, 0.052844f}, {0.011465f, 0.009828f, 0.060750f},
    {0.013708f, 0.011771f, 0.068667f}, {0.016156f, 0.013840f, 0.076603f},
    {0.018815f, 0.016026f, 0.084584f}, {0.021692f, 0.018320f, 0.092610f},
    {0.024792f, 0.020715f, 0.100676f}, {0.028123f, 0.023201f, 0.108787f},
    {0.031696f, 0.025765f, 0.116965f}, {0.035520f, 0.028397f, 0.125209f},
    {0.039608f, 0.031090f, 0.133515f}, {0.043830f, 0.033830f, 0.141886f},
    {0.048062f, 0.036607f, 0.150327f}, {0.052320f, 0.039407f, 0.158841f},
    {0.056615f, 0.042160f, 0.167446f}, {0.060949f, 0.044794f, 0.176129f},
    {0.065330f, 0.047318f, 0.184892f}, {0.069764f, 0.049726f, 0.193735f},
    {0.074257f, 0.052017f, 0.202660f}, {0.078815f, 0.054184f, 0.211667f},
    {0.083446f, 0.056225f, 0.220755f}, {0.088155f, 0.058133f, 0.229922f},
    {0.092949f, 0.059904f, 0.239164f}, {0.097833f, 0.061531f, 0.248477f},
    {0.102815f, 0.063010f, 0.257854f}, {0.107899f, 0.064335f, 0.267289f},
    {0.113094f, 0.065492f, 0.276784f}, {0.118405f, 0.066479f, 0.286321f},
    {0.123833f, 0.067295f, 0.295879f}, {0.129380f, 0.067935f, 0.305443f},
    {0.135053f, 0.068391f, 0.315000f}, {0.140858f, 0.068654f, 0.324538f},
    {0.146785f, 0.068738f, 0.334011f}, {0.152839f, 0.068637f, 0.343404f},
    {0.159018f, 0.068354f, 0.352688f}, {0.165308f, 0.067911f, 0.361816f},
    {0.171713f, 0.067305f, 0.370771f}, {0.178212f, 0.066576f, 0.379497f},
    {0.184801f, 0.065732f, 0.387973f}, {0.191460f, 0.064818f, 0.396152f},
    {0.198177f, 0.063862f, 0.404009f}, {0.204935f, 0.062907f, 0.411514f},
    {0.211718f, 0.061992f, 0.418647f}, {0.218512f, 0.061158f, 0.425392f},
    {0.225302f, 0.060445f, 0.431742f}, {0.232077f, 0.059889f, 0.437695f},
    {0.238826f, 0.059517f, 0.443256f}, {0.245543f, 0.059352f, 0.448436f},
    {0.252220f, 0.059415f, 0.453248f}, {0.258857f, 0.059706f, 0.457710f},
    {0.265447f, 0.060237f, 0.461840f}, {0.271994f, 0.060994f, 0.465660f},
    {0.278493f, 0.061978f, 0.469190f}, {0.284951f, 0.063168f, 0.472451f},
    {0.291366f, 0.064553f, 0.475462f}, {0.297740f, 0.066117f, 0.478243f},
    {0.304081f, 0.067835f, 0.480812f}, {0.310382f, 0.069702f, 0.483186f},
    {0.316654f, 0.071690f, 0.485380f}, {0.322899f, 0.073782f, 0.487408f},
    {0.329114f, 0.075972f, 0.489287f}, {0.335308f, 0.078236f, 0.491024f},
    {0.341482f, 0.080564f, 0.492631f}, {0.347636f, 0.082946f, 0.494121f},
    {0.353773f, 0.085373f, 0.495501f}, {0.359898f, 0.087831f, 0.496778f},
    {0.366012f, 0.090314f, 0.497960f}, {0.372116f, 0.092816f, 0.499053f},
    {0.378211f, 0.095332f, 0.500067f}, {0.384299f, 0.097855f, 0.501002f},
    {0.390384f, 0.100379f, 0.501864f}, {0.396467f, 0.102902f, 0.502658f},
    {0.402548f, 0.105420f, 0.503386f}, {0.408629f, 0.107930f, 0.504052f},
    {0.414709f, 0.110431f, 0.504662f}, {0.420791f, 0.112920f, 0.505215f},
    {0.426877f, 0.115395f, 0.505714f}, {0.432967f, 0.117855f, 0.506160f},
    {0.439062f, 0.120298f, 0.506555f}, {0.445163f, 0.122724f, 0.506901f},
    {0.451271f, 0.125132f, 0.507198f}, {0.457386f, 0.127522f, 0.507448f},
    {0.463508f, 0.129893f, 0.507652f}, {0.469640f, 0.132245f, 0.507809f},
    {0.475780f, 0.134577f, 0.507921f}, {0.481929f, 0.136891f, 0.507989f},
    {0.488088f, 0.139186f, 0.508011f}, {0.494258f, 0.141462f, 0.507988f},
    {0.500438f, 0.143719f, 0.507920f}, {0.506629f, 0.145958f, 0.507806f},
    {0.512831f, 0.148179f, 0.507648f}, {0.519045f, 0.150383f, 0.507443f},
    {0.525270f, 0.152569f, 0.507192f}, {0.531507f, 0.154739f, 0.506895f},
    {0.537755f, 0.156894f, 0.506551f}, {0.544015f, 0.159033f, 0.506159f},
    {0.550287f, 0.161158f, 0.505719f}, {0.556571f, 0.163269f, 0.505230f},
    {0.562866f, 0.165368f, 0.504692f}, {0.569172f, 0.167454f, 0.504105f},
    {0.575490f, 0.169530f, 0.503466f}, {0.581819f, 0.171596f, 0.502777f},
    {0.588158f, 0.173652f, 0.502035f}, {0.594508f, 0.175701f, 0.501241f},
    {0.600868f, 0.177743f, 0.500394f}, {0.607238f, 0.179779f, 0.499492f},
    {0.613617f, 0.181811f, 0.498536f}, {0.620005f, 0.183840f, 0.497524f},
    {0.626401f, 0.185867f, 0.496456f}, {0.632805f, 0.187893f, 0.495332f},
    {0.639216f, 0.189921f, 0.494150f}, {0.645633f, 0.191952f, 0.492910f},
    {0.652056f, 0.193986f, 0.491611f}, {0.658483f, 0.196027f, 0.490253f},
    {0.664915f, 0.198075f, 0.488836f}, {0.671349f, 0.200133f, 0.487358f},
    {0.677786f, 0.202203f, 0.485819f}, {0.684224f, 0.204286f, 0.484219f},
    {0.690661f, 0.206384f, 0.482558f}, {0.697098f, 0.208501f, 0.480835f},
    {0.703532f, 0.210638f, 0.479049f}, {0.709962f, 0.212797f, 0.477201f},
    {0.716387f, 0.214982f, 0.475290f}, {0.722805f, 0.217194f, 0.473316f},
    {0.729216f, 0.219437f, 0.471279f}, {0.735616f, 0.221713f, 0.469180f},
    {0.742004f, 0.224025f, 0.467018f}, {0.748378f, 0.226377f, 0.464794f},
    {0.754737f, 0.228772f, 0.462509f}, {0.761077f, 0.231214f, 0.460162f},
    {0.767398f, 0.233705f, 0.457755f}, {0.773695f, 0.236249f, 0.455289f},
    {0.779968f, 0.238851f, 0.452765f}, {0.786212f, 0.241514f, 0.450184f},
    {0.792427f, 0.244242f, 0.447543f}, {0.798608f, 0.247040f, 0.444848f},
    {0.804752f, 0.249911f, 0.442102f}, {0.810855f, 0.252861f, 0.439305f},
    {0.816914f, 0.255895f, 0.436461f}, {0.822926f, 0.259016f, 0.433573f},
    {0.828886f, 0.262229f, 0.430644f}, {0.834791f, 0.265540f, 0.427671f},
    {0.840636f, 0.268953f, 0.424666f}, {0.846416f, 0.272473f, 0.421631f},
    {0.852126f, 0.276106f, 0.418573f}, {0.857763f, 0.279857f, 0.415496f},
    {0.863320f, 0.283729f, 0.412403f}, {0.868793f, 0.287728f, 0.409303f},
    {0.874176f, 0.291859f, 0.406205f}, {0.879464f, 0.296125f, 0.403118f},
    {0.884651f, 0.300530f, 0.400047f}, {0.889731f, 0.305079f, 0.397002f},
    {0.894700f, 0.309773f, 0.393995f}, {0.899552f, 0.314616f, 0.391037f},
    {0.904281f, 0.319610f, 0.388137f}, {0.908884f, 0.324755f, 0.385308f},
    {0.913354f, 0.330052f, 0.382563f}, {0.917689f, 0.335500f, 0.379915f},
    {0.921884f, 0.341098f, 0.377376f}, {0.925937f, 0.346844f, 0.374959f},
    {0.929845f, 0.352734f, 0.372677f}, {0.933606f, 0.358764f, 0.370541f},
    {0.937221f, 0.364929f, 0.368567f}, {0.940687f, 0.371224f, 0.366762f},
    {0.944006f, 0.377643f, 0.365136f}, {0.947180f, 0.384178f, 0.363701f},
    {0.950210f, 0.390820f, 0.362468f}, {0.953099f, 0.397563f, 0.361438f},
    {0.955849f, 0.404400f, 0.360619f}, {0.958464f, 0.411324f, 0.360014f},
    {0.960949f, 0.418323f, 0.359630f}, {0.963310f, 0.425390f, 0.359469f},
    {0.965549f, 0.432519f, 0.359529f}, {0.967671f, 0.439703f, 0.359810f},
    {0.969680f, 0.446936f, 0.360311f}, {0.971582f, 0.454210f, 0.361030f},
    {0.973381f, 0.461520f, 0.361965f}, {0.975082f, 0.468861f, 0.363111f},
    {0.976690f, 0.476226f, 0.364466f}, {0.978210f, 0.483612f, 0.366025f},
    {0.979645f, 0.491014f, 0.367783f}, {0.981000f, 0.498428f, 0.369734f},
    {0.982279f, 0.505851f, 0.371874f}, {0.983485f, 0.513280f, 0.374198f},
    {0.984622f, 0.520713f, 0.376698f}, {0.985693f, 0.528148f, 0.379371f},
    {0.986700f, 0.535582f, 0.382210f}, {0.987646f, 0.543015f, 0.385210f},
    {0.988533f, 0.550446f, 0.388365f}, {0.989363f, 0.557873f, 0.391671f},
    {0.990138f, 0.565296f, 0.395122f}, {0.990871f, 0.572706f, 0.398714f},
    {0.991558f, 0.580107f, 0.402441f}, {0.992196f, 0.587502f, 0.406299f},
    {0.992785f, 0.594891f, 0.410283f}, {0.993326f, 0.602275f, 0.414390f},
    {0.993834f, 0.609644f, 0.418613f}, {0.994309f, 0.616999f, 0.422950f},
    {0.994738f, 0.624350f, 0.427397f}, {0.995122f, 0.631696f, 0.431951f},
    {0.995480f, 0.639027f, 0.436607f}, {0.995810f, 0.646344f, 0.441361f},
    {0.996096f, 0.653659f, 0.446213f}, {0.996341f, 0.660969f, 0.451160f},
    {0.996580f, 0.668256f, 0.456192f}, {0.996775f, 0.675541f, 0.461314f},
    {0.996925f, 0.682828f, 0.466526f}, {0.997077f, 0.690088f, 0.471811f},
    {0.997186f, 0.697349f, 0.477182f}, {0.997254f, 0.704611f, 0.482635f},
    {0.997325f, 0.711848f, 0.488154f}, {0.997351f, 0.719089f, 0.493755f},
    {0.997351f, 0.726324f, 0.499428f}, {0.997341f, 0.733545f, 0.505167f},
    {0.997285f, 0.740772f, 0.510983f}, {0.997228f, 0.747981f, 0.516859f},
    {0.997138f, 0.755190f, 0.522806f}, {0.997019f, 0.762398f, 0.528821f},
    {0.996898f, 0.769591f, 0.534892f}, {0.996727f, 0.776795f, 0.541039f},
    {0.996571f, 0.783977f, 0.547233f}, {0.996369f, 0.791167f, 0.553499f},
    {0.996162f, 0.798348f, 0.559820f}, {0.995932f, 0.805527f, 0.566202f},
    {0.995680f, 0.812706f, 0.572645f}, {0.995424f, 0.819875f, 0.579140f},
    {0.995131f, 0.827052f, 0.585701f}, {0.994851f, 0.834213f, 0.592307f},
    {0.994524f, 0.841387f, 0.598983f}, {0.994222f, 0.848540f, 0.605696f},
    {0.993866f, 0.855711f, 0.612482f}, {0.993545f, 0.862859f, 0.619299f},
    {0.993170f, 0.870024f, 0.626189f}, {0.992831f, 0.877168f, 0.633109f},
    {0.992440f, 0.884330f, 0.640099f}, {0.992089f, 0.891470f, 0.647116f},
    {0.991688f, 0.898627f, 0.654202f}, {0.991332f, 0.905763f, 0.661309f},
    {0.990930f, 0.912915f, 0.668481f}, {0.990570f, 0.920049f, 0.675675f},
    {0.990175f, 0.927196f, 0.682926f}, {0.989815f, 0.934329f, 0.690198f},
    {0.989434f, 0.941470f, 0.697519f}, {0.989077f, 0.948604f, 0.704863f},
    {0.988717f, 0.955742f, 0.712242f}, {0.988367f, 0.962878f, 0.719649f},
    {0.988033f, 0.970012f, 0.727077f}, {0.987691f, 0.977154f, 0.734536f},
    {0.987387f, 0.984288f, 0.742002f}, {0.987053f, 0.991438f, 0.749504f},
};

static float srgb_decode(float v)
{
    return v <= 0.04045f ? v / 12.92f : powf((v + 0.055f) / 1.055f, 2.4f);
}

lumis_status lumis_flip_colormap(const float *error_map, int width, int height, lumis_image **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!error_map) return LUMIS_ERR_INVALID_ARGUMENT;
    lumis_image *img = NULL;
    lumis_status st = lumis_image_create(width, height, &img);
    if (st != LUMIS_OK) return st;
    float lut[256][3];
    for (int i = 0; i < 256; i++)
        for (int c = 0; c < 3; c++) lut[i][c] = srgb_decode(MAGMA[i][c]);
    const size_t n = (size_t)width * (size_t)height;
    for (size_t i = 0; i < n; i++) {
        int k = (int)(clamp01(error_map[i]) * 255.0f + 0.5f);
        memcpy(img->pixels + 3 * i, lut[k], sizeof lut[k]);
    }
    *out = img;
    return LUMIS_OK;
}
