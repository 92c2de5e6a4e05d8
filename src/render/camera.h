/* The pinhole camera (internal to lumis-render). */
#ifndef LUMIS_RENDER_CAMERA_H
#define LUMIS_RENDER_CAMERA_H

#include "lumis/render.h"

#include "vec.h"

typedef struct cam_frame {
    lumis_camera cam; /* with defaults filled in */
    v3 eye, fwd, right, up;
    double th, aspect; /* tan(fov / 2), width / height */
} cam_frame;

/* Checks a camera (NULL: the default) and derives its frame. */
lumis_status lumis__camera_frame(const lumis_camera *in, const lumis_error_sink *errors,
                                 cam_frame *f);

/* The direction through image position (sx, sy) in [-1, 1]^2 (sy up). */
static inline v3 camera_dir(const cam_frame *f, double sx, double sy)
{
    return norm(add(f->fwd, add(mul(f->right, sx * f->th * f->aspect), mul(f->up, sy * f->th))));
}

#endif
