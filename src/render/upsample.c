/* Joint-bilateral upsampling (Kopf, Cohen, Lischinski and Uyttendaele 2007), as Wu uses it
 * to bring EnvIndirects rendered at reduced resolution back to the full image: the weights
 * come from G-buffers of both resolutions, so edges in normal, depth and albedo stay sharp
 * while the light between them is interpolated.  docs/render.md has the formulas. */
#include "lumis/render.h"

#include "../core/internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>

enum { MAX_RADIUS = 8, MAX_WINDOW = (2 * MAX_RADIUS + 1) * (2 * MAX_RADIUS + 1) };

static float sq(float x)
{
    return x * x;
}

/* |a - b|^2 of two RGB or xyz triples. */
static float dist3_sq(const float *a, const float *b)
{
    return sq(a[0] - b[0]) + sq(a[1] - b[1]) + sq(a[2] - b[2]);
}

lumis_status lumis_joint_bilateral_upsample(const lumis_image *low, const lumis_gbuffer *low_g,
                                            const lumis_gbuffer *high_g,
                                            const lumis_upsample_desc *desc, lumis_image **out)
{
    const lumis_error_sink *errors = desc ? &desc->errors : NULL;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!low || !low_g || !high_g || !low->pixels || !low_g->normal || !high_g->normal)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "upsample: needs an image and two G-buffers");
    if (low->width != low_g->width || low->height != low_g->height || low->width < 1 ||
        low->height < 1 || high_g->width < 1 || high_g->height < 1)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "upsample: the image (%d x %d) and its G-buffer (%d x %d) differ",
                           low->width, low->height, low_g->width, low_g->height);
    const float sn = desc && desc->sigma_normal > 0.0f ? desc->sigma_normal : 0.005f;
    const float sd = desc && desc->sigma_depth > 0.0f ? desc->sigma_depth : 0.005f;
    const float sa = desc && desc->sigma_albedo > 0.0f ? desc->sigma_albedo : 0.005f;
    const float ss = desc && desc->sigma_spatial > 0.0f ? desc->sigma_spatial : 1.0f;
    const int rad = desc && desc->radius > 0 ? desc->radius : 2;
    if (!(isfinite(sn) && isfinite(sd) && isfinite(sa) && isfinite(ss)) || rad > MAX_RADIUS)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "upsample: sigmas must be finite and the radius at most %d, not %d",
                           MAX_RADIUS, rad);
    const int W = high_g->width, H = high_g->height, w = low->width, h = low->height;
    lumis_status st = lumis_image_create(W, H, out);
    if (st != LUMIS_OK) return lumis__fail(errors, st, "upsample: %d x %d: out of memory", W, H);
    /* Depth is compared relative to the scene's depth range in the full-resolution view. */
    float dmin = INFINITY, dmax = -INFINITY;
    for (size_t p = 0; p < (size_t)W * (size_t)H; p++)
        if (isfinite(high_g->depth[p])) {
            dmin = fminf(dmin, high_g->depth[p]);
            dmax = fmaxf(dmax, high_g->depth[p]);
        }
    const float drange = dmax > dmin ? dmax - dmin : 1.0f;
    const float kn = -0.5f / sq(sn), kd = -0.5f / sq(sd * drange), ka = -0.5f / sq(sa),
                ks = -0.5f / sq(ss);
    const double sxr = (double)w / W, syr = (double)h / H;
    const int threads = desc && desc->threads > 0 ? desc->threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads)
    for (int Y = 0; Y < H; Y++)
        for (int X = 0; X < W; X++) {
            const size_t P = (size_t)Y * (size_t)W + (size_t)X;
            float *o = (*out)->pixels + 3 * P;
            const int hit = isfinite(high_g->depth[P]);
            /* Position of P's centre in low-resolution pixel units (centres at k + 0.5). */
            const double u = (X + 0.5) * sxr - 0.5, v = (Y + 0.5) * syr - 0.5;
            const int cx = (int)floor(u + 0.5), cy = (int)floor(v + 0.5);
            /* The exponents first; the weights are exp(e - e_max), so the most similar
             * neighbour always counts (a window of strangers is a soft nearest match,
             * never an underflow). */
            float e[MAX_WINDOW];
            int qs[MAX_WINDOW], n = 0;
            float emax = -INFINITY;
            for (int dy = -rad; dy <= rad; dy++)
                for (int dx = -rad; dx <= rad; dx++) {
                    const int qx = cx + dx, qy = cy + dy;
                    if (qx < 0 || qy < 0 || qx >= w || qy >= h) continue;
                    const size_t q = (size_t)qy * (size_t)w + (size_t)qx;
                    if (isfinite(low_g->depth[q]) != hit) continue; /* object vs background */
                    float eq = ks * (sq((float)(qx - u)) + sq((float)(qy - v)));
                    if (hit) {
                        eq += kn * dist3_sq(high_g->normal + 3 * P, low_g->normal + 3 * q);
                        eq += kd * sq(high_g->depth[P] - low_g->depth[q]);
                        eq += ka * dist3_sq(high_g->albedo + 3 * P, low_g->albedo + 3 * q);
                    }
                    e[n] = eq;
                    qs[n++] = (int)q;
                    emax = eq > emax ? eq : emax;
                }
            float acc[3] = {0, 0, 0}, wsum = 0.0f;
            for (int k = 0; k < n; k++) {
                const float d = e[k] - emax;
                if (d < -87.0f) continue; /* 0 in float */
                const float wq = expf(d);
                const float *L = low->pixels + 3 * (size_t)qs[k];
                acc[0] += wq * L[0];
                acc[1] += wq * L[1];
                acc[2] += wq * L[2];
                wsum += wq;
            }
            if (n == 0) {
                o[0] = o[1] = o[2] = 0.0f; /* no pixel of its kind in the window */
            } else {
                o[0] = acc[0] / wsum;
                o[1] = acc[1] / wsum;
                o[2] = acc[2] / wsum;
            }
        }
    return LUMIS_OK;
}
