/* What the pieces of the extremes suite share (not part of extremes.h):
 * the scenes built in code and the ray patterns aimed at them
 * (extremes_scenes.c), the report's storage (extremes_report.c).  */
#ifndef RTT_EXTREMES_INTERNAL_H
#define RTT_EXTREMES_INTERNAL_H

#include "extremes.h"

/* Soups are 9 floats per triangle, malloc'd; NULL when out of memory. */

/* The scene most checks scale and move: a closed sphere, a random soup and
 * an axis-aligned floor grid (triangles lying in split planes), spanning
 * about [-2, 2]^3. */
float *rtt_ext_base_soup(uint32_t *count);
/* Zero-area triangles (a point, two equal corners, exactly collinear
 * corners), needles, coplanar overlapping and duplicated triangles, beside a
 * small sphere.  degenerate[] receives the prims of the zero-area ones. */
float *rtt_ext_degenerate_soup(uint32_t *count, uint32_t degenerate[], uint32_t degenerate_cap,
                               uint32_t *degenerate_count);
/* Triangles shrinking geometrically towards the origin (ratio 3/4): the SAH
 * cuts one off per level, so every builder reaches its maximum depth. */
float *rtt_ext_deep_soup(uint32_t count);
/* x -> x * scale + offset, in double then rounded once. */
void rtt_ext_transform(float *xyz9, uint32_t count, double scale, const double offset[3]);

/* Ray patterns; each writes at most max rays to out and returns the count. */
/* Axis-parallel rays from outside the bounds through vertices and edge
 * midpoints, the other two components +0.0 or -0.0 in turn. */
size_t rtt_ext_rays_axis_parallel(const rtt_scene *scene, uint64_t seed, size_t max, rtt_ray *out);
/* Origins whose coordinates are vertex coordinates (where perfect splits
 * put their planes), random and axis-parallel directions. */
size_t rtt_ext_rays_split_planes(const rtt_scene *scene, uint64_t seed, size_t max, rtt_ray *out);
/* Origins on triangle surfaces (and exactly at vertices), random directions. */
size_t rtt_ext_rays_on_surface(const rtt_scene *scene, uint64_t seed, size_t max, rtt_ray *out);
/* From random points around the bounds exactly at vertices and edge midpoints. */
size_t rtt_ext_rays_vertex_aimed(const rtt_scene *scene, uint64_t seed, size_t max, rtt_ray *out);
/* From two triangle sizes away at interior points of random triangles, so
 * precision is relative to each triangle however small it is. */
size_t rtt_ext_rays_near_triangles(const rtt_scene *scene, uint64_t seed, size_t max, rtt_ray *out);
/* Rays with NaN or infinite parts, zero directions, empty intervals:
 * no engine may hit with them.  Fills max rays cycling through the list. */
size_t rtt_ext_rays_invalid(rtt_vec3 centre, size_t max, rtt_ray *out);
/* How many distinct invalid rays rtt_ext_rays_invalid cycles through. */
size_t rtt_ext_invalid_pattern_count(void);

/* A point inside the closed mesh: candidate `skip` (0 = the first) of those
 * (bounds centre, then a 5x5x5 grid) that brute force finds inside along
 * three directions (odd crossing counts).  False when there is none. */
bool rtt_ext_inside_point(const rtt_scene *scene, int skip, float inside[3]);
/* Every undirected edge (by vertex index) shared by exactly two triangles. */
bool rtt_ext_mesh_closed(const rtt_scene *scene);

/* Appends a zeroed result; NULL when out of memory. */
rtt_extreme_result *rtt_ext_add_result(rtt_extremes_report *report, const char *check, const char *engine);

#endif
