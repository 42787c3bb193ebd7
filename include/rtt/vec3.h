/* Small 3-vector maths shared by every module.  All functions are static
 * inline: they are the innermost operations of the scalar paths. */
#ifndef RTT_VEC3_H
#define RTT_VEC3_H

#include <math.h>

typedef struct rtt_vec3 {
    float x, y, z;
} rtt_vec3;

/* Axis-aligned box; an empty box has lo > hi (see rtt_bounds_empty). */
typedef struct rtt_bounds {
    rtt_vec3 lo, hi;
} rtt_bounds;

static inline rtt_vec3 rtt_v3(float x, float y, float z) { return (rtt_vec3){x, y, z}; }
static inline rtt_vec3 rtt_v3_add(rtt_vec3 a, rtt_vec3 b) { return rtt_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline rtt_vec3 rtt_v3_sub(rtt_vec3 a, rtt_vec3 b) { return rtt_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline rtt_vec3 rtt_v3_mul(rtt_vec3 a, rtt_vec3 b) { return rtt_v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline rtt_vec3 rtt_v3_scale(rtt_vec3 a, float s) { return rtt_v3(a.x * s, a.y * s, a.z * s); }
static inline rtt_vec3 rtt_v3_madd(rtt_vec3 a, rtt_vec3 b, float s) { return rtt_v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static inline float rtt_v3_dot(rtt_vec3 a, rtt_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline rtt_vec3 rtt_v3_cross(rtt_vec3 a, rtt_vec3 b)
{
    return rtt_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
/* Scale-free: the squares of a vector's parts leave float's range for
 * lengths beyond about 1e19 (inf) or below 1e-19 (subnormal, then 0), where
 * scenes scaled by 1e+-20 live; there the length is taken in double.  In
 * between, the float arithmetic as it always was (the same bits). */
static inline float rtt_v3_length(rtt_vec3 a)
{
    const float len = sqrtf(rtt_v3_dot(a, a));
    if (len > 1e-18f && len < 1e18f) return len;
    return (float)sqrt((double)a.x * a.x + (double)a.y * a.y + (double)a.z * a.z);
}
/* Returns a unchanged when its length is zero (no NaN from 0/0). */
static inline rtt_vec3 rtt_v3_normalize(rtt_vec3 a)
{
    const float len = sqrtf(rtt_v3_dot(a, a));
    if (len > 1e-18f && len < 1e18f) return rtt_v3_scale(a, 1.0f / len);
    const double exact = sqrt((double)a.x * a.x + (double)a.y * a.y + (double)a.z * a.z);
    return exact > 0.0 && isfinite(exact) ? rtt_v3((float)(a.x / exact), (float)(a.y / exact), (float)(a.z / exact))
                                          : a;
}
static inline rtt_vec3 rtt_v3_min(rtt_vec3 a, rtt_vec3 b)
{
    return rtt_v3(fminf(a.x, b.x), fminf(a.y, b.y), fminf(a.z, b.z));
}
static inline rtt_vec3 rtt_v3_max(rtt_vec3 a, rtt_vec3 b)
{
    return rtt_v3(fmaxf(a.x, b.x), fmaxf(a.y, b.y), fmaxf(a.z, b.z));
}
static inline float rtt_v3_get(rtt_vec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
static inline void rtt_v3_set(rtt_vec3 *a, int axis, float value)
{
    if (axis == 0) a->x = value; else if (axis == 1) a->y = value; else a->z = value;
}
static inline int rtt_v3_is_finite(rtt_vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
/* Reflects incident direction d about unit normal n. */
static inline rtt_vec3 rtt_v3_reflect(rtt_vec3 d, rtt_vec3 n) { return rtt_v3_madd(d, n, -2.0f * rtt_v3_dot(d, n)); }

static inline rtt_bounds rtt_bounds_empty(void)
{
    return (rtt_bounds){rtt_v3(INFINITY, INFINITY, INFINITY), rtt_v3(-INFINITY, -INFINITY, -INFINITY)};
}
static inline rtt_bounds rtt_bounds_grow(rtt_bounds b, rtt_vec3 p) { return (rtt_bounds){rtt_v3_min(b.lo, p), rtt_v3_max(b.hi, p)}; }
static inline rtt_bounds rtt_bounds_union(rtt_bounds a, rtt_bounds b)
{
    return (rtt_bounds){rtt_v3_min(a.lo, b.lo), rtt_v3_max(a.hi, b.hi)};
}
static inline rtt_bounds rtt_bounds_intersection(rtt_bounds a, rtt_bounds b)
{
    return (rtt_bounds){rtt_v3_max(a.lo, b.lo), rtt_v3_min(a.hi, b.hi)};
}
static inline int rtt_bounds_is_empty(rtt_bounds b) { return b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z; }
/* Surface area; 0 for an empty box. */
static inline float rtt_bounds_area(rtt_bounds b)
{
    if (rtt_bounds_is_empty(b)) return 0.0f;
    rtt_vec3 e = rtt_v3_sub(b.hi, b.lo);
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
}

#endif
