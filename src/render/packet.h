/* Shadow rays sixteen at a time (internal to lumis-render): the packet every light kind
 * fills, and the one place that hands packets to Embree. */
#ifndef LUMIS_RENDER_PACKET_H
#define LUMIS_RENDER_PACKET_H

#include <embree3/rtcore.h>

enum { LUMIS__PACKET = 16 };

typedef struct lumis__packet {
    struct RTCRay16 r; /* 64-byte aligned, as Embree requires */
    _Alignas(64) int valid[LUMIS__PACKET];
    int n; /* lanes filled, 0 .. n-1 */
} lumis__packet;

/* Fills the next lane with a ray from o along the unit vector d, up to tfar. */
void lumis__packet_push(lumis__packet *p, const float o[3], const float d[3], float tfar);

/* Traces the filled lanes for occlusion (hook, if any, sees each ray first); a lane's tfar
 * is then negative when its ray is occluded.  Every lane is handed to Embree initialised,
 * filled or not: Embree's 8- and 4-wide kernels split the packet and check each half's
 * rays against its valid mask (Debian's build asserts it), so an idle lane holding stale
 * stack bytes aborted renders on every CPU without AVX-512.  An idle lane is a valid ray
 * that cannot hit (tfar < tnear) with valid = 0. */
void lumis__packet_trace(RTCScene scene, void (*hook)(void *, const float[3], const float[3]),
                         void *user, lumis__packet *p);

#endif
