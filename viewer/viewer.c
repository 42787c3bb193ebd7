/* `rtt view` (viewer.h): renders continuously into an SDL2 window with the
 * chosen engine on every core.
 *
 * A frame: the keys held move the camera; when the camera or a setting has
 * changed, the frame is rendered anew; when both rest, nothing is rendered
 * (the window only waits for events).  No frame allocates: the engines are
 * built once per acceleration structure (on first use), the image and the
 * streaming texture only when the window changes size, the renderer keeps its
 * scratch in an rtt_render_cache, and the thread pool's workers persist.
 *
 * The overlay is the window title (fps, Mrays/s, the kernel and instruction
 * set, the shadow method, the resolution); `print-overlay` in a script
 * prints the same line. */
#include <SDL.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "engine/clock.h"
#include "engine/threads.h"
#include "fly_camera.h"
#include "rtt/engine.h"
#include "rtt/image.h"
#include "view_choices.h"
#include "view_script.h"
#include "viewer.h"

#define SCRIPT_SECONDS_PER_FRAME (1.0f / 30.0f)
#define LOOK_DEGREES_PER_PIXEL 0.2f
#define SPEED_STEP 2.0f
#define SRGB_LUT_SIZE 4096u
#define OVERLAY_MAX 320u

enum { HOLD_FORWARD, HOLD_BACK, HOLD_LEFT, HOLD_RIGHT, HOLD_UP, HOLD_DOWN, HOLD_COUNT };

typedef struct viewer {
    const rtt_viewer_options *opt;
    rtt_scene *scene;
    float scene_size;
    rtt_engine *engines[RTT_ACCEL_COUNT];  /* built once each, on first use */
    view_choices choices;
    rtt_render_options render;
    fly_camera camera, home;
    SDL_Window *window;
    SDL_Renderer *renderer;
    SDL_Texture *texture;
    uint32_t width, height;
    rtt_image *image;
    rtt_render_cache *cache;
    uint8_t srgb[SRGB_LUT_SIZE + 1];
    bool held[HOLD_COUNT];
    bool dirty;                 /* the picture on screen is not the current camera's and settings' */
    uint32_t target_spp;        /* samples per pixel the picture converges to at rest (--spp, default 16) */
    bool quit;
    bool scripted;
    double fps, mrays;          /* of the last rendered frame */
    uint64_t last_rays;
    uint64_t last_render_ns, last_present_ns; /* of the last frame: rtt_render, and the hand-over to SDL */
    uint32_t frames_rendered;
    uint32_t screenshots;
    char overlay[OVERLAY_MAX];
} viewer;

/* ---- engines and frames ---- */

static rtt_engine *engine_for(viewer *v, rtt_accel accel, rtt_error *err)
{
    if (v->engines[accel]) return v->engines[accel];
    rtt_engine_options eo = v->render.engine;
    eo.accel = accel;
    if (accel != RTT_ACCEL_DEFAULT) eo.given |= RTT_OPTION_ACCEL;
    eo.threads = v->render.threads;
    const uint64_t start = rtt_clock_ns();
    v->engines[accel] = rtt_engine_create(v->opt->engine, v->scene, &eo, err);
    if (v->engines[accel] && !v->scripted)
        fprintf(stderr, "rtt view: %s %s ready in %.2f s\n", v->opt->engine,
                accel == RTT_ACCEL_DEFAULT ? "engine" : rtt_accel_name(accel), 1e-9 * (double)(rtt_clock_ns() - start));
    return v->engines[accel];
}

/* The samples per pixel of a resting picture: --spp's (16 by default), 1
 * for the perspective grid, which traces pixel centres only. */
static uint32_t target_spp(const viewer *v)
{
    return v->render.engine.accel == RTT_ACCEL_PGRID ? 1u : v->target_spp;
}

static void build_overlay(viewer *v)
{
    const char *kernel = view_choices_label(&v->choices, VIEW_CHOICE_TRAVERSAL);
    const char *isa = view_choices_label(&v->choices, VIEW_CHOICE_ISA);
    char method[96];
    if (kernel[0])
        snprintf(method, sizeof method, "%s %s/%s", rtt_accel_name(v->render.engine.accel), kernel, isa[0] ? isa : "-");
    else
        snprintf(method, sizeof method, "%s", v->opt->engine);
    snprintf(v->overlay, sizeof v->overlay, "rtt view | %.1f fps | %.1f Mrays/s | %s | shadows %s | %ux%u | spp %u/%u",
             v->fps, v->mrays, method, view_choices_label(&v->choices, VIEW_CHOICE_SHADOWS), v->width, v->height,
             rtt_render_spp(&v->render), target_spp(v));
}

static void present(viewer *v)
{
    void *pixels = NULL;
    int pitch = 0;
    if (SDL_LockTexture(v->texture, NULL, &pixels, &pitch) != 0) return;
    const float *rgb = v->image->rgb;
    for (uint32_t y = 0; y < v->height; y++) {
        uint32_t *row = (uint32_t *)((uint8_t *)pixels + (size_t)y * (size_t)pitch);
        for (uint32_t x = 0; x < v->width; x++) {
            const float *p = rgb + 3 * ((size_t)y * v->width + x);
            uint32_t c[3];
            for (int k = 0; k < 3; k++) {
                float f = p[k] > 0.0f ? (p[k] < 1.0f ? p[k] : 1.0f) : 0.0f; /* NaN → 0 */
                c[k] = v->srgb[(uint32_t)(f * (float)SRGB_LUT_SIZE + 0.5f)];
            }
            row[x] = 0xFF000000u | c[0] << 16 | c[1] << 8 | c[2];
        }
    }
    SDL_UnlockTexture(v->texture);
    SDL_RenderClear(v->renderer);
    SDL_RenderCopy(v->renderer, v->texture, NULL, NULL);
    SDL_RenderPresent(v->renderer);
}

/* Renders the current camera and settings; a setting the engine refuses is
 * reported once and the previous one restored by the caller. */
static bool render_frame(viewer *v, rtt_error *err)
{
    /* the scene is the viewer's: its camera is the one field the viewer changes */
    v->scene->camera = fly_camera_to(&v->camera);
    rtt_engine *engine = engine_for(v, v->render.engine.accel, err);
    if (!engine) return false;
    rtt_render_stats stats;
    const uint64_t start = rtt_clock_ns();
    if (!rtt_render(engine, &v->render, v->image, &stats, err)) return false;
    const uint64_t rendered = rtt_clock_ns();
    present(v);
    const uint64_t end = rtt_clock_ns();
    v->last_render_ns = rendered - start;
    v->last_present_ns = end - rendered;
    const double seconds = 1e-9 * (double)(end - start);
    v->last_rays = stats.primary_rays + stats.shadow_rays + stats.secondary_rays;
    v->fps = seconds > 0 ? 1.0 / seconds : 0.0;
    v->mrays = seconds > 0 ? 1e-6 * (double)v->last_rays / seconds : 0.0;
    v->frames_rendered++;
    v->dirty = false;
    build_overlay(v);
    SDL_SetWindowTitle(v->window, v->overlay);
    return true;
}

/* ---- window and image size ---- */

static bool resize(viewer *v, uint32_t width, uint32_t height, rtt_error *err)
{
    if (width == v->width && height == v->height && v->image) return true;
    rtt_image *image = rtt_image_create(width, height, 0, err);
    if (!image) return false;
    SDL_Texture *texture = SDL_CreateTexture(v->renderer, SDL_PIXELFORMAT_ARGB8888, SDL_TEXTUREACCESS_STREAMING,
                                             (int)width, (int)height);
    if (!texture) {
        rtt_image_free(image);
        return rtt_error_set(err, "cannot make a %ux%u texture: %s", width, height, SDL_GetError());
    }
    if (v->texture) SDL_DestroyTexture(v->texture);
    rtt_image_free(v->image);
    v->texture = texture;
    v->image = image;
    v->width = width;
    v->height = height;
    v->render.width = width;
    v->render.height = height;
    v->dirty = true;
    return true;
}

/* ---- keys and mouse ---- */

static int hold_of(SDL_Keycode key)
{
    switch (key) {
    case SDLK_w: case SDLK_UP: return HOLD_FORWARD;
    case SDLK_s: case SDLK_DOWN: return HOLD_BACK;
    case SDLK_a: case SDLK_LEFT: return HOLD_LEFT;
    case SDLK_d: case SDLK_RIGHT: return HOLD_RIGHT;
    case SDLK_e: case SDLK_r: return HOLD_UP;
    case SDLK_q: case SDLK_f: return HOLD_DOWN;
    default: return -1;
    }
}

/* The camera as a views.json entry, in the scene's own coordinates (the
 * scene stores them relative to its origin: rtt/scene.h). */
static void print_camera(viewer *v, const char *name)
{
    rtt_camera c = fly_camera_to(&v->camera);
    double eye[3], at[3];
    rtt_scene_point_from_stored(v->scene, c.eye, eye);
    rtt_scene_point_from_stored(v->scene, c.look_at, at);
    printf("\"%s\": {\"camera\": {\"eye\": [%.9g, %.9g, %.9g], \"look_at\": [%.9g, %.9g, %.9g], "
           "\"up\": [%.9g, %.9g, %.9g], \"fov\": %.9g}}\n",
           name, eye[0], eye[1], eye[2], at[0], at[1], at[2], c.up.x, c.up.y, c.up.z, c.fov_deg);
    fflush(stdout);
}

/* The screenshot key: the next free rtt-view-NNNN.png and .exr in the
 * current directory, and the camera as a views.json entry. */
static void screenshot_key(viewer *v)
{
    char png[64], exr[64], name[32];
    for (;;) {
        v->screenshots++;
        snprintf(name, sizeof name, "rtt-view-%04u", v->screenshots);
        snprintf(png, sizeof png, "%s.png", name);
        snprintf(exr, sizeof exr, "%s.exr", name);
        FILE *f = fopen(png, "rb"), *g = fopen(exr, "rb");
        if (f) fclose(f);
        if (g) fclose(g);
        if (!f && !g) break;
        if (v->screenshots > 9999) return;
    }
    rtt_error err = {{0}};
    if (!rtt_image_write(v->image, png, &err) || !rtt_image_write(v->image, exr, &err)) {
        fprintf(stderr, "rtt view: %s\n", err.message);
        return;
    }
    printf("screenshot: %s, %s\n", png, exr);
    print_camera(v, name);
}

/* Takes the choices `c` when the engine accepts them; else says why and
 * keeps the current ones. */
static bool take_choices(viewer *v, const view_choices *c, rtt_error *err)
{
    rtt_render_options trial = v->render;
    view_choices_apply(c, &trial);
    if (!rtt_render_options_check(v->opt->engine, &trial, err)) return false;
    v->choices = *c;
    v->render = trial;
    v->dirty = true;
    return true;
}

static void step_choice(viewer *v, view_choice which, int step)
{
    view_choices next = v->choices;
    if (!view_choices_step(&next, which, step)) return;
    rtt_error err = {{0}};
    if (!take_choices(v, &next, &err)) fprintf(stderr, "rtt view: %s\n", err.message);
}

static void on_key_down(viewer *v, const SDL_KeyboardEvent *key)
{
    const int hold = hold_of(key->keysym.sym);
    if (hold >= 0) {
        v->held[hold] = true;
        return;
    }
    const int step = key->keysym.mod & KMOD_SHIFT ? -1 : 1;
    switch (key->keysym.sym) {
    case SDLK_ESCAPE: v->quit = true; break;
    case SDLK_HOME: v->camera = v->home; v->dirty = true; break;
    case SDLK_EQUALS: case SDLK_PLUS: case SDLK_KP_PLUS: case SDLK_RIGHTBRACKET:
        fly_camera_scale_speed(&v->camera, SPEED_STEP, v->scene_size);
        break;
    case SDLK_MINUS: case SDLK_KP_MINUS: case SDLK_LEFTBRACKET:
        fly_camera_scale_speed(&v->camera, 1.0f / SPEED_STEP, v->scene_size);
        break;
    case SDLK_t: step_choice(v, VIEW_CHOICE_TRAVERSAL, step); break;
    case SDLK_g: step_choice(v, VIEW_CHOICE_SHADOWS, step); break;
    case SDLK_i: step_choice(v, VIEW_CHOICE_ISA, step); break;
    case SDLK_p: case SDLK_F12: screenshot_key(v); break;
    case SDLK_c: print_camera(v, "view"); break;
    default: break;
    }
}

static void handle_event(viewer *v, const SDL_Event *e, rtt_error *err, bool *ok)
{
    switch (e->type) {
    case SDL_QUIT: v->quit = true; break;
    case SDL_KEYDOWN: if (!e->key.repeat) on_key_down(v, &e->key); break;
    case SDL_KEYUP: {
        const int hold = hold_of(e->key.keysym.sym);
        if (hold >= 0) v->held[hold] = false;
        break;
    }
    case SDL_MOUSEMOTION:
        if (e->motion.state) {
            fly_camera_turn(&v->camera, LOOK_DEGREES_PER_PIXEL * (float)e->motion.xrel,
                            -LOOK_DEGREES_PER_PIXEL * (float)e->motion.yrel);
            v->dirty = true;
        }
        break;
    case SDL_WINDOWEVENT:
        if (e->window.event == SDL_WINDOWEVENT_SIZE_CHANGED && e->window.data1 > 0 && e->window.data2 > 0)
            *ok = *ok && resize(v, (uint32_t)e->window.data1, (uint32_t)e->window.data2, err);
        if (e->window.event == SDL_WINDOWEVENT_EXPOSED) v->dirty = true;
        break;
    default: break;
    }
}

static bool pump_events(viewer *v, rtt_error *err)
{
    SDL_Event e;
    bool ok = true;
    while (SDL_PollEvent(&e)) handle_event(v, &e, err, &ok);
    return ok;
}

static void move_camera(viewer *v, float seconds)
{
    const float forward = (float)v->held[HOLD_FORWARD] - (float)v->held[HOLD_BACK];
    const float right = (float)v->held[HOLD_RIGHT] - (float)v->held[HOLD_LEFT];
    const float upward = (float)v->held[HOLD_UP] - (float)v->held[HOLD_DOWN];
    if (forward == 0.0f && right == 0.0f && upward == 0.0f) return;
    fly_camera_move(&v->camera, forward, right, upward, seconds);
    v->dirty = true;
}

/* Whether the resting picture has fewer samples than it converges to. */
static bool refining(const viewer *v)
{
    return rtt_render_spp(&v->render) < target_spp(v);
}

/* One step of the loop: events, movement, and a render when something
 * changed (one sample per pixel, so moving stays fast), when the resting
 * picture can converge further (twice the samples of the last, up to the
 * target: each such frame is exactly `rtt render --spp N`'s image), or when
 * `force` (benchmarks: the same frame again). */
static bool frame(viewer *v, float seconds, bool force, rtt_error *err)
{
    if (!pump_events(v, err)) return false;
    move_camera(v, seconds);
    if (v->dirty) {
        v->render.spp = 1;
    } else if (refining(v)) {
        const uint32_t doubled = 2u * rtt_render_spp(&v->render), target = target_spp(v);
        v->render.spp = doubled < target ? doubled : target;
    } else if (!force) {
        return true;
    }
    return render_frame(v, err);
}

/* ---- scripts ---- */

static void push_key(const char *name, bool down)
{
    SDL_Event e;
    memset(&e, 0, sizeof e);
    e.type = down ? SDL_KEYDOWN : SDL_KEYUP;
    e.key.state = down ? SDL_PRESSED : SDL_RELEASED;
    e.key.keysym.sym = SDL_GetKeyFromName(name);
    e.key.keysym.scancode = SDL_GetScancodeFromKey(e.key.keysym.sym);
    SDL_PushEvent(&e);
}

static void print_choices(const view_choices *c)
{
    printf("traversals:");
    for (uint32_t i = 0; i < c->traversal_count; i++)
        printf(" %s:%s", rtt_accel_name(c->traversals[i].accel), c->traversals[i].name);
    printf("\nshadows:");
    for (uint32_t i = 0; i < c->shadow_count; i++) printf(" %s", c->shadows[i]);
    printf("\nisas:");
    for (uint32_t i = 0; i < c->isa_count; i++) printf(" %s", rtt_isa_name(c->isas[i]));
    printf("\n");
    fflush(stdout);
}

static bool run_frames(viewer *v, int32_t n, bool force, rtt_error *err)
{
    for (int32_t i = 0; i < n && !v->quit; i++)
        if (!frame(v, SCRIPT_SECONDS_PER_FRAME, force, err)) return false;
    return true;
}

static bool run_bench(viewer *v, int32_t n, rtt_error *err)
{
    const uint64_t start = rtt_clock_ns();
    uint64_t rays = 0, render_ns = 0, present_ns = 0;
    for (int32_t i = 0; i < n; i++) {
        if (!frame(v, 0.0f, true, err)) return false;
        rays += v->last_rays;
        render_ns += v->last_render_ns;
        present_ns += v->last_present_ns;
    }
    const double seconds = 1e-9 * (double)(rtt_clock_ns() - start);
    const char *kernel = view_choices_label(&v->choices, VIEW_CHOICE_TRAVERSAL);
    /* the frame's two parts, a frame's mean: rtt_render, and the texture update and present */
    printf("bench: %d frames, %.2f fps, %.2f Mrays/s, %s %s/%s, shadows %s, %ux%u, threads %u, render %.2f ms, "
           "present %.2f ms\n",
           n,
           seconds > 0 ? n / seconds : 0.0, seconds > 0 ? 1e-6 * (double)rays / seconds : 0.0,
           rtt_accel_name(v->render.engine.accel), kernel[0] ? kernel : v->opt->engine,
           view_choices_label(&v->choices, VIEW_CHOICE_ISA), view_choices_label(&v->choices, VIEW_CHOICE_SHADOWS),
           v->width, v->height, rtt_thread_count(v->render.threads), n > 0 ? 1e-6 * (double)render_ns / n : 0.0,
           n > 0 ? 1e-6 * (double)present_ns / n : 0.0);
    fflush(stdout);
    return true;
}

static bool run_command(viewer *v, const view_command *c, rtt_error *err)
{
    switch (c->kind) {
    case VIEW_CMD_FRAMES: return run_frames(v, c->a, false, err);
    case VIEW_CMD_KEY:
        if (SDL_GetKeyFromName(c->text) == SDLK_UNKNOWN)
            return rtt_error_set(err, "%s:%u: unknown key \"%s\" (SDL key names: w, t, Home, F12, Left, ...)",
                                 v->opt->script_path, c->line, c->text);
        push_key(c->text, true);
        if (c->b > 0) {
            if (!run_frames(v, c->b, false, err)) return false;
            push_key(c->text, false);
            return pump_events(v, err);
        }
        push_key(c->text, false);
        return run_frames(v, 1, false, err);
    case VIEW_CMD_DRAG: {
        SDL_Event e;
        memset(&e, 0, sizeof e);
        e.type = SDL_MOUSEMOTION;
        e.motion.state = SDL_BUTTON_LMASK;
        e.motion.xrel = c->a;
        e.motion.yrel = c->b;
        SDL_PushEvent(&e);
        return run_frames(v, 1, false, err);
    }
    case VIEW_CMD_RESIZE: {
        SDL_SetWindowSize(v->window, c->a, c->b);
        /* the window manager answers asynchronously: wait up to a second for it */
        for (int i = 0; i < 100; i++) {
            int w = 0, h = 0;
            SDL_GetWindowSize(v->window, &w, &h);
            if (w == c->a && h == c->b) break;
            SDL_Delay(10);
            if (!pump_events(v, err)) return false;
        }
        int w = 0, h = 0;
        SDL_GetWindowSize(v->window, &w, &h);
        if (!resize(v, (uint32_t)w, (uint32_t)h, err)) return false;
        return run_frames(v, 1, false, err);
    }
    case VIEW_CMD_SET: {
        view_choices next = v->choices;
        static const char *const whats[] = {"traversal", "shadows", "isa"};
        if (!view_choices_select(&next, (view_choice)c->what, c->text))
            return rtt_error_set(err, "%s:%u: set %s %s: not offered by engine \"%s\" here", v->opt->script_path,
                                 c->line, whats[c->what], c->text, v->opt->engine);
        rtt_error why = {{0}};
        if (!take_choices(v, &next, &why))
            return rtt_error_set(err, "%s:%u: set %s %s: %s", v->opt->script_path, c->line, whats[c->what], c->text,
                                 why.message);
        return run_frames(v, 1, false, err);
    }
    case VIEW_CMD_CONVERGE:
        for (int i = 0; i < 16 && (v->dirty || refining(v)); i++)
            if (!frame(v, 0.0f, false, err)) return false;
        return true;
    case VIEW_CMD_BENCH: return run_bench(v, c->a, err);
    case VIEW_CMD_PRINT_OVERLAY:
        build_overlay(v);
        printf("%s\n", v->overlay);
        fflush(stdout);
        return true;
    case VIEW_CMD_PRINT_CAMERA: print_camera(v, "view"); return true;
    case VIEW_CMD_PRINT_CHOICES: print_choices(&v->choices); return true;
    case VIEW_CMD_SCREENSHOT: return rtt_image_write(v->image, c->text, err);
    }
    return true;
}

static bool run_script(viewer *v, rtt_error *err)
{
    view_script script;
    if (!view_script_load(v->opt->script_path, &script, err)) return false;
    bool ok = frame(v, 0.0f, true, err);
    for (uint32_t i = 0; ok && i < script.count && !v->quit; i++) ok = run_command(v, &script.commands[i], err);
    view_script_free(&script);
    if (ok && v->opt->screenshot_path) ok = rtt_image_write(v->image, v->opt->screenshot_path, err);
    return ok;
}

static bool run_interactive(viewer *v, rtt_error *err)
{
    uint64_t last = rtt_clock_ns();
    while (!v->quit) {
        const bool moving = v->held[HOLD_FORWARD] || v->held[HOLD_BACK] || v->held[HOLD_LEFT] ||
                            v->held[HOLD_RIGHT] || v->held[HOLD_UP] || v->held[HOLD_DOWN];
        if (!moving && !v->dirty && !refining(v)) SDL_WaitEventTimeout(NULL, 100); /* at rest: sleep until something happens */
        const uint64_t now = rtt_clock_ns();
        const float seconds = (float)(1e-9 * (double)(now - last));
        last = now;
        if (!frame(v, seconds > 0.25f ? 0.25f : seconds, false, err)) return false;
    }
    return true;
}

/* ---- setup ---- */

static void make_srgb_table(viewer *v)
{
    for (uint32_t i = 0; i <= SRGB_LUT_SIZE; i++) v->srgb[i] = rtt_linear_to_srgb8((float)i / (float)SRGB_LUT_SIZE);
}

static void close_viewer(viewer *v)
{
    for (int a = 0; a < RTT_ACCEL_COUNT; a++) rtt_engine_destroy(v->engines[a]);
    rtt_render_cache_destroy(v->cache);
    rtt_image_free(v->image);
    if (v->texture) SDL_DestroyTexture(v->texture);
    if (v->renderer) SDL_DestroyRenderer(v->renderer);
    if (v->window) SDL_DestroyWindow(v->window);
    SDL_Quit();
}

bool rtt_viewer_run(rtt_scene *scene, const rtt_viewer_options *opt, rtt_error *err)
{
    static viewer v; /* large (the sRGB table); one viewer per process */
    memset(&v, 0, sizeof v);
    v.opt = opt;
    v.scene = scene;
    v.scripted = opt->script_path != NULL;
    v.render = opt->render;
    v.target_spp = opt->render.spp ? opt->render.spp : 16u;
    v.render.spp = 1;
    v.scene_size = rtt_v3_length(rtt_v3_sub(scene->bounds.hi, scene->bounds.lo));
    v.camera = v.home = fly_camera_from(&scene->camera, v.scene_size);
    make_srgb_table(&v);
    const uint32_t width = opt->render.width ? opt->render.width : scene->width;
    const uint32_t height = opt->render.height ? opt->render.height : scene->height;

    /* the first engine first: the choices start from the kernel it reports */
    rtt_engine *first = engine_for(&v, v.render.engine.accel, err);
    if (!first ||
        !view_choices_make(opt->engine, &v.render, opt->shadows_text, rtt_engine_kernel_name(first), &v.choices, err)) {
        close_viewer(&v);
        return false;
    }
    view_choices_apply(&v.choices, &v.render);
    if (v.render.engine.accel != RTT_ACCEL_DEFAULT && !v.engines[v.render.engine.accel]) {
        /* the default accel's engine is the one the choices name */
        v.engines[v.render.engine.accel] = first;
        v.engines[RTT_ACCEL_DEFAULT] = NULL;
    }
    v.cache = rtt_render_cache_create();
    if (!v.cache) {
        close_viewer(&v);
        return rtt_error_set(err, "out of memory");
    }

    if (SDL_Init(SDL_INIT_VIDEO) != 0) {
        rtt_error_set(err, "cannot open a window: %s (no display? scripts run headless under xvfb-run)",
                      SDL_GetError());
        close_viewer(&v);
        return false;
    }
    v.window = SDL_CreateWindow("rtt view", SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, (int)width, (int)height,
                                SDL_WINDOW_RESIZABLE);
    v.renderer = v.window ? SDL_CreateRenderer(v.window, -1, 0) : NULL;
    if (!v.renderer) {
        rtt_error_set(err, "cannot open a window: %s", SDL_GetError());
        close_viewer(&v);
        return false;
    }
    bool ok = resize(&v, width, height, err);
    if (ok) ok = v.scripted ? run_script(&v, err) : run_interactive(&v, err);
    close_viewer(&v);
    return ok;
}
