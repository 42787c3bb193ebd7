/* Interleaved soft-shadow sampling and the discontinuity filter (Benthin and
 * Wald 2009, section 4.5, after Keller and Heidrich's interleaved sampling).
 *
 * Samples.  Every pixel of a 4x4 block uses its own fixed set of N light
 * samples (N from RTT_INTERLEAVED_MIN_SAMPLES to RTT_INTERLEAVED_MAX_SAMPLES),
 * set = (py % 4) * 4 + px % 4.  The 16 sets partition one 2D Hammersley point
 * set of 16N points, point k = (k / 16N, radical inverse of k in base 2): set j
 * holds the points whose index k has XOR of its 4-bit digits equal to j,
 * sample i of set j being k = 16 i + (j ^ nibble-XOR of i).  For N a power of
 * two each set is a (0, log2 N, 2)-net and their union a (0, log2 16N, 2)-net,
 * so one pixel's N samples cover the light evenly and any 4x4 window's 16N
 * samples cover it as a Hammersley set of 16N would.  The sets never change:
 * renders are deterministic.
 *
 * Light frames.  A sample s in [0,1)^2 becomes a point of the light's own 2D
 * domain (rtt_light_sample_coords) and then a point of the light by a map
 * that is affine in the domain point (x, y):
 *
 *     point = (base + du * x) + dv * y        (per component, in that order)
 *
 * with (base, du, dv) from rtt_light_sample_frame(light, p):
 *   sphere light  the disc of the light's radius through its centre, facing p
 *                 (the disc rtt_light_sample uses): base = centre, du and dv
 *                 orthogonal of length radius; domain: the unit disc,
 *                 (x, y) = sqrt(s0) (cos 2 pi s1, sin 2 pi s1);
 *   quad light    base = position, du = edge_u, dv = edge_v, whatever p;
 *                 domain: the square, (x, y) = (s0 - 1/2, s1 - 1/2);
 *   point light   base = position, du = dv = 0 (every sample is the centre).
 * The domain coordinates of a set depend only on the light's type, so a kernel
 * computes a set's N (x, y) once per frame (rtt_interleaved_coords), bounds
 * its frustum by their 2D bounds (rtt_interleaved_bounds), and generates the
 * rays of a hit point on demand from the point's frame: origin p, target
 * base + du x + dv y.  A sample ray is the segment of rtt/shade.h: from p
 * towards the target, tnear = epsilon, tfar = |target - p| - epsilon.
 *
 * Visibility and composition.  The visibility of a light at a primary hit is
 * the fraction of its N sample rays that reach the light (point lights: the
 * one ray to the centre); the light's unoccluded contribution is shaded from
 * its centre (rtt_shade_light), as for every shadow method.  The renderer
 * keeps, per pixel, the colour without the primary hit's light terms
 * ("rest"), each light's weighted contribution c_l = (1 - wr - wt) *
 * contribution and its visibility v_l (NaN where the light casts no rays:
 * contribution zero, or a miss); the image is then
 *
 *     colour = rest;  for each light l in order:  colour += c_l * v_l'
 *
 * with v_l' the filtered visibility (rtt_discontinuity_filter) for lights
 * with area or, without the filter and for point lights, v_l itself (NaN:
 * the term is left out).  Deeper hits (reflected, refracted)
 * use the pixel's set too, unfiltered.  rtt_shadow_planes holds these planes
 * and rtt_shadow_planes_resolve does the last step, so every renderer that
 * draws interleaved shadows composes its image the same way. */
#ifndef RTT_INTERLEAVED_H
#define RTT_INTERLEAVED_H

#include <stdbool.h>
#include <stdint.h>

#include "rtt/scene.h"

#define RTT_INTERLEAVED_SETS 16u            /* 4x4 pixels, one set each */
#define RTT_INTERLEAVED_MIN_SAMPLES 4u
#define RTT_INTERLEAVED_MAX_SAMPLES 32u
#define RTT_INTERLEAVED_DEFAULT_SAMPLES 16u

/* The set of pixel (px, py): (py % 4) * 4 + px % 4. */
static inline uint32_t rtt_interleaved_set(uint32_t px, uint32_t py) { return (py & 3u) * 4u + (px & 3u); }

/* Sample i (0..n-1) of set `set` (0..15) of n samples per set, in [0,1)^2.
 * n from 1 to 2^20 is accepted (the renderers use 4..32). */
void rtt_interleaved_sample(uint32_t set, uint32_t i, uint32_t n, float out[2]);

/* The light-domain point of square sample s for this light's type (see above). */
void rtt_light_sample_coords(const rtt_light *light, const float s[2], float out[2]);

/* The affine map from the light's domain to its points as seen from p. */
typedef struct rtt_light_frame {
    rtt_vec3 base, du, dv;
} rtt_light_frame;

rtt_light_frame rtt_light_sample_frame(const rtt_light *light, rtt_vec3 p);
/* (base + du * x) + dv * y, per component in that order. */
rtt_vec3 rtt_light_frame_point(const rtt_light_frame *frame, float x, float y);

/* The n domain coordinates of set `set` for this light, xy[i] = sample i. */
void rtt_interleaved_coords(const rtt_light *light, uint32_t set, uint32_t n, float (*xy)[2]);
/* Their 2D bounds: lo[k] <= xy[i][k] <= hi[k] for every sample i. */
void rtt_interleaved_bounds(const rtt_light *light, uint32_t set, uint32_t n, float lo[2], float hi[2]);

/* ---- the discontinuity filter ---- */

/* Two pixels belong to the same surface when their depths differ by at most
 * depth_relative times the centre pixel's depth and their unit normals'
 * dot product is at least normal_cos. */
typedef struct rtt_discontinuity_thresholds {
    float depth_relative;
    float normal_cos;
} rtt_discontinuity_thresholds;

/* Defaults: 10% of the centre's depth (the hit distance): a plane seen at
 * up to 87 degrees from its normal keeps its neighbours 2 pixels away at
 * 512 pixels over 60 degrees of view, while a step onto a surface 10%
 * nearer or farther is an edge; and 25 degrees between normals (cos 25 deg
 * = 0.906): a curved surface keeps neighbours whose normals turn slower. */
#define RTT_DISCONTINUITY_DEPTH_RELATIVE 0.1f
#define RTT_DISCONTINUITY_NORMAL_COS 0.906f

void rtt_discontinuity_thresholds_default(rtt_discontinuity_thresholds *t);

/* The 4x4 discontinuity filter over one light's visibility plane: out[p] is
 * the weighted mean of visibility[q] over a 4-pixel box centred on p = (x, y):
 * the pixels q at offsets -2..2 on each axis (clipped to the image), those at
 * +-2 weighted 1/2 per axis (the box covers them by half), that have a
 * visibility (not NaN), a finite depth, and pass the thresholds against p.
 * The weights of each of the 16 interleaved sets in a full window sum to
 * one, so a flat region gets the mean of all 16 sets, and the box is
 * centred, so a visibility ramp is not shifted.  Pixels without a
 * visibility or with a non-finite depth keep theirs; p itself always
 * counts.  visibility, depth: width*height values; normals: 3 per pixel
 * (unit).  out must not overlap the inputs.  t NULL: the defaults. */
void rtt_discontinuity_filter(const float *visibility, const float *depth, const float *normals, uint32_t width,
                              uint32_t height, const rtt_discontinuity_thresholds *t, float *out);

/* The planes of an interleaved render before its last step (see above).
 * rest, normal and point (the primary hit's shading point, the shadow
 * rays' origin: what the refining pass retraces from): 3 floats per pixel;
 * depth: 1 (INFINITY on a miss);
 * visibility: `lights` planes of width*height (NaN: no rays);
 * contribution: `lights` planes of 3*width*height.  Pixel index y*width+x.
 * soft[l]: light l has area (rtt_light_has_area); only those planes are
 * filtered, a point light's one ray being exact. */
typedef struct rtt_shadow_planes {
    uint32_t width, height, lights;
    float *rest, *depth, *normal, *point;
    float *visibility, *contribution;
    bool *soft;
} rtt_shadow_planes;

/* The planes' size: 40 bytes per pixel and 16 per pixel and light.  The
 * renderers refuse a render whose planes would exceed
 * RTT_SHADOW_PLANES_MAX_BYTES (a map lit by hundreds of its light entities
 * at a large size), with the figures, rather than run out of memory. */
#define RTT_SHADOW_PLANES_MAX_BYTES (4ull << 30)
uint64_t rtt_shadow_planes_bytes(uint32_t width, uint32_t height, uint32_t lights);

/* Allocates zeroed planes (visibility NaN, depth INFINITY) for the `count`
 * lights; false when out of memory, the size overflows or exceeds
 * RTT_SHADOW_PLANES_MAX_BYTES (nothing left allocated). */
bool rtt_shadow_planes_init(rtt_shadow_planes *planes, uint32_t width, uint32_t height, const rtt_light *lights,
                            uint32_t count);
/* rtt_shadow_planes_init for the scene's lights, with one line in err when
 * the planes are too large or memory runs out: what the renderers call. */
bool rtt_shadow_planes_create(rtt_shadow_planes *planes, const rtt_scene *scene, uint32_t width, uint32_t height,
                              rtt_error *err);
void rtt_shadow_planes_free(rtt_shadow_planes *planes);

/* rgb (3 per pixel) = the composition above, each soft light's visibility
 * plane filtered first when `filter` (thresholds t, NULL: the defaults).  False when out of
 * memory for the filter's scratch plane (rgb untouched). */
bool rtt_shadow_planes_resolve(const rtt_shadow_planes *planes, bool filter, const rtt_discontinuity_thresholds *t,
                               float *rgb);

/* ---- the refining second pass (:refine) ----
 *
 * Benthin and Wald (5.4): "perform a second pass over the image and
 * adaptively refine only the penumbra pixels".  The filter's bias sits
 * where the visibility changes faster than its 4-pixel box on one surface
 * (a contact shadow: bench/results/interleaved.md); there the filtered
 * value departs from the pixel's own N samples by more than those samples'
 * noise.  A pixel of a light with area is refined when
 *
 *     |filtered - own| > sqrt(filtered (1 - filtered) / N) + RTT_REFINE_MARGIN
 *
 * (the binomial standard deviation of N samples around the filtered value,
 * plus a margin that keeps smooth penumbrae unrefined), and its visibility
 * becomes that of all 16 sets' samples from its own point (16 N rays, set
 * by set, sample by sample, the transmissions summed in that order and
 * divided by 16 N), unfiltered.  About 0.2-0.3% of the pixels of the test
 * scenes at 512² (1-2% at 128²). */
#define RTT_REFINE_MARGIN 0.02f

bool rtt_refine_needed(float visibility, float filtered, uint32_t samples);

/* The renderer's half of the second pass: for the `count` pixels pixel[i]
 * (index y*width+x) of light `light`, the refined visibility (all 16 sets'
 * samples from planes->point) into vis[i]; false when it fails (out of
 * memory: the resolve fails too). */
typedef bool (*rtt_refine_fn)(void *context, uint32_t light, const uint32_t *pixel, size_t count, float *vis);

/* rtt_shadow_planes_resolve with the filter and the second pass: the soft
 * lights' planes filtered, the pixels rtt_refine_needed picks (with N =
 * samples) replaced by refine's answers, then composed; *refined (may be
 * NULL) gets how many pixel-light pairs were retraced.  False when out of
 * memory (rgb untouched) or refine fails. */
bool rtt_shadow_planes_resolve_refined(const rtt_shadow_planes *planes, uint32_t samples,
                                       const rtt_discontinuity_thresholds *t, rtt_refine_fn refine, void *context,
                                       float *rgb, uint64_t *refined);

#endif
