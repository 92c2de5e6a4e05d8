/* lumis/types.h - plain value types shared by every header. */
#ifndef LUMIS_TYPES_H
#define LUMIS_TYPES_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* A direction or point.  Directions are unit length unless stated otherwise. */
typedef struct lumis_vec3 {
    float x, y, z;
} lumis_vec3;

/* Linear RGB with Rec. 709 primaries. */
typedef struct lumis_rgb {
    float r, g, b;
} lumis_rgb;

/* Luminance weights of linear Rec. 709 RGB: Y = 0.2126 R + 0.7152 G + 0.0722 B. */
#define LUMIS_LUMA_R 0.2126f
#define LUMIS_LUMA_G 0.7152f
#define LUMIS_LUMA_B 0.0722f

static inline float lumis_luminance(lumis_rgb c)
{
    return LUMIS_LUMA_R * c.r + LUMIS_LUMA_G * c.g + LUMIS_LUMA_B * c.b;
}

#ifdef __cplusplus
}
#endif
#endif
