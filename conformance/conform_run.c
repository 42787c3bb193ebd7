/* Running the conformance suite on one scene: the engine list, every engine
 * on every selected ray set, each compared with the reference. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "conform.h"

void rtt_conform_config_default(rtt_conform_config *config)
{
    memset(config, 0, sizeof *config);
    for (int i = 0; i < RTT_CONFORM_RAY_SET_COUNT; i++) config->sets[i] = i != RTT_CONFORM_FILE;
    config->engines = NULL;
    config->max_rays = 0;
    config->seed = 0x5EED0001ull;
}

const char *rtt_conform_default_engines(void)
{
#ifdef RTT_HAVE_EMBREE
    return "optimized,embree";
#else
    return "optimized";
#endif
}

/* The acceleration structure whose kernel table names `kernel` (the
 * default's first: kernel names are unique across an engine's tables). */
static rtt_accel kernel_accel(const rtt_engine_class *cls, const char *kernel)
{
    const char *name;
    for (int a = RTT_ACCEL_DEFAULT; cls->kernel && kernel && a < RTT_ACCEL_COUNT; a++)
        for (uint32_t k = 0; (name = cls->kernel((rtt_accel)a, k)); k++)
            if (strcmp(name, kernel) == 0) return (rtt_accel)a;
    return RTT_ACCEL_DEFAULT;
}

/* One spec: engine `cls`, kernel `kernel` (NULL: the engine's default). */
static void spec_make(rtt_conform_engine_spec *spec, const rtt_engine_class *cls, const char *kernel)
{
    spec->name = cls->name;
    rtt_engine_options_default(&spec->opt);
    spec->opt.accel = kernel_accel(cls, kernel);
    if (spec->opt.accel != RTT_ACCEL_DEFAULT) spec->opt.given |= RTT_OPTION_ACCEL;
    if (kernel) {
        snprintf(spec->opt.traversal, sizeof spec->opt.traversal, "%s", kernel);
        spec->opt.given |= RTT_OPTION_TRAVERSAL;
        snprintf(spec->label, sizeof spec->label, "%s/%s", cls->name, kernel);
    } else {
        snprintf(spec->label, sizeof spec->label, "%s", cls->name);
    }
}

int rtt_conform_expand_engines(const char *list, rtt_conform_engine_spec *specs, int cap, rtt_error *err)
{
    char buffer[512];
    if (strlen(list) >= sizeof buffer) return rtt_error_set(err, "engine list: too long"), -1;
    strcpy(buffer, list);
    int n = 0;
    char *save = NULL;
    for (char *item = strtok_r(buffer, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        char *kernel = strchr(item, '/');
        if (kernel) *kernel++ = '\0';
        const rtt_engine_class *cls = rtt_engine_find(item);
        if (!cls) {
            rtt_engine_options_check(item, &(rtt_engine_options){0}, err);
            return -1;
        }
        if (!kernel && cls->kernel) { /* an engine with kernels: every one of every structure */
            const char *name;
            for (int a = RTT_ACCEL_DEFAULT; a < RTT_ACCEL_COUNT; a++) {
                if (a == RTT_ACCEL_KD) continue; /* the default's table */
                for (uint32_t k = 0; (name = cls->kernel((rtt_accel)a, k)); k++, n++) {
                    if (n >= cap) return rtt_error_set(err, "engine list: more than %d engines", cap), -1;
                    spec_make(&specs[n], cls, name);
                }
            }
            continue;
        }
        if (n >= cap) return rtt_error_set(err, "engine list: more than %d engines", cap), -1;
        spec_make(&specs[n], cls, kernel);
        if (!rtt_engine_options_check(cls->name, &specs[n].opt, err)) return -1;
        n++;
    }
    if (n == 0) return rtt_error_set(err, "engine list: no engine named"), -1;
    return n;
}

/* One engine option (its RTT_OPTION_* bit) for each spec whose engine reads it. */
static void give_option(rtt_conform_engine_spec *spec, uint32_t bit, rtt_isa isa, rtt_isect isect)
{
    const rtt_engine_class *cls = rtt_engine_find(spec->name);
    if (!cls || !(cls->uses & bit)) return;
    if (bit == RTT_OPTION_ISA) spec->opt.isa = isa;
    if (bit == RTT_OPTION_ISECT) spec->opt.isect = isect;
    spec->opt.given |= bit;
}

void rtt_conform_specs_set_isa(rtt_conform_engine_spec *specs, int count, rtt_isa isa, rtt_isect isect)
{
    for (int i = 0; i < count; i++) {
        if (isa != RTT_ISA_AUTO) give_option(&specs[i], RTT_OPTION_ISA, isa, isect);
        if (isect != RTT_ISECT_DEFAULT) give_option(&specs[i], RTT_OPTION_ISECT, isa, isect);
    }
}

bool rtt_conform_engines_valid(const char *engines, rtt_error *err)
{
    rtt_conform_engine_spec specs[64];
    return rtt_conform_expand_engines(engines, specs, 64, err) > 0;
}

static rtt_conform_row *add_row(rtt_conform_report *report, const char *engine, rtt_conform_ray_set set,
                                rtt_error *err)
{
    if (report->row_count == report->row_cap) {
        size_t cap = report->row_cap ? report->row_cap * 2 : 16;
        rtt_conform_row *rows = realloc(report->rows, cap * sizeof *rows);
        if (!rows) return rtt_error_set(err, "out of memory for the report"), NULL;
        report->rows = rows;
        report->row_cap = cap;
    }
    rtt_conform_row *row = &report->rows[report->row_count++];
    memset(row, 0, sizeof *row);
    snprintf(row->engine, sizeof row->engine, "%.39s", engine);
    snprintf(row->oracle, sizeof row->oracle, "reference");
    row->set = set;
    row->engine_is_embree_row = strcmp(engine, "embree") == 0;
    /* The extreme set aims half its rays exactly at edges and vertices:
     * there grazing hit/miss is what it measures, so it is reported, not
     * bounded (conformance/README.md); every other rule still holds. */
    if (set == RTT_CONFORM_EXTREME)
        row->grazing_limit = 1.0;
    else
        row->grazing_limit = strcmp(engine, "embree") == 0 ? RTT_CONFORM_GRAZING_SHARE_EMBREE
                                                           : RTT_CONFORM_GRAZING_SHARE_OPTIMIZED;
    return row;
}

/* Rays, the reference's hits on them and the referee's answers, per set. */
typedef struct ray_set_data {
    rtt_ray *rays;
    rtt_hit *oracle;
    size_t count;
    bool used;           /* the set is traced in this run */
    rtt_conform_referee_cache referee;
    int64_t *file_index; /* per ray: its record in the failing-rays file, -1 when not in it */
} ray_set_data;

static void run_engine(const rtt_scene *scene, const rtt_conform_engine_spec *spec, bool every_ray, ray_set_data *data,
                       rtt_conform_report *report, rtt_error *err, bool *ok)
{
    rtt_error engine_err = {{0}};
    rtt_engine *engine = rtt_engine_create(spec->name, scene, &spec->opt, &engine_err);
    for (int s = 0; s < RTT_CONFORM_RAY_SET_COUNT && *ok; s++) {
        if (!data[s].used) continue;
        rtt_conform_row *row = add_row(report, spec->label, (rtt_conform_ray_set)s, err);
        if (!row) {
            *ok = false;
            break;
        }
        if (!engine) {
            snprintf(row->error, sizeof row->error, "cannot create: %.230s",
                     engine_err.message[0] ? engine_err.message : "(no message)");
            rtt_conform_row_judge(row);
            continue;
        }
        size_t n = data[s].count;
        rtt_hit *hits = malloc((n ? n : 1) * sizeof *hits);
        uint8_t *occluded = malloc(n ? n : 1);
        if (!hits || !occluded) {
            snprintf(row->error, sizeof row->error, "out of memory");
        } else {
            rtt_engine_intersect(engine, data[s].rays, hits, n);
            rtt_engine_occluded(engine, data[s].rays, occluded, n);
            rtt_conform_judging judging = {.referee = &data[s].referee,
                                           .engine_is_embree = strcmp(spec->name, "embree") == 0, .collect = true,
                                           .every_ray = every_ray};
            if (!rtt_conform_compare_judged(scene, data[s].rays, hits, occluded, data[s].oracle, n, row, &judging))
                snprintf(row->error, sizeof row->error, "out of memory for the referee");
        }
        free(hits);
        free(occluded);
        rtt_conform_row_judge(row);
    }
    rtt_engine_destroy(engine);
}

/* The errors of every failing row, each ray once, in row order: the
 * failing-rays file, and each named ray's record in it. */
static bool gather_failing_rays(const rtt_scene *scene, ray_set_data *data, rtt_conform_report *report, rtt_error *err)
{
    size_t total = 0;
    for (size_t i = 0; i < report->row_count; i++)
        if (!report->rows[i].pass) total += report->rows[i].error_ray_count;
    report->failing_rays = malloc((total ? total : 1) * sizeof *report->failing_rays);
    if (!report->failing_rays) return rtt_error_set(err, "%s: out of memory for the failing rays", scene->path);
    for (size_t i = 0; i < report->row_count; i++) {
        rtt_conform_row *row = &report->rows[i];
        if (row->pass || row->error_ray_count == 0) continue;
        ray_set_data *d = &data[row->set];
        if (!d->file_index) {
            d->file_index = malloc((d->count ? d->count : 1) * sizeof *d->file_index);
            if (!d->file_index) return rtt_error_set(err, "%s: out of memory for the failing rays", scene->path);
            for (size_t k = 0; k < d->count; k++) d->file_index[k] = -1;
        }
        for (size_t k = 0; k < row->error_ray_count; k++) {
            uint32_t ray = row->error_rays[k];
            if (d->file_index[ray] >= 0) continue;
            d->file_index[ray] = (int64_t)report->failing_ray_count;
            rtt_ray scene_ray = d->rays[ray], back;
            rtt_rays_from_stored(scene, &scene_ray, 1);
            back = scene_ray;
            rtt_rays_to_stored(scene, &back, 1);
            if (memcmp(back.org, d->rays[ray].org, sizeof back.org) != 0) report->failing_rays_inexact++;
            report->failing_rays[report->failing_ray_count++] = scene_ray;
        }
        for (size_t k = 0; k < row->failing_count; k++) row->failing[k].file_index = d->file_index[row->failing[k].index];
    }
    return true;
}

bool rtt_conform_run(const rtt_scene *scene, const rtt_conform_config *config, rtt_conform_report *report,
                     rtt_error *err)
{
    memset(report, 0, sizeof *report);
    snprintf(report->scene, sizeof report->scene, "%s", scene->path);
    report->triangles = scene->triangle_count;
    report->magnitude = rtt_conform_scene_magnitude(scene);
    rtt_conform_engine_spec specs[64];
    int n_specs = rtt_conform_expand_engines(config->engines ? config->engines : rtt_conform_default_engines(), specs, 64, err);
    if (n_specs < 0) return false;
    rtt_conform_specs_set_isa(specs, n_specs, config->isa, config->isect);

    rtt_engine *reference = rtt_engine_create("reference", scene, NULL, err);
    if (!reference) return false;
    ray_set_data data[RTT_CONFORM_RAY_SET_COUNT] = {{0}};
    uint64_t referee_budget = RTT_CONFORM_REFEREE_BUDGET;
    bool ok = true;
    for (int s = 0; s < RTT_CONFORM_RAY_SET_COUNT && ok; s++) {
        data[s].used = config->file_rays ? s == RTT_CONFORM_FILE : config->sets[s] && s != RTT_CONFORM_FILE;
        if (!data[s].used) continue;
        if (s == RTT_CONFORM_FILE) {
            data[s].count = config->file_ray_count;
            data[s].rays = malloc((data[s].count ? data[s].count : 1) * sizeof *data[s].rays);
            ok = data[s].rays != NULL || rtt_error_set(err, "%s: out of memory for %zu rays", scene->path, data[s].count);
            if (ok) memcpy(data[s].rays, config->file_rays, data[s].count * sizeof *data[s].rays);
            if (ok) rtt_rays_to_stored(scene, data[s].rays, data[s].count); /* given in the scene's own coordinates */
        } else {
            ok = rtt_conform_make_rays(scene, (rtt_conform_ray_set)s, reference, config->max_rays,
                                       config->seed + (uint64_t)s, &data[s].rays, &data[s].count, err);
        }
        if (!ok) break;
        data[s].oracle = malloc((data[s].count ? data[s].count : 1) * sizeof *data[s].oracle);
        if (!data[s].oracle) {
            ok = rtt_error_set(err, "%s: out of memory", scene->path);
            break;
        }
        rtt_engine_intersect(reference, data[s].rays, data[s].oracle, data[s].count);
        data[s].referee = (rtt_conform_referee_cache){.n = data[s].count, .budget = &referee_budget};
    }
    for (int e = 0; e < n_specs && ok; e++)
        run_engine(scene, &specs[e], config->referee_every_ray, data, report, err, &ok);
    if (ok) ok = gather_failing_rays(scene, data, report, err);
    for (int s = 0; s < RTT_CONFORM_RAY_SET_COUNT; s++) {
        free(data[s].rays);
        free(data[s].oracle);
        free(data[s].file_index);
        rtt_conform_referee_cache_free(&data[s].referee);
    }
    rtt_engine_destroy(reference);
    if (!ok) {
        rtt_conform_report_free(report);
        return false;
    }
    report->pass = true;
    for (size_t i = 0; i < report->row_count; i++) report->pass = report->pass && report->rows[i].pass;
    return true;
}

void rtt_conform_report_free(rtt_conform_report *report)
{
    for (size_t i = 0; i < report->row_count; i++) rtt_conform_row_free(&report->rows[i]);
    free(report->failing_rays);
    report->failing_rays = NULL;
    report->failing_ray_count = 0;
    free(report->rows);
    report->rows = NULL;
    report->row_count = report->row_cap = 0;
}
