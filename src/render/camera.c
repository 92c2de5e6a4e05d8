/* The pinhole camera: defaults, checks and its frame. */
#include "camera.h"

#include "../core/internal.h"

#include <math.h>

lumis_status lumis__camera_frame(const lumis_camera *in, const lumis_error_sink *errors,
                                 cam_frame *f)
{
    lumis_camera cam = {{0, 1, 5}, {0, 0.5f, 0}, {0, 1, 0}, 40.0f, 640, 480};
    if (in) cam = *in;
    if (cam.fov_deg == 0.0f) cam.fov_deg = 40.0f;
    if (cam.width == 0) cam.width = 640;
    if (cam.height == 0) cam.height = 480;
    if (!(cam.fov_deg > 0.0f && cam.fov_deg < 180.0f))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "render: fov must be in (0, 180)");
    if (cam.width < 1 || cam.height < 1 || cam.width > 65536 || cam.height > 65536 ||
        (size_t)cam.width * (size_t)cam.height > ((size_t)1 << 28))
        return lumis__fail(errors, LUMIS_ERR_TOO_LARGE, "render: %d x %d: bad image size",
                           cam.width, cam.height);
    v3 eye = fromf(cam.eye), fwd = norm(sub(fromf(cam.look_at), eye));
    v3 right = norm(cross(fwd, fromf(cam.up)));
    if (!(dot(right, right) > 0.5))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: camera eye equals look_at, or up is parallel to the view");
    f->cam = cam;
    f->eye = eye;
    f->fwd = fwd;
    f->right = right;
    f->up = cross(right, fwd);
    f->th = tan(0.5 * cam.fov_deg * LUMIS_PI / 180.0);
    f->aspect = (double)cam.width / cam.height;
    return LUMIS_OK;
}
