/* Precomputation of Wald's projected barycentric records (Wald 2004, 7.1.1;
 * see isect_projected_bary.h for the test and what it trades). */
#include <math.h>

#include "isect_projected_bary.h"

static bool all_finite(const float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i])) return false;
    return true;
}

bool kd_triangle_record(kd_triangle *rec, const rtt_vec3 p[3], uint32_t prim)
{
    double a[3] = {p[0].x, p[0].y, p[0].z};
    double c[3] = {(double)p[1].x - a[0], (double)p[1].y - a[1], (double)p[1].z - a[2]}; /* edge to vertex 1 */
    double b[3] = {(double)p[2].x - a[0], (double)p[2].y - a[1], (double)p[2].z - a[2]}; /* edge to vertex 2 */
    double n[3] = {c[1] * b[2] - c[2] * b[1], c[2] * b[0] - c[0] * b[2], c[0] * b[1] - c[1] * b[0]};
    uint32_t k = 0;
    if (fabs(n[1]) > fabs(n[k])) k = 1;
    if (fabs(n[2]) > fabs(n[k])) k = 2;
    if (!(fabs(n[k]) > 0.0) || !isfinite(n[k])) return false;
    uint32_t u = (k + 1) % 3, v = (k + 2) % 3;
    double nk = n[k];
    rec->n_u = (float)(n[u] / nk);
    rec->n_v = (float)(n[v] / nk);
    rec->a_k = (float)a[k];
    rec->a_u = (float)a[u];
    rec->a_v = (float)a[v];
    /* (h_u, h_v) = beta (c_u, c_v) + gamma (b_u, b_v); det = n_k. */
    rec->b_nu = (float)(b[v] / nk);
    rec->b_nv = (float)(-b[u] / nk);
    rec->c_nu = (float)(-c[v] / nk);
    rec->c_nv = (float)(c[u] / nk);
    rec->k = k;
    rec->prim = prim;
    rec->pad = 0;
    const float check[9] = {rec->n_u, rec->n_v, rec->a_k, rec->a_u, rec->a_v,
                            rec->b_nu, rec->b_nv, rec->c_nu, rec->c_nv};
    if (!all_finite(check, 9)) return false;
    /* A needle whose edge coefficients all round to zero would accept the
     * whole plane. */
    if ((rec->b_nu == 0.0f && rec->b_nv == 0.0f) || (rec->c_nu == 0.0f && rec->c_nv == 0.0f)) return false;
    return true;
}
