/* The viewer's choices (view_choices.h). */
#include <stdio.h>
#include <string.h>

#include "view_choices.h"

/* The --shadows text of method m as a key offers it: its bare name, or with
 * the default sample count when the name alone does not parse. */
static bool shadow_text(rtt_shadow_method m, char out[VIEW_LABEL_MAX], rtt_render_options *trial)
{
    const char *name = rtt_shadow_method_name(m);
    if (strcmp(name, "unknown") == 0) return false;
    rtt_error ignored = {{0}};
    snprintf(out, VIEW_LABEL_MAX, "%s", name);
    if (rtt_shadow_method_parse(out, trial, &ignored) && trial->shadows == m) return true;
    snprintf(out, VIEW_LABEL_MAX, "%s:16", name);
    return rtt_shadow_method_parse(out, trial, &ignored) && trial->shadows == m;
}

static void collect_traversals(view_choices *c, const rtt_render_options *start, const char *current)
{
    const rtt_engine_class *cls = c->cls;
    if (!(cls->uses & RTT_OPTION_TRAVERSAL) || !cls->kernel) return;
    rtt_accel want = start->engine.accel; /* the default: the first accel with kernels */
    for (int a = RTT_ACCEL_DEFAULT + 1; a < RTT_ACCEL_COUNT; a++) {
        const char *name;
        if (want == RTT_ACCEL_DEFAULT && cls->kernel((rtt_accel)a, 0)) want = (rtt_accel)a;
        for (uint32_t i = 0; (name = cls->kernel((rtt_accel)a, i)) && c->traversal_count < VIEW_CHOICES_MAX; i++) {
            view_traversal *t = &c->traversals[c->traversal_count];
            t->accel = (rtt_accel)a;
            snprintf(t->name, sizeof t->name, "%s", name);
            const bool asked = current ? strcmp(current, name) == 0 : i == 0;
            if (want == (rtt_accel)a && asked) c->traversal = c->traversal_count;
            c->traversal_count++;
        }
    }
}

bool view_choices_make(const char *name, const rtt_render_options *start, const char *shadows_text,
                       const char *current_kernel, view_choices *out, rtt_error *err)
{
    memset(out, 0, sizeof *out);
    out->cls = rtt_engine_find(name);
    if (!out->cls) return rtt_error_set(err, "no engine \"%s\"", name);
    /* the kernel in use: the one asked for, else the engine's ("mft/avx512" → "mft") */
    char current[RTT_TRAVERSAL_NAME_MAX] = "";
    snprintf(current, sizeof current, "%s", start->engine.traversal[0] ? start->engine.traversal
                                            : current_kernel ? current_kernel : "");
    char *slash = strchr(current, '/');
    if (slash) *slash = '\0';
    collect_traversals(out, start, current[0] ? current : NULL);
    for (int m = 0; m < (int)RTT_SHADOW_METHOD_COUNT && out->shadow_count < VIEW_CHOICES_MAX; m++) {
        rtt_render_options trial = *start;
        char text[VIEW_LABEL_MAX];
        if (!shadow_text((rtt_shadow_method)m, text, &trial)) continue; /* a value without a method */
        if (!(out->cls->shadow_methods & (1u << m))) continue;
        if (trial.shadows == start->shadows) {
            out->shadow = out->shadow_count;
            if (shadows_text) snprintf(text, sizeof text, "%s", shadows_text);
        }
        memcpy(out->shadows[out->shadow_count++], text, VIEW_LABEL_MAX);
    }
    if (out->cls->uses & RTT_OPTION_ISA) {
        const rtt_isa current = rtt_isa_resolve(start->engine.isa);
        for (int i = RTT_ISA_AUTO + 1; i < RTT_ISA_COUNT; i++) {
            if (!rtt_isa_supported((rtt_isa)i)) continue;
            if ((rtt_isa)i == current) out->isa = out->isa_count;
            out->isas[out->isa_count++] = (rtt_isa)i;
        }
    }
    return true;
}

bool view_choices_step(view_choices *c, view_choice which, int step)
{
    uint32_t *index = which == VIEW_CHOICE_TRAVERSAL ? &c->traversal : which == VIEW_CHOICE_SHADOWS ? &c->shadow : &c->isa;
    const uint32_t count = which == VIEW_CHOICE_TRAVERSAL ? c->traversal_count
                           : which == VIEW_CHOICE_SHADOWS ? c->shadow_count
                                                          : c->isa_count;
    if (count < 2) return false;
    *index = (uint32_t)(((int64_t)*index + step % (int)count + count) % count);
    return true;
}

void view_choices_apply(const view_choices *c, rtt_render_options *opt)
{
    if (c->traversal_count) {
        const view_traversal *t = &c->traversals[c->traversal];
        opt->engine.accel = t->accel;
        snprintf(opt->engine.traversal, sizeof opt->engine.traversal, "%s", t->name);
    }
    if (c->shadow_count) {
        rtt_error ignored = {{0}};
        rtt_shadow_method_parse(c->shadows[c->shadow], opt, &ignored);
    }
    if (c->isa_count) opt->engine.isa = c->isas[c->isa];
}

const char *view_choices_label(const view_choices *c, view_choice which)
{
    switch (which) {
    case VIEW_CHOICE_TRAVERSAL: return c->traversal_count ? c->traversals[c->traversal].name : "";
    case VIEW_CHOICE_SHADOWS: return c->shadow_count ? c->shadows[c->shadow] : "";
    case VIEW_CHOICE_ISA: return c->isa_count ? rtt_isa_name(c->isas[c->isa]) : "";
    }
    return "";
}

bool view_choices_select(view_choices *c, view_choice which, const char *label)
{
    const uint32_t count = which == VIEW_CHOICE_TRAVERSAL ? c->traversal_count
                           : which == VIEW_CHOICE_SHADOWS ? c->shadow_count
                                                          : c->isa_count;
    view_choices trial = *c;
    for (uint32_t i = 0; i < count; i++) {
        if (which == VIEW_CHOICE_TRAVERSAL) trial.traversal = i;
        else if (which == VIEW_CHOICE_SHADOWS) trial.shadow = i;
        else trial.isa = i;
        char qualified[2 * VIEW_LABEL_MAX] = "";
        if (which == VIEW_CHOICE_TRAVERSAL)
            snprintf(qualified, sizeof qualified, "%s:%s", rtt_accel_name(c->traversals[i].accel), c->traversals[i].name);
        if (strcmp(view_choices_label(&trial, which), label) == 0 || strcmp(qualified, label) == 0) {
            *c = trial;
            return true;
        }
    }
    if (which != VIEW_CHOICE_SHADOWS) return false;
    /* a shadow method with other parameters ("multi:64"): the entry of its method takes them */
    rtt_render_options parsed;
    rtt_render_options_default(&parsed);
    rtt_error ignored = {{0}};
    if (!rtt_shadow_method_parse(label, &parsed, &ignored)) return false;
    for (uint32_t i = 0; i < count; i++) {
        rtt_render_options entry;
        rtt_render_options_default(&entry);
        if (rtt_shadow_method_parse(c->shadows[i], &entry, &ignored) && entry.shadows == parsed.shadows) {
            c->shadow = i;
            snprintf(c->shadows[i], VIEW_LABEL_MAX, "%s", label);
            return true;
        }
    }
    return false;
}
