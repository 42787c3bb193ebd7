/* The engine registry: names to engine classes, filled by the layers that
 * implement engines (rtt_builtin_engines_register for reference and
 * optimized, the conformance layer for Embree), and the one options check
 * that the command line, the engines and the renderers all call. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rtt/engine.h"

#define REGISTRY_MAX 16u

static pthread_mutex_t registry_lock = PTHREAD_MUTEX_INITIALIZER;
static const rtt_engine_class *registry[REGISTRY_MAX];
static uint32_t registry_count;

bool rtt_engine_register(const rtt_engine_class *cls, rtt_error *err)
{
    if (!cls || !cls->name || !cls->create) return rtt_error_set(err, "engine registry: a class needs a name and a constructor");
    bool ok = true;
    pthread_mutex_lock(&registry_lock);
    uint32_t i = 0;
    while (i < registry_count && strcmp(registry[i]->name, cls->name) != 0) i++;
    if (i < registry_count) registry[i] = cls;
    else if (registry_count < REGISTRY_MAX) registry[registry_count++] = cls;
    else ok = false;
    pthread_mutex_unlock(&registry_lock);
    return ok ? true : rtt_error_set(err, "engine registry: more than %u engines", REGISTRY_MAX);
}

const rtt_engine_class *rtt_engine_class_at(uint32_t i)
{
    pthread_mutex_lock(&registry_lock);
    const rtt_engine_class *cls = i < registry_count ? registry[i] : NULL;
    pthread_mutex_unlock(&registry_lock);
    return cls;
}

const rtt_engine_class *rtt_engine_find(const char *name)
{
    const rtt_engine_class *cls;
    for (uint32_t i = 0; name && (cls = rtt_engine_class_at(i)); i++)
        if (strcmp(cls->name, name) == 0) return cls;
    return NULL;
}

static bool unknown_engine(const char *name, rtt_error *err)
{
    char names[256] = "";
    const rtt_engine_class *cls;
    for (uint32_t i = 0; (cls = rtt_engine_class_at(i)); i++) {
        size_t used = strlen(names);
        snprintf(names + used, sizeof names - used, "%s%s", i ? ", " : "", cls->name);
    }
    return rtt_error_set(err, "unknown engine \"%s\": this build has %s", name ? name : "(null)",
                         names[0] ? names : "no engine registered");
}

static const struct { uint32_t bit; const char *what; } option_names[] = {
    {RTT_OPTION_ACCEL, "an acceleration structure"}, {RTT_OPTION_TRAVERSAL, "a traversal kernel"},
    {RTT_OPTION_TILE, "a tile size"},               {RTT_OPTION_LEAF_CULLING, "a leaf-culling setting"},
    {RTT_OPTION_MAX_DEPTH, "a tree depth bound"},   {RTT_OPTION_ISA, "an instruction-set choice"},
    {RTT_OPTION_ISECT, "a triangle-test choice"},
};

static bool check_isa(rtt_isa isa, rtt_error *err)
{
    if ((unsigned)isa >= RTT_ISA_COUNT) return rtt_error_set(err, "unknown instruction set %d", (int)isa);
    if (isa == RTT_ISA_AUTO) {
        const char *env = getenv("RTT_ISA");
        rtt_isa from_env;
        if (!env || !env[0]) return true; /* unset or set empty: the widest */
        if (!rtt_isa_parse(env, &from_env))
            return rtt_error_set(err, "RTT_ISA=%s: expected auto, sse4, avx2 or avx512", env);
        isa = from_env;
    }
    if (!rtt_isa_supported(isa))
        return rtt_error_set(err, "instruction set %s: this CPU does not have it (widest here: %s)", rtt_isa_name(isa),
                             rtt_isa_name(rtt_isa_resolve(RTT_ISA_AUTO)));
    return true;
}

bool rtt_engine_options_check(const char *name, const rtt_engine_options *opt, rtt_error *err)
{
    const rtt_engine_class *cls = rtt_engine_find(name);
    return cls ? rtt_engine_class_check(cls, opt, err) : unknown_engine(name, err);
}

bool rtt_engine_class_check(const rtt_engine_class *cls, const rtt_engine_options *opt, rtt_error *err)
{
    const char *name = cls->name;
    for (size_t i = 0; i < sizeof option_names / sizeof option_names[0]; i++)
        if ((opt->given & option_names[i].bit) && !(cls->uses & option_names[i].bit))
            return rtt_error_set(err, "engine \"%s\" does not use %s", name, option_names[i].what);
    if ((unsigned)opt->accel >= RTT_ACCEL_COUNT)
        return rtt_error_set(err, "unknown acceleration structure %d", (int)opt->accel);
    if (opt->tile != 0 && opt->tile != 4 && opt->tile != 8 && opt->tile != 16 && opt->tile != 32)
        return rtt_error_set(err, "tile %u: the tile side must be 4, 8, 16 or 32", opt->tile);
    if (opt->max_tree_depth > RTT_KD_DEPTH_LIMIT)
        return rtt_error_set(err, "tree depth bound %u: at most %u", opt->max_tree_depth, RTT_KD_DEPTH_LIMIT);
    if (memchr(opt->traversal, '\0', sizeof opt->traversal) == NULL)
        return rtt_error_set(err, "traversal name longer than %u characters", RTT_TRAVERSAL_NAME_MAX - 1);
    if (!check_isa(opt->isa, err)) return false;
    if ((unsigned)opt->isect >= RTT_ISECT_COUNT) return rtt_error_set(err, "unknown triangle test %d", (int)opt->isect);
    return cls->check ? cls->check(opt, err) : true;
}

rtt_engine *rtt_engine_create(const char *name, const rtt_scene *scene, const rtt_engine_options *opt,
                              rtt_error *err)
{
    rtt_engine_options defaults;
    if (!opt) {
        rtt_engine_options_default(&defaults);
        opt = &defaults;
    }
    if (!rtt_engine_options_check(name, opt, err)) return NULL;
    return rtt_engine_find(name)->create(scene, opt, err);
}
