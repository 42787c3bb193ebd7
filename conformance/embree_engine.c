/* The Embree 3 engine: Embree behind the engine interface, as the oracle of
 * the conformance suite and the performance peer of the benchmarks.
 *
 * What it promises, and what it does not:
 * - One triangle geometry holds every triangle in the global order, so
 *   Embree's primID is our prim index.  Degenerate triangles are kept (Embree
 *   never hits a zero-area triangle), so ids agree with the other engines.
 * - RTC_SCENE_FLAG_ROBUST and RTC_BUILD_QUALITY_HIGH.  Robust mode is still
 *   not watertight: rays aimed exactly at the vertices of a closed mesh
 *   escape it at a measurable rate (conformance/README.md).
 * - The ISA is pinned: the device is always created with "isa=sse4.2", so
 *   results do not change with the machine (AVX2's FMA changes which
 *   neighbour is hit near an edge).  Anything stored from Embree (golden
 *   data, reports) is therefore reproducible; the price is speed on AVX
 *   machines, which only the benchmarks care about.
 * - Embree's interval is [tnear, tfar], inclusive at both ends, where ours is
 *   open: a hit exactly at tnear or tfar may be reported.  The conformance
 *   comparison counts hits within tolerance of either bound as "boundary".
 * - Rays Embree does not accept (a non-finite origin or direction, a
 *   component of 1.844e18 or more, which aborts it on an assertion, a NaN
 *   bound, an empty interval tnear >= tfar or tfar <= 0, a zero direction)
 *   are answered as misses without asking Embree: its behaviour on them is
 *   unspecified.
 * - Embree's precision range is narrower than the reference's: scenes
 *   scaled to 1e+-18 and beyond lose most hits (products of coordinates
 *   leave float range).  The extremes suite reports those checks for
 *   Embree rather than asserting them (conformance/README.md).
 * - Errors reported by Embree's callback never print: the first one is kept
 *   and becomes the rtt_error of the failing call. */
#include <embree3/rtcore.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "embree_engine.h"
#include "rtt/reference.h"

/* The ISA every Embree device is created with (see above). */
#define EMBREE_DEVICE_CONFIG "isa=sse4.2,verbose=0"

typedef struct embree_engine {
    rtt_engine base;
    RTCDevice device;
    RTCScene scene;
    char first_error[256]; /* filled by the error callback, empty when none */
} embree_engine;

static void record_error(void *user, enum RTCError code, const char *str)
{
    embree_engine *e = user;
    if (e->first_error[0] == '\0')
        snprintf(e->first_error, sizeof e->first_error, "embree error %d: %s", (int)code, str ? str : "(no message)");
}

/* Embree's own validity bound on ray components (FLT_LARGE in its
 * sources, 1.844e18): a component at or beyond it trips an assertion that
 * aborts the process, so such rays are never handed to Embree. */
#define EMBREE_COMPONENT_LIMIT 1.844e18f

bool rtt_embree_ray_in_range(const rtt_ray *r)
{
    for (int k = 0; k < 3; k++)
        if (!isfinite(r->org[k]) || !isfinite(r->dir[k])) return false;
    for (int k = 0; k < 3; k++)
        if (!(fabsf(r->org[k]) < EMBREE_COMPONENT_LIMIT && fabsf(r->dir[k]) < EMBREE_COMPONENT_LIMIT)) return false;
    /* Our interval is open: (tnear, tfar) is empty unless tnear < tfar, also
     * after tnear is raised to 0 for Embree (an untraced ray keeps its tfar,
     * and a tfar of -inf would read as "occluded"). */
    if (isnan(r->tnear) || isnan(r->tfar) || !(r->tnear < r->tfar) || !(r->tfar > 0.0f)) return false;
    return r->dir[0] != 0.0f || r->dir[1] != 0.0f || r->dir[2] != 0.0f;
}

static void fill_ray(struct RTCRay *out, const rtt_ray *r)
{
    out->org_x = r->org[0];
    out->org_y = r->org[1];
    out->org_z = r->org[2];
    out->tnear = r->tnear < 0.0f ? 0.0f : r->tnear; /* Embree wants tnear >= 0 */
    out->dir_x = r->dir[0];
    out->dir_y = r->dir[1];
    out->dir_z = r->dir[2];
    out->time = 0.0f;
    out->tfar = r->tfar;
    out->mask = 0xFFFFFFFFu;
    out->id = 0;
    out->flags = 0;
}

static void embree_intersect(rtt_engine *engine, const rtt_ray *rays, rtt_hit *hits, size_t n)
{
    embree_engine *e = (embree_engine *)engine;
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = 0; i < n; i++) {
        hits[i] = (rtt_hit){INFINITY, 0.0f, 0.0f, RTT_MISS};
        if (!rtt_embree_ray_in_range(&rays[i])) continue;
        struct RTCRayHit rh;
        fill_ray(&rh.ray, &rays[i]);
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(e->scene, &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        hits[i] = (rtt_hit){rh.ray.tfar, rh.hit.u, rh.hit.v, rh.hit.primID};
    }
}

static void embree_occluded(rtt_engine *engine, const rtt_ray *rays, uint8_t *occluded, size_t n)
{
    embree_engine *e = (embree_engine *)engine;
    struct RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (size_t i = 0; i < n; i++) {
        occluded[i] = 0;
        if (!rtt_embree_ray_in_range(&rays[i])) continue;
        struct RTCRay ray;
        fill_ray(&ray, &rays[i]);
        rtcOccluded1(e->scene, &context, &ray);
        occluded[i] = ray.tfar == -INFINITY; /* Embree's mark for "occluded" */
    }
}

static void embree_destroy(rtt_engine *engine)
{
    embree_engine *e = (embree_engine *)engine;
    if (!e) return;
    if (e->scene) rtcReleaseScene(e->scene);
    if (e->device) rtcReleaseDevice(e->device);
    free(e);
}

static const rtt_engine_vtable embree_vtable = {
    .name = "embree",
    .intersect = embree_intersect,
    .occluded = embree_occluded,
    .render = rtt_reference_render_engine, /* the reference renderer, every ray traced by Embree */
    .destroy = embree_destroy,
    .tree_info = NULL,
};

const rtt_engine_class rtt_embree_engine_class = {
    .name = "embree",
    .summary = "Embree 3 (robust, SSE4.2) tracing for the reference renderer: the oracle and peer",
    .uses = 0,
    .shadow_methods = RTT_REFERENCE_SHADOW_METHODS,
    .create = rtt_embree_engine_create,
};

bool rtt_embree_attach_triangles(RTCDevice device, RTCScene target, const rtt_scene *scene)
{
    if (scene->triangle_count == 0) return true;
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!geom) return false;
    float *vertices = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                              3 * sizeof(float), scene->vertex_count);
    unsigned *indices = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                3 * sizeof(unsigned), scene->triangle_count);
    if (!vertices || !indices) {
        rtcReleaseGeometry(geom);
        return false;
    }
    for (uint32_t i = 0; i < scene->vertex_count; i++) {
        vertices[3 * i + 0] = scene->vertices[i].x;
        vertices[3 * i + 1] = scene->vertices[i].y;
        vertices[3 * i + 2] = scene->vertices[i].z;
    }
    for (uint32_t i = 0; i < scene->triangle_count; i++)
        for (int k = 0; k < 3; k++) indices[3 * i + k] = scene->triangles[i].v[k];
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(target, geom, 0);
    rtcReleaseGeometry(geom);
    return true;
}

static bool attach_triangles(embree_engine *e, const rtt_scene *scene)
{
    return rtt_embree_attach_triangles(e->device, e->scene, scene) && e->first_error[0] == '\0';
}

rtt_engine *rtt_embree_engine_create(const rtt_scene *scene, const rtt_engine_options *opt, rtt_error *err)
{
    (void)opt; /* Embree has no traversal modes or tree options (its class uses none) */
    embree_engine *e = calloc(1, sizeof *e);
    if (!e) {
        rtt_error_set(err, "%s: out of memory creating the Embree engine", scene->path);
        return NULL;
    }
    e->base.vt = &embree_vtable;
    e->base.scene = scene;
    e->device = rtcNewDevice(EMBREE_DEVICE_CONFIG);
    if (!e->device) {
        rtt_error_set(err, "%s: embree: rtcNewDevice(\"%s\") failed with error %d", scene->path,
                      EMBREE_DEVICE_CONFIG, (int)rtcGetDeviceError(NULL));
        free(e);
        return NULL;
    }
    rtcSetDeviceErrorFunction(e->device, record_error, e);
    e->scene = rtcNewScene(e->device);
    if (e->scene) {
        rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);
        rtcSetSceneBuildQuality(e->scene, RTC_BUILD_QUALITY_HIGH);
        if (attach_triangles(e, scene)) rtcCommitScene(e->scene);
    }
    if (!e->scene || e->first_error[0] != '\0') {
        rtt_error_set(err, "%s: %s", scene->path, e->first_error[0] ? e->first_error : "embree: cannot create the scene");
        embree_destroy(&e->base);
        return NULL;
    }
    return &e->base;
}
