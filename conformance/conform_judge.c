/* The judgement of a row: every ray classified against the oracle
 * (conform_classify.c), every disagreement decided by the double-precision
 * referee (conform_referee.c), and the errors that count against the row
 * separated from the oracle's own ("Embree wrong", "reference wrong").
 * conformance/README.md, "Judged in double", states the rules. */
#include <stdlib.h>
#include <string.h>

#include "conform.h"
#ifdef RTT_HAVE_EMBREE
#include "embree_engine.h"
#endif

static const char *const verdict_names[] = {
    "not refereed", "engine wrong", "reference wrong", "embree wrong", "both right", "undecidable",
};

const char *rtt_conform_verdict_name(rtt_conform_verdict v)
{
    return (unsigned)v < sizeof verdict_names / sizeof verdict_names[0] ? verdict_names[v] : "unknown";
}

void rtt_conform_referee_cache_free(rtt_conform_referee_cache *cache)
{
    free(cache->hits);
    free(cache->state);
    cache->hits = NULL;
    cache->state = NULL;
}

void rtt_conform_row_free(rtt_conform_row *row)
{
    free(row->error_rays);
    row->error_rays = NULL;
    row->error_ray_count = row->error_ray_cap = 0;
}

static bool is_hit(const rtt_hit *h) { return h->prim != RTT_MISS; }

typedef enum referee_answer { ANSWERED, UNDECIDABLE, OVER_BUDGET, NO_MEMORY } referee_answer;

/* The referee's hit on ray i of the set, computed once per set. */
static referee_answer referee_ask(rtt_conform_referee_cache *cache, const rtt_scene *scene, const rtt_ray *r, size_t i,
                                  rtt_conform_referee_hit *out)
{
    if (!cache->hits) {
        cache->hits = malloc((cache->n ? cache->n : 1) * sizeof *cache->hits);
        cache->state = calloc(cache->n ? cache->n : 1, 1);
        if (!cache->hits || !cache->state) {
            rtt_conform_referee_cache_free(cache);
            return NO_MEMORY;
        }
    }
    if (i >= cache->n) return UNDECIDABLE;
    if (cache->state[i] == 0) {
        if (*cache->budget < scene->triangle_count) return OVER_BUDGET;
        *cache->budget -= scene->triangle_count;
        cache->state[i] = rtt_conform_referee(scene, r, &cache->hits[i]) ? 1 : 2;
    }
    *out = cache->hits[i];
    return cache->state[i] == 1 ? ANSWERED : UNDECIDABLE;
}

/* occluded() against the referee: it must say "occluded" exactly when the
 * referee hits something, unless that hit (or the engine's own intersect()
 * hit) lies within tolerance of tnear or tfar, where either answer is right. */
static bool referee_accepts_occluded(const rtt_scene *scene, double magnitude, const rtt_ray *r, uint8_t occluded,
                                     const rtt_hit *engine_hit, const rtt_conform_referee_hit *referee)
{
    rtt_hit decided = rtt_conform_referee_as_hit(referee), miss = {INFINITY, 0.0f, 0.0f, RTT_MISS};
    if ((occluded != 0) == is_hit(&decided)) return true;
    return rtt_conform_classify(scene, magnitude, r, &miss, &decided) == RTT_CONFORM_BOUNDARY ||
           rtt_conform_classify(scene, magnitude, r, engine_hit, &miss) == RTT_CONFORM_BOUNDARY;
}

/* A ray the Embree adapter does not hand to Embree although the referee
 * (and so every rtt engine) takes it: unspecified for Embree. */
static bool outside_embree_range(const rtt_ray *r)
{
#ifdef RTT_HAVE_EMBREE
    return !rtt_embree_ray_in_range(r) && rtt_conform_ray_decidable(r);
#else
    (void)r;
    return false;
#endif
}

static void add_note(rtt_conform_ray_note *notes, size_t *count, const rtt_scene *scene, const rtt_conform_ray_note *n)
{
    if (*count >= RTT_CONFORM_NOTES) return;
    notes[*count] = *n;
    rtt_rays_from_stored(scene, &notes[*count].ray, 1); /* named in the scene's own coordinates */
    (*count)++;
}

static bool collect_error(rtt_conform_row *row, uint32_t index)
{
    if (row->error_ray_count == row->error_ray_cap) {
        size_t cap = row->error_ray_cap ? 2 * row->error_ray_cap : 64;
        uint32_t *grown = realloc(row->error_rays, cap * sizeof *grown);
        if (!grown) return false;
        row->error_rays = grown;
        row->error_ray_cap = cap;
    }
    row->error_rays[row->error_ray_count++] = index;
    return true;
}

/* Decides one disagreement: the verdict, and whether it is an error of the
 * row's rtt side. */
static rtt_conform_verdict decide(const rtt_scene *scene, double magnitude, const rtt_conform_judging *judging,
                                  rtt_conform_ray_note *note, rtt_conform_row *row, bool *no_memory)
{
    if (!judging->referee) return RTT_VERDICT_NONE;
    switch (referee_ask(judging->referee, scene, &note->ray, note->index, &note->referee)) {
    case OVER_BUDGET: row->unrefereed++; return RTT_VERDICT_NONE;
    case NO_MEMORY: *no_memory = true; return RTT_VERDICT_NONE;
    case UNDECIDABLE: return RTT_VERDICT_UNDECIDABLE;
    case ANSWERED: break;
    }
    row->refereed++;
    bool engine_ok = note->occluded ? referee_accepts_occluded(scene, magnitude, &note->ray, note->engine_occluded,
                                                               &note->engine, &note->referee)
                                    : rtt_conform_referee_accepts(scene, magnitude, &note->ray, &note->engine,
                                                                  &note->referee);
    bool oracle_ok = rtt_conform_referee_accepts(scene, magnitude, &note->ray, &note->oracle, &note->referee);
    if (engine_ok && oracle_ok) return RTT_VERDICT_BOTH_RIGHT;
    if (engine_ok) return RTT_VERDICT_REFERENCE_WRONG;
    if (oracle_ok) return judging->engine_is_embree ? RTT_VERDICT_EMBREE_WRONG : RTT_VERDICT_ENGINE_WRONG;
    /* both wrong: the error is the rtt side's */
    return judging->engine_is_embree ? RTT_VERDICT_REFERENCE_WRONG : RTT_VERDICT_ENGINE_WRONG;
}

bool rtt_conform_compare_judged(const rtt_scene *scene, const rtt_ray *rays, const rtt_hit *test,
                                const uint8_t *test_occluded, const rtt_hit *oracle, size_t n, rtt_conform_row *row,
                                const rtt_conform_judging *judging)
{
    double magnitude = rtt_conform_scene_magnitude(scene);
    bool no_memory = false;
    row->rays += n;
    for (size_t i = 0; i < n; i++) {
        if (judging->engine_is_embree && outside_embree_range(&rays[i])) {
            row->count[RTT_CONFORM_UNSPECIFIED]++;
            continue;
        }
        rtt_conform_category c = rtt_conform_classify(scene, magnitude, &rays[i], &test[i], &oracle[i]);
        row->count[c]++;
        bool agreed = c == RTT_CONFORM_AGREE || c == RTT_CONFORM_TIE;
        bool occluded = test_occluded && agreed && (test_occluded[i] != 0) != is_hit(&oracle[i]);
        if (occluded) row->occluded_mismatch++;
        bool check_agreement = agreed && !occluded && judging->every_ray && judging->referee;
        if ((agreed && !occluded && !check_agreement) || c == RTT_CONFORM_BOUNDARY) continue;

        rtt_conform_ray_note note = {.index = (uint32_t)i, .file_index = -1, .ray = rays[i], .engine = test[i],
                                     .oracle = oracle[i], .engine_occluded = test_occluded ? test_occluded[i] : 0,
                                     .occluded = occluded, .category = c,
                                     .referee = {INFINITY, RTT_MISS}};
        note.verdict = decide(scene, magnitude, judging, &note, row, &no_memory);
        if (check_agreement) {
            /* engine and oracle agree: only an answer both give and the
             * referee refuses is an error, in the category of the engine's
             * hit against the referee's */
            bool refused = note.verdict == RTT_VERDICT_ENGINE_WRONG || note.verdict == RTT_VERDICT_REFERENCE_WRONG ||
                           note.verdict == RTT_VERDICT_EMBREE_WRONG;
            if (!refused) continue;
        }
        /* an answer the referee refused counts by its category against the
         * referee's hit: the truth, not the other engine */
        note.judged = RTT_CONFORM_CATEGORY_COUNT;
        if (!occluded && (note.verdict == RTT_VERDICT_ENGINE_WRONG || note.verdict == RTT_VERDICT_REFERENCE_WRONG)) {
            rtt_hit decided = rtt_conform_referee_as_hit(&note.referee);
            const rtt_hit *wrong = note.verdict == RTT_VERDICT_REFERENCE_WRONG ? &oracle[i] : &test[i];
            note.judged = rtt_conform_classify(scene, magnitude, &rays[i], wrong, &decided);
            c = note.judged;
        }
        bool error = note.verdict == RTT_VERDICT_NONE || note.verdict == RTT_VERDICT_UNDECIDABLE ||
                     note.verdict == RTT_VERDICT_ENGINE_WRONG ||
                     (note.verdict == RTT_VERDICT_REFERENCE_WRONG && judging->engine_is_embree);
        if (note.verdict == RTT_VERDICT_BOTH_RIGHT) row->both_right++;
        if (note.verdict == RTT_VERDICT_EMBREE_WRONG) row->embree_wrong++;
        if (note.verdict == RTT_VERDICT_REFERENCE_WRONG) row->reference_wrong++;
        if (error) {
            if (occluded)
                row->occluded_errors++;
            else
                row->errors[c]++;
            add_note(row->failing, &row->failing_count, scene, &note);
            if (judging->collect && !collect_error(row, (uint32_t)i)) no_memory = true;
        } else if (note.verdict == RTT_VERDICT_EMBREE_WRONG || note.verdict == RTT_VERDICT_REFERENCE_WRONG) {
            add_note(row->wrong_oracle, &row->wrong_oracle_count, scene, &note);
        }
    }
    return !no_memory;
}

void rtt_conform_compare(const rtt_scene *scene, const rtt_ray *rays, const rtt_hit *test, const uint8_t *test_occluded,
                         const rtt_hit *oracle, size_t n, rtt_conform_row *row)
{
    rtt_conform_judging plain = {0};
    rtt_conform_compare_judged(scene, rays, test, test_occluded, oracle, n, row, &plain);
}

/* A non-zero grazing limit always allows one ray: a share of 0.05% means
 * nothing on a set of a few thousand rays. */
void rtt_conform_row_judge(rtt_conform_row *row)
{
    double allowed = row->grazing_limit * (double)row->rays;
    if (row->grazing_limit > 0.0 && allowed < 1.0) allowed = 1.0;
    row->pass = row->error[0] == '\0' && row->errors[RTT_CONFORM_T_MISMATCH] == 0 &&
                row->errors[RTT_CONFORM_HITMISS_OTHER] == 0 && row->occluded_errors == 0 &&
                (double)row->errors[RTT_CONFORM_GRAZING] <= allowed;
}
