/* What the viewer's keys cycle through (view_choices.c): every kernel the
 * engine offers (over all its acceleration structures, new ones included,
 * read from the engine registry), every shadow method its renderer draws,
 * every instruction set this CPU runs.  Independent of SDL. */
#ifndef RTT_VIEWER_VIEW_CHOICES_H
#define RTT_VIEWER_VIEW_CHOICES_H

#include <stdint.h>

#include "rtt/render.h"

#define VIEW_CHOICES_MAX 48u
#define VIEW_LABEL_MAX 48u

typedef struct view_traversal {
    rtt_accel accel;
    char name[RTT_TRAVERSAL_NAME_MAX];
} view_traversal;

typedef struct view_choices {
    const rtt_engine_class *cls;
    view_traversal traversals[VIEW_CHOICES_MAX];
    uint32_t traversal_count, traversal;
    char shadows[VIEW_CHOICES_MAX][VIEW_LABEL_MAX];    /* --shadows text of each */
    uint32_t shadow_count, shadow;
    rtt_isa isas[RTT_ISA_COUNT];
    uint32_t isa_count, isa;
} view_choices;

typedef enum view_choice { VIEW_CHOICE_TRAVERSAL, VIEW_CHOICE_SHADOWS, VIEW_CHOICE_ISA } view_choice;

/* The choices of engine `name`, starting at what `start` asks for (its
 * traversal, accel, instruction set and shadow method, whose --shadows text
 * is `shadows_text`, NULL for the default); `current_kernel` is what the
 * engine reports it traces with (rtt_engine_kernel_name), the start when
 * `start` names no traversal. */
bool view_choices_make(const char *name, const rtt_render_options *start, const char *shadows_text,
                       const char *current_kernel, view_choices *out, rtt_error *err);
/* Steps choice `which` by `step` (+1 next, -1 previous), wrapping; false when
 * there is nothing to choose from. */
bool view_choices_step(view_choices *c, view_choice which, int step);
/* Makes the choice labelled `label` current (as view_choices_label names
 * it; a traversal also as "accel:name", the first of that name otherwise);
 * false when it is not offered. */
bool view_choices_select(view_choices *c, view_choice which, const char *label);
/* Writes the current choices into render options. */
void view_choices_apply(const view_choices *c, rtt_render_options *opt);
/* "mft", "hard", "avx512": the current choice's label ("" when none). */
const char *view_choices_label(const view_choices *c, view_choice which);

#endif
