/* Helpers shared by the harnesses: temporary files, the error contract and
 * the scene model's invariants (see fuzz_common.h). */
#include "fuzz_common.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

void fuzz_fail(const char *fmt, ...)
{
    va_list args;
    va_start(args, fmt);
    fputs("fuzz: ", stderr);
    vfprintf(stderr, fmt, args);
    fputc('\n', stderr);
    va_end(args);
    abort();
}

void fuzz_check_error_line(const rtt_error *err)
{
    size_t n = strnlen(err->message, sizeof err->message);
    if (n == 0)
        fuzz_fail("loader failed without a message");
    if (n == sizeof err->message)
        fuzz_fail("error message is not terminated");
    if (strchr(err->message, '\n'))
        fuzz_fail("error message spans lines: %s", err->message);
}

rtt_scene *fuzz_load_scene_bytes(const uint8_t *data, size_t size, const char *extension, rtt_error *err)
{
    const char *dir = getenv("TMPDIR");
    char path[512];
    snprintf(path, sizeof path, "%s/rtt_fuzz_XXXXXX%s", dir && dir[0] ? dir : "/tmp", extension);
    int fd = mkstemps(path, (int)strlen(extension));
    if (fd < 0)
        fuzz_fail("cannot create a temporary file %s", path);
    for (size_t done = 0; done < size;) {
        ssize_t n = write(fd, data + done, size - done);
        if (n <= 0)
            fuzz_fail("cannot write %s", path);
        done += (size_t)n;
    }
    close(fd);
    err->message[0] = '\0';
    rtt_scene *scene = rtt_scene_load(path, NULL, err);
    unlink(path);
    if (!scene)
        fuzz_check_error_line(err);
    return scene;
}

void fuzz_check_scene(const rtt_scene *scene)
{
    if (scene->material_count < 1 || scene->light_count < 1)
        fuzz_fail("scene has %u materials and %u lights", scene->material_count, scene->light_count);
    for (uint32_t i = 0; i < scene->vertex_count; i++)
        if (!rtt_v3_is_finite(scene->vertices[i]))
            fuzz_fail("vertex %u is not finite", i);
    for (uint32_t i = 0; i < scene->triangle_count; i++) {
        for (int k = 0; k < 3; k++)
            if (scene->triangles[i].v[k] >= scene->vertex_count)
                fuzz_fail("triangle %u vertex %u out of range", i, scene->triangles[i].v[k]);
        if (scene->triangle_material && scene->triangle_material[i] >= scene->material_count)
            fuzz_fail("triangle %u material out of range", i);
        if (scene->triangle_mesh && scene->triangle_mesh[i] >= scene->mesh_count)
            fuzz_fail("triangle %u mesh out of range", i);
    }
    uint32_t next = 0;
    for (uint32_t m = 0; m < scene->mesh_count; m++) {
        if (scene->meshes[m].first_triangle != next)
            fuzz_fail("mesh %u starts at %u, expected %u", m, scene->meshes[m].first_triangle, next);
        if (scene->meshes[m].material >= scene->material_count)
            fuzz_fail("mesh %u material out of range", m);
        next += scene->meshes[m].triangle_count;
    }
    if (scene->mesh_count && next != scene->triangle_count)
        fuzz_fail("meshes cover %u of %u triangles", next, scene->triangle_count);
    for (uint32_t i = 0; i < scene->light_count; i++)
        if (!rtt_v3_is_finite(scene->lights[i].position) || !isfinite(scene->lights[i].radius))
            fuzz_fail("light %u is not finite", i);
    if (!rtt_v3_is_finite(scene->camera.eye) || !rtt_v3_is_finite(scene->camera.look_at) ||
        !isfinite(scene->camera.fov_deg))
        fuzz_fail("camera is not finite");
    if (scene->width == 0 || scene->height == 0)
        fuzz_fail("image size %ux%u", scene->width, scene->height);
}
