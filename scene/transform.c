/* Instance transforms (conventions in transform.h).
 *
 * Floats throughout, each point through the same fixed sequence of
 * operations, so vertices that share a position still share it, bit for
 * bit, after the transform (scene.c decides closedness by exact position). */
#include <math.h>
#include <string.h>

#include "transform.h"

void rtt_transform_multiply(const float a[16], const float b[16], float out[16])
{
    float r[16];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r[4 * i + j] =
                a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] + a[4 * i + 3] * b[12 + j];
    memcpy(out, r, sizeof r);
}

/* Rotation by deg degrees about axis (0 x, 1 y, 2 z), right-handed. */
static void rotation(int axis, float deg, float out[16])
{
    double rad = (double)deg * 3.14159265358979323846 / 180.0;
    float c = (float)cos(rad), s = (float)sin(rad);
    int a = (axis + 1) % 3, b = (axis + 2) % 3;
    memset(out, 0, sizeof(float) * 16);
    out[0] = out[5] = out[10] = out[15] = 1.0f;
    out[4 * a + a] = c, out[4 * a + b] = -s;
    out[4 * b + a] = s, out[4 * b + b] = c;
}

void rtt_transform_compose(rtt_vec3 scale, rtt_vec3 rotate_deg, rtt_vec3 translate, float out[16])
{
    float m[16] = {scale.x, 0, 0, 0, 0, scale.y, 0, 0, 0, 0, scale.z, 0, 0, 0, 0, 1}, r[16];
    rotation(0, rotate_deg.x, r), rtt_transform_multiply(r, m, m);
    rotation(1, rotate_deg.y, r), rtt_transform_multiply(r, m, m);
    rotation(2, rotate_deg.z, r), rtt_transform_multiply(r, m, m);
    m[3] = translate.x, m[7] = translate.y, m[11] = translate.z;
    memcpy(out, m, sizeof m);
}

rtt_vec3 rtt_transform_point(const float m[16], rtt_vec3 p)
{
    return rtt_v3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
                  m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}

void rtt_transform_point_exact(const float m[16], rtt_vec3 p, double out[3])
{
    for (int r = 0; r < 3; r++)
        out[r] = (double)m[4 * r] * p.x + (double)m[4 * r + 1] * p.y + (double)m[4 * r + 2] * p.z + (double)m[4 * r + 3];
}

/* The cofactor matrix is the inverse transpose up to a scale, which
 * normalizing removes; it needs no division, so it exists for every matrix. */
rtt_vec3 rtt_transform_normal(const float m[16], rtt_vec3 n)
{
    rtt_vec3 r0 = rtt_v3(m[0], m[1], m[2]), r1 = rtt_v3(m[4], m[5], m[6]), r2 = rtt_v3(m[8], m[9], m[10]);
    rtt_vec3 c0 = rtt_v3_cross(r1, r2), c1 = rtt_v3_cross(r2, r0), c2 = rtt_v3_cross(r0, r1);
    rtt_vec3 out = rtt_v3_add(rtt_v3_add(rtt_v3_scale(c0, n.x), rtt_v3_scale(c1, n.y)), rtt_v3_scale(c2, n.z));
    return rtt_v3_normalize(out);
}
