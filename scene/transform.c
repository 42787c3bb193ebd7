/* Instance transforms (conventions in transform.h).
 *
 * Doubles throughout (a translation of 1e5 + 0.3 keeps its 0.3), each point
 * through the same fixed sequence of operations, so vertices that share a
 * position still share it, bit for bit, after the transform (scene.c
 * decides closedness by exact position). */
#include <math.h>
#include <string.h>

#include "transform.h"

void rtt_transform_multiply(const double a[16], const double b[16], double out[16])
{
    double r[16];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r[4 * i + j] =
                a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j] + a[4 * i + 2] * b[8 + j] + a[4 * i + 3] * b[12 + j];
    memcpy(out, r, sizeof r);
}

/* Rotation by deg degrees about axis (0 x, 1 y, 2 z), right-handed. */
static void rotation(int axis, double deg, double out[16])
{
    double rad = deg * 3.14159265358979323846 / 180.0;
    double c = cos(rad), s = sin(rad);
    int a = (axis + 1) % 3, b = (axis + 2) % 3;
    memset(out, 0, sizeof(double) * 16);
    out[0] = out[5] = out[10] = out[15] = 1.0;
    out[4 * a + a] = c, out[4 * a + b] = -s;
    out[4 * b + a] = s, out[4 * b + b] = c;
}

void rtt_transform_compose(const double scale[3], const double rotate_deg[3], const double translate[3],
                           double out[16])
{
    double m[16] = {scale[0], 0, 0, 0, 0, scale[1], 0, 0, 0, 0, scale[2], 0, 0, 0, 0, 1}, r[16];
    rotation(0, rotate_deg[0], r), rtt_transform_multiply(r, m, m);
    rotation(1, rotate_deg[1], r), rtt_transform_multiply(r, m, m);
    rotation(2, rotate_deg[2], r), rtt_transform_multiply(r, m, m);
    m[3] = translate[0], m[7] = translate[1], m[11] = translate[2];
    memcpy(out, m, sizeof m);
}

void rtt_transform_point_exact(const double m[16], const double p[3], double out[3])
{
    for (int r = 0; r < 3; r++) out[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3];
}

/* The cofactor matrix is the inverse transpose up to a scale, which
 * normalizing removes; it needs no division, so it exists for every matrix.
 * In double, then rounded: the rows of a matrix scaled by 1e20 overflow
 * float's products. */
rtt_vec3 rtt_transform_normal(const double m[16], rtt_vec3 n)
{
    const double *r0 = &m[0], *r1 = &m[4], *r2 = &m[8], in[3] = {n.x, n.y, n.z};
    double c[3][3], out[3];
    const double *rows[3][2] = {{r1, r2}, {r2, r0}, {r0, r1}};
    for (int k = 0; k < 3; k++) {
        const double *a = rows[k][0], *b = rows[k][1];
        c[k][0] = a[1] * b[2] - a[2] * b[1];
        c[k][1] = a[2] * b[0] - a[0] * b[2];
        c[k][2] = a[0] * b[1] - a[1] * b[0];
    }
    for (int a = 0; a < 3; a++) out[a] = c[0][a] * in[0] + c[1][a] * in[1] + c[2][a] * in[2];
    double length = sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2]);
    if (!(length > 0.0) || !isfinite(length)) return rtt_v3_normalize(rtt_v3((float)out[0], (float)out[1], (float)out[2]));
    return rtt_v3((float)(out[0] / length), (float)(out[1] / length), (float)(out[2] / length));
}
