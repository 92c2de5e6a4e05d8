/* Shadow-ray packets: packet.h. */
#include "packet.h"

void lumis__packet_push(lumis__packet *p, const float o[3], const float d[3], float tfar)
{
    const int q = p->n++;
    p->valid[q] = -1;
    p->r.org_x[q] = o[0];
    p->r.org_y[q] = o[1];
    p->r.org_z[q] = o[2];
    p->r.dir_x[q] = d[0];
    p->r.dir_y[q] = d[1];
    p->r.dir_z[q] = d[2];
    p->r.tnear[q] = 0.0f;
    p->r.tfar[q] = tfar;
    p->r.mask[q] = 0xffffffffu;
    p->r.flags[q] = 0;
    p->r.time[q] = 0.0f;
    p->r.id[q] = (unsigned)q;
}

void lumis__packet_trace(RTCScene scene, void (*hook)(void *, const float[3], const float[3]),
                         void *user, lumis__packet *p)
{
    for (int k = p->n; k < LUMIS__PACKET; k++) {
        p->valid[k] = 0;
        p->r.org_x[k] = p->r.org_y[k] = p->r.org_z[k] = 0.0f;
        p->r.dir_x[k] = p->r.dir_y[k] = 0.0f;
        p->r.dir_z[k] = 1.0f;
        p->r.tnear[k] = 0.0f;
        p->r.tfar[k] = -1.0f;
        p->r.mask[k] = 0xffffffffu;
        p->r.flags[k] = 0;
        p->r.time[k] = 0.0f;
        p->r.id[k] = (unsigned)k;
    }
    if (hook)
        for (int k = 0; k < p->n; k++) {
            const float o[3] = {p->r.org_x[k], p->r.org_y[k], p->r.org_z[k]},
                        d[3] = {p->r.dir_x[k], p->r.dir_y[k], p->r.dir_z[k]};
            hook(user, o, d);
        }
    struct RTCIntersectContext ictx;
    rtcInitIntersectContext(&ictx);
    rtcOccluded16(p->valid, scene, &ictx, &p->r);
}
