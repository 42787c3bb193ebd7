/* Brute-force oracle for the traversal harnesses (fuzz/ only).
 *
 * Every ray is tested against every triangle with the reference's
 * watertight test (rtt_reference_intersect_triangle); an engine's answer is
 * then checked against that table:
 *
 *  - a reported hit (prim p, t) must be a hit of p within the t tolerance;
 *  - no hit that the table marks required may lie closer than t - tolerance
 *    (for a miss: none at all);
 *  - occluded must be set exactly when some hit exists, with the same
 *    leniency.
 *
 * Tolerance on t (docs/ARCHITECTURE.md "Conformance"): tol(t) = 1e-4 * (|t| + S / |dir|),
 * S the largest coordinate magnitude among the scene's vertices and the ray
 * origin, so it scales with the coordinates.  Hits within tol of tnear or
 * tfar are unspecified: they are optional, never required.
 *
 * Rays with NaN or infinite components, or magnitudes beyond 1e30, or a
 * direction whose largest component is below 1e-30, or distances in the
 * scene below 1e-30 in units of the direction (past the 1e-20 .. 1e20
 * extremes of docs/ARCHITECTURE.md: 1/dir and t go denormal or overflow), must only not
 * crash and must report a prim in range; so must every engine, strict or
 * lenient, on triangles with a coordinate beyond 1e30 (a reference kd-tree
 * cell at 1.4e38 put t past what its float intervals hold).
 *
 * Strict engines (the reference) must match the watertight test: any other
 * hit is wrong, and no hit may be dropped unless it lies exactly on an edge
 * or vertex (barycentric within 1e-6 of 0: there the float test and the
 * exact answer can differ, e.g. a ray leaving a split plane by 1e-56) or on
 * a triangle seen edge-on or degenerate (the lenient rule's |det| bound
 * below: such a triangle is all edge).  The
 * reference's watertightness at shared edges is checked by the conformance
 * suite's closed-mesh rays, where some neighbour must be hit.  Lenient engines (the
 * optimized kernels, which use a different, non-watertight triangle test —
 * their documented trade) may also report or drop hits that lie near a
 * triangle's edge (a barycentric within 1e-4 of 0, computed in double, plus
 * the rounding of their float hit point o + t d: 8 ulps of the largest
 * coordinate involved, times 1 / cos of the incidence angle, over the
 * triangle's smallest altitude; a unit triangle at 1e7 is all edge; the
 * same error over |dir| widens their t tolerance, which matters for grazing
 * rays) or on a
 * triangle seen nearly edge-on or nearly degenerate (|det| below 1e-5 of
 * |e1||e2||dir|) or with a coordinate beyond 1e30.  Edge ties between prims are accepted because the
 * reported prim only has to be hit at the reported t.  Rays with a
 * subnormal direction component are checked by the lenient rules for every
 * engine (fuzz_oracle.c: the optimized engine traces them scaled). */
#ifndef RTT_FUZZ_ORACLE_H
#define RTT_FUZZ_ORACLE_H

#include <stdbool.h>
#include <stddef.h>

#include "rtt/engine.h"

typedef struct fuzz_oracle fuzz_oracle;

/* Builds the brute-force table for rays against scene (both must outlive it). */
fuzz_oracle *fuzz_oracle_create(const rtt_scene *scene, const rtt_ray *rays, size_t ray_count);
void fuzz_oracle_free(fuzz_oracle *oracle);

/* Traces the rays through engine (intersect and occluded) and aborts with a
 * one-line report naming `label`, the ray and the prims on disagreement. */
void fuzz_oracle_check(const fuzz_oracle *oracle, rtt_engine *engine, const char *label, bool lenient);

/* Aborts when the tree info breaks its own bounds (depth, reference cap) or
 * has fewer leaf references than hittable triangles (for a lenient engine:
 * triangles neither needles, nor below an altitude of 1e-30, nor beyond
 * 1e30, which a float projected test cannot represent). */
void fuzz_check_tree_info(rtt_engine *engine, const char *label, const rtt_scene *scene, bool lenient);

#endif
