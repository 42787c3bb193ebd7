/* The software Z-buffer anchor of Hunt & Mark 6.3 (their Pixomatic; here
 * Mesa's llvmpipe through OSMesa, bench only): the same view drawn with the
 * primitive id as a flat colour (prim + 1 in the 24 RGB bits, 0 the
 * background) into a 24-bit depth buffer, one frame = clear, draw every
 * triangle from client-side arrays (llvmpipe transforms, clips, bins and
 * rasterises them each frame, as our grid is built each frame), glFinish.
 * The projection is the camera's (rtt_camera_frame_make's frame, pixel
 * centres at +0.5 as GL samples them); near and far planes bound the scene
 * (near = far * 2^-14: what GL clips away in front of it, the grid keeps).
 * llvmpipe's threads are LP_NUM_THREADS, which Mesa reads once per process,
 * when OSMesa makes its screen: each row runs in a child process of its
 * own that sets it first (bench_llvmpipe_row), so the two-thread row really
 * draws on two threads and every row starts from a fresh screen.
 * Built only where OSMesa is (RTT_HAVE_OSMESA); elsewhere the rows report
 * themselves missing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include "bench_internal.h"
#include "rtt/shade.h"

#ifdef RTT_HAVE_OSMESA
#include <GL/gl.h>
#include <GL/osmesa.h>

bool bench_llvmpipe_available(void) { return true; }

typedef struct llvmpipe_frame {
    uint32_t vertex_count;
} llvmpipe_frame;

static void draw_frame(void *context)
{
    const llvmpipe_frame *f = context;
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLES, 0, (GLsizei)f->vertex_count);
    glFinish();
}

/* Column-major view and projection of the camera. */
static void load_matrices(const rtt_scene *scene, uint32_t width, uint32_t height)
{
    const rtt_camera *c = &scene->camera;
    rtt_camera_frame frame = rtt_camera_frame_make(c, width, height);
    rtt_vec3 right = rtt_v3_normalize(frame.du), up = rtt_v3_scale(rtt_v3_normalize(frame.dv), -1.0f);
    rtt_vec3 forward = rtt_v3_normalize(rtt_v3_cross(frame.du, frame.dv));
    const float view[16] = {right.x, up.x, -forward.x, 0, right.y, up.y, -forward.y, 0, right.z, up.z, -forward.z, 0,
                            -rtt_v3_dot(right, c->eye), -rtt_v3_dot(up, c->eye), rtt_v3_dot(forward, c->eye), 1};
    float far_plane = 0.0f;
    for (int k = 0; k < 8; k++) {
        rtt_vec3 corner = rtt_v3(k & 1 ? scene->bounds.hi.x : scene->bounds.lo.x,
                                 k & 2 ? scene->bounds.hi.y : scene->bounds.lo.y,
                                 k & 4 ? scene->bounds.hi.z : scene->bounds.lo.z);
        float d = rtt_v3_length(rtt_v3_sub(corner, c->eye));
        far_plane = d > far_plane ? d : far_plane;
    }
    far_plane = far_plane * 1.01f + 1e-30f;
    const double near_plane = far_plane * 0x1p-14;
    const double half_h = tan(0.5 * c->fov_deg * 3.14159265358979 / 180.0), half_w = half_h * width / height;
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    glFrustum(-half_w * near_plane, half_w * near_plane, -half_h * near_plane, half_h * near_plane, near_plane,
              far_plane);
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixf(view);
}

/* The row in this process (the child's part of bench_llvmpipe_row). */
static bool llvmpipe_row_here(const rtt_scene *scene, uint32_t width, uint32_t height, const bench_trace_spec *spec,
                              rtt_bench_row *row, uint32_t *result, rtt_error *err)
{
    char threads[16];
    snprintf(threads, sizeof threads, "%u", spec->threads);
    setenv("LP_NUM_THREADS", threads, 1);
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
    uint8_t *pixels = malloc((size_t)width * height * 4);
    const uint32_t vertex_count = scene->triangle_count * 3u;
    float *xyz = malloc((size_t)vertex_count * 3 * sizeof *xyz);
    uint8_t *rgba = malloc((size_t)vertex_count * 4);
    bool ok = ctx && pixels && xyz && rgba && OSMesaMakeCurrent(ctx, pixels, GL_UNSIGNED_BYTE, (GLsizei)width,
                                                                (GLsizei)height);
    if (ok) {
        for (uint32_t i = 0; i < scene->triangle_count; i++) {
            rtt_vec3 c[3];
            rtt_scene_triangle(scene, i, c);
            for (int k = 0; k < 3; k++) {
                float *p = &xyz[(3 * (size_t)i + k) * 3];
                p[0] = c[k].x, p[1] = c[k].y, p[2] = c[k].z;
                uint8_t *q = &rgba[(3 * (size_t)i + k) * 4];
                const uint32_t id = i + 1u;
                q[0] = (uint8_t)id, q[1] = (uint8_t)(id >> 8), q[2] = (uint8_t)(id >> 16), q[3] = 255;
            }
        }
        OSMesaPixelStore(OSMESA_Y_UP, 0); /* row 0 at the top, as our images */
        glViewport(0, 0, (GLsizei)width, (GLsizei)height);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        glDisable(GL_CULL_FACE);
        glDisable(GL_DITHER);
        glShadeModel(GL_FLAT);
        glClearColor(0, 0, 0, 0);
        load_matrices(scene, width, height);
        glEnableClientState(GL_VERTEX_ARRAY);
        glEnableClientState(GL_COLOR_ARRAY);
        glVertexPointer(3, GL_FLOAT, 0, xyz);
        glColorPointer(4, GL_UNSIGNED_BYTE, 0, rgba);
        llvmpipe_frame frame = {vertex_count};
        snprintf(row->variant, sizeof row->variant, "%.31s", (const char *)glGetString(GL_RENDERER));
        bench_time_frames(draw_frame, &frame, spec->warmup, spec->frames, row);
        if (result)
            for (size_t p = 0; p < (size_t)width * height; p++) {
                const uint8_t *q = &pixels[4 * p];
                const uint32_t id = (uint32_t)q[0] | (uint32_t)q[1] << 8 | (uint32_t)q[2] << 16;
                result[p] = id ? id - 1u : RTT_MISS;
            }
    }
    if (ctx) OSMesaDestroyContext(ctx);
    free(pixels);
    free(xyz);
    free(rgba);
    return ok || rtt_error_set(err, "llvmpipe: no OSMesa context of %ux%u (or out of memory)", width, height);
}

/* What the child hands back, in a shared anonymous mapping. */
typedef struct llvmpipe_shared {
    rtt_bench_row row;
    rtt_error err;
    int ok;
    uint32_t result[];
} llvmpipe_shared;

bool bench_llvmpipe_row(const rtt_scene *scene, uint32_t width, uint32_t height, const bench_trace_spec *spec,
                        rtt_bench_row *row, uint32_t *result, rtt_error *err)
{
    const size_t size = sizeof(llvmpipe_shared) + (result ? (size_t)width * height * sizeof(uint32_t) : 0);
    llvmpipe_shared *shared = mmap(NULL, size, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (shared == MAP_FAILED) return rtt_error_set(err, "llvmpipe: no memory for the row's %zu bytes", size);
    shared->row = *row;
    shared->ok = 0;
    fflush(NULL);
    const pid_t child = fork();
    if (child == 0) {
        shared->ok = llvmpipe_row_here(scene, width, height, spec, &shared->row, result ? shared->result : NULL,
                                       &shared->err);
        _exit(0);
    }
    bool ok = false;
    int status = 0;
    if (child < 0) {
        rtt_error_set(err, "llvmpipe: cannot start the row's process");
    } else if (waitpid(child, &status, 0) != child || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        rtt_error_set(err, "llvmpipe: the row's process died (%s %d)", WIFSIGNALED(status) ? "signal" : "status",
                      WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
    } else if (!shared->ok) {
        if (err) *err = shared->err;
    } else {
        *row = shared->row;
        if (result) memcpy(result, shared->result, (size_t)width * height * sizeof(uint32_t));
        ok = true;
    }
    munmap(shared, size);
    return ok;
}
#else
bool bench_llvmpipe_available(void) { return false; }

bool bench_llvmpipe_row(const rtt_scene *scene, uint32_t width, uint32_t height, const bench_trace_spec *spec,
                        rtt_bench_row *row, uint32_t *result, rtt_error *err)
{
    (void)scene, (void)width, (void)height, (void)spec, (void)row, (void)result;
    return rtt_error_set(err, "llvmpipe: not built (no OSMesa)");
}
#endif
