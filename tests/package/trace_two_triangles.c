/* What a library user writes: two triangles, each registered engine by name,
 * rays through them, the hits checked.  Exit 0 when every engine answers
 * every ray as expected, else one line on stderr and 1. */
#include <math.h>
#include <stdio.h>

#include <rtt/rtt.h>

static int check_engine(const char *name, const rtt_scene *scene)
{
    rtt_error err = {{0}};
    rtt_engine *engine = rtt_engine_create(name, scene, NULL, &err);
    if (!engine) {
        fprintf(stderr, "%s: %s\n", name, err.message);
        return 1;
    }
    /* down the z axis: through triangle 0 at z = 1, triangle 1 at z = 2, and past both */
    const rtt_ray rays[3] = {
        {{0.25f, 0.25f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, INFINITY},
        {{0.25f, 0.25f, 1.5f}, {0.0f, 0.0f, 1.0f}, 0.0f, INFINITY},
        {{5.0f, 5.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, 0.0f, INFINITY},
    };
    const uint32_t want_prim[3] = {0, 1, RTT_MISS};
    const float want_t[3] = {1.0f, 0.5f, INFINITY};
    rtt_hit hits[3];
    uint8_t occluded[3];
    rtt_engine_intersect(engine, rays, hits, 3);
    rtt_engine_occluded(engine, rays, occluded, 3);
    int bad = 0;
    for (int i = 0; i < 3; i++) {
        if (hits[i].prim != want_prim[i] || !(fabsf(hits[i].t - want_t[i]) <= 1e-5f || hits[i].t == want_t[i]) ||
            occluded[i] != (want_prim[i] != RTT_MISS)) {
            fprintf(stderr, "%s ray %d: prim %u t %g occluded %u\n", name, i, hits[i].prim, (double)hits[i].t,
                    occluded[i]);
            bad = 1;
        }
    }
    printf("%s (%s): %s\n", name, rtt_engine_kernel_name(engine), bad ? "wrong" : "3 rays right");
    rtt_engine_destroy(engine);
    return bad;
}

int main(void)
{
    rtt_error err = {{0}};
    if (!rtt_builtin_engines_register(&err)) {
        fprintf(stderr, "register: %s\n", err.message);
        return 1;
    }
    const float xyz9[2 * 9] = {
        -1, -1, 1, 2, -1, 1, -1, 2, 1, /* z = 1 */
        -1, -1, 2, 2, -1, 2, -1, 2, 2, /* z = 2 */
    };
    rtt_scene *scene = rtt_scene_from_triangles(xyz9, 2, &err);
    if (!scene || !rtt_scene_finish(scene, &err)) {
        fprintf(stderr, "scene: %s\n", err.message);
        return 1;
    }
    int bad = check_engine("reference", scene) | check_engine("optimized", scene);
    rtt_scene_free(scene);
    return bad;
}
