/* Edge Width Soft Shadows: the pairing of crossings into edge widths and
 * Equation 5.1 (Thesis chapter 5, Listing 5.1), shared by both engines.  See
 * include/rtt/edge_width.h for the semantics. */
#include <math.h>

#include "rtt/edge_width.h"

rtt_edge_width_model rtt_edge_width_model_make(const rtt_scene *scene, float radius, bool leak_fix)
{
    rtt_edge_width_model m = {scene, radius > 0.0f ? radius : RTT_EDGE_WIDTH_DEFAULT_RADIUS, leak_fix};
    return m;
}

bool rtt_edge_width_ray(rtt_vec3 c, rtt_vec3 p, float epsilon, rtt_ray *out)
{
    rtt_vec3 d = rtt_v3_sub(p, c);
    float distance = rtt_v3_length(d);
    if (!(distance > 2.0f * epsilon)) return false;
    float margin = epsilon / distance;
    *out = (rtt_ray){{c.x, c.y, c.z}, {d.x, d.y, d.z}, margin, 1.0f - margin};
    return true;
}

float rtt_edge_width_occlusion(float width, float radius)
{
    if (!(width > 0.0f)) return 0.0f;
    if (width >= radius) return 1.0f;
    return width / radius;
}

static bool same_point(rtt_vec3 a, rtt_vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

bool rtt_edge_width_share_vertex(const rtt_scene *scene, uint32_t a, uint32_t b)
{
    const rtt_triangle *ta = &scene->triangles[a], *tb = &scene->triangles[b];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (ta->v[i] == tb->v[j] || same_point(scene->vertices[ta->v[i]], scene->vertices[tb->v[j]])) return true;
    return false;
}

/* Bit 0 when triangle prim faces the ray (geometric normal against dir),
 * bit 1 when it faces away. */
static uint32_t facing(const rtt_scene *scene, const float dir[3], uint32_t prim)
{
    rtt_vec3 p[3];
    rtt_scene_triangle(scene, prim, p);
    rtt_vec3 n = rtt_v3_cross(rtt_v3_sub(p[1], p[0]), rtt_v3_sub(p[2], p[0]));
    return rtt_v3_dot(n, rtt_v3(dir[0], dir[1], dir[2])) < 0.0f ? 1u : 2u;
}

static float width_scale(const rtt_scene *scene, uint32_t prim)
{
    float s = scene->materials[scene->triangle_material[prim]].edge_width_scale;
    return s > 0.0f ? s : 1.0f;
}

void rtt_edge_width_start(rtt_edge_width_state *s, const float dir[3])
{
    for (int a = 0; a < 3; a++) s->dir[a] = dir[a];
    s->max_width = 0.0f;
    s->entry_t = 0.0f;
    s->entry_prim = RTT_MISS;
    s->inside = false;
    s->decided = false;
    s->cluster_t = -INFINITY;
    s->cluster_prim = RTT_MISS;
    s->cluster_facing = 0;
}

/* Is the crossing the second of its facing in the current cluster? */
static bool merged_into_cluster(const rtt_edge_width_model *m, rtt_edge_width_state *s, float t, uint32_t prim)
{
    if (!(fabsf(t - s->cluster_t) <= RTT_EDGE_WIDTH_CLUSTER)) {
        s->cluster_t = t;
        s->cluster_prim = prim;
        s->cluster_facing = 0; /* computed only if a second crossing comes */
        return false;
    }
    if (s->cluster_facing == 0) s->cluster_facing = facing(m->scene, s->dir, s->cluster_prim);
    uint32_t f = facing(m->scene, s->dir, prim);
    if (s->cluster_facing & f) return true;
    s->cluster_facing |= f;
    return false;
}

bool rtt_edge_width_feed(const rtt_edge_width_model *m, rtt_edge_width_state *s, float t, uint32_t prim)
{
    if (s->decided) return true;
    const rtt_scene *scene = m->scene;
    if (!scene->meshes[scene->triangle_mesh[prim]].closed) return s->decided = true;
    if (merged_into_cluster(m, s, t, prim)) return false;
    if (!s->inside) {
        s->inside = true;
        s->entry_t = t;
        s->entry_prim = prim;
        return false;
    }
    s->inside = false;
    float width = (t - s->entry_t) * fmaxf(width_scale(scene, s->entry_prim), width_scale(scene, prim));
    if (m->leak_fix && !rtt_edge_width_share_vertex(scene, s->entry_prim, prim)) width = INFINITY;
    if (width > s->max_width) s->max_width = width;
    if (s->max_width > m->radius) s->decided = true; /* Listing 5.1's early exit */
    return s->decided;
}

float rtt_edge_width_finish(const rtt_edge_width_model *m, const rtt_edge_width_state *s)
{
    if (s->decided || s->inside) return 1.0f;
    return rtt_edge_width_occlusion(s->max_width, m->radius);
}
