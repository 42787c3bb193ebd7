/* The double-precision brute force of bench/accuracy.sh: every ray of a
 * rays.bin (rtt_ray records, float32) against every triangle of a file of 9
 * little-endian doubles per triangle (the scene's own coordinates, exact),
 * closest hit in (tnear, tfar) by the Moller-Trumbore test in double, ties
 * to the smaller index.  Writes per ray a double t (inf on a miss) and a
 * uint32 prim (0xFFFFFFFF on a miss), 12 bytes.  Standalone (no rtt library):
 * the script compiles it with cc.
 *
 *   oracle TRIS.f64 RAYS.bin OUT.bin */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static void *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    void *data = n > 0 ? malloc((size_t)n) : NULL;
    if (data && fread(data, 1, (size_t)n, f) != (size_t)n) {
        free(data);
        data = NULL;
    }
    fclose(f);
    *size = data ? (size_t)n : 0;
    return data;
}

/* t of the hit of ray (o, d) with triangle a, b, c, or NAN. */
static double hit(const double o[3], const double d[3], const double *a, const double *b, const double *c)
{
    const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]};
    const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0.0 || !isfinite(det)) return NAN;
    const double s[3] = {o[0] - a[0], o[1] - a[1], o[2] - a[2]};
    const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    if (!(u >= 0.0 && u <= 1.0)) return NAN;
    const double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
    const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    if (!(v >= 0.0 && u + v <= 1.0)) return NAN;
    return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: oracle TRIS.f64 RAYS.bin OUT.bin\n");
        return 2;
    }
    size_t tri_bytes = 0, ray_bytes = 0;
    double *tris = read_all(argv[1], &tri_bytes);
    float *rays = read_all(argv[2], &ray_bytes);
    if (!tris || !rays || tri_bytes % 72 || ray_bytes % 32) {
        fprintf(stderr, "oracle: cannot read %s or %s (or a size that is not whole records)\n", argv[1], argv[2]);
        return 1;
    }
    const size_t ntri = tri_bytes / 72, nray = ray_bytes / 32;
    FILE *out = fopen(argv[3], "wb");
    if (!out) {
        fprintf(stderr, "oracle: cannot write %s\n", argv[3]);
        return 1;
    }
    for (size_t r = 0; r < nray; r++) {
        const float *ray = &rays[8 * r];
        const double o[3] = {ray[0], ray[1], ray[2]}, d[3] = {ray[3], ray[4], ray[5]};
        double best = INFINITY;
        uint32_t prim = 0xFFFFFFFFu;
        for (size_t i = 0; i < ntri; i++) {
            const double *t = &tris[9 * i];
            double th = hit(o, d, t, t + 3, t + 6);
            if (th > (double)ray[6] && th < (double)ray[7] && th < best) best = th, prim = (uint32_t)i;
        }
        fwrite(&best, sizeof best, 1, out);
        fwrite(&prim, sizeof prim, 1, out);
    }
    return fclose(out) == 0 ? 0 : 1;
}
