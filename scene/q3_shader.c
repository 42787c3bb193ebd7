/* Quake III shader scripts, as the engine's own parser reads them
 * (whitespace-separated tokens, "//" and block comments, quoted tokens),
 * reduced to each shader's first image stage: rtt draws one texture per
 * surface, so the stage that gives a surface its look is the first that
 * samples an image (later stages blend lightmaps, glows and effects over
 * it). */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "q3_shader.h"

typedef struct lexer {
    const char *p, *end;
    unsigned line;
} lexer;

/* The next token into out (cut to RTT_Q3_NAME_MAX - 1 bytes); false at
 * the end of the text. */
static bool next_token(lexer *lx, char out[RTT_Q3_NAME_MAX], bool *newline_before)
{
    *newline_before = false;
    for (;;) {
        while (lx->p < lx->end && (unsigned char)*lx->p <= ' ') {
            if (*lx->p == '\n') lx->line++, *newline_before = true;
            lx->p++;
        }
        if (lx->p + 1 < lx->end && lx->p[0] == '/' && lx->p[1] == '/') {
            while (lx->p < lx->end && *lx->p != '\n') lx->p++;
            continue;
        }
        if (lx->p + 1 < lx->end && lx->p[0] == '/' && lx->p[1] == '*') {
            lx->p += 2;
            while (lx->p + 1 < lx->end && !(lx->p[0] == '*' && lx->p[1] == '/')) {
                if (*lx->p == '\n') lx->line++, *newline_before = true;
                lx->p++;
            }
            lx->p = lx->p + 1 < lx->end ? lx->p + 2 : lx->end;
            continue;
        }
        break;
    }
    if (lx->p >= lx->end) return false;
    size_t n = 0;
    if (*lx->p == '"') {
        lx->p++;
        while (lx->p < lx->end && *lx->p != '"' && *lx->p != '\n') {
            if (n + 1 < RTT_Q3_NAME_MAX) out[n++] = *lx->p;
            lx->p++;
        }
        if (lx->p < lx->end && *lx->p == '"') lx->p++;
    } else if (*lx->p == '{' || *lx->p == '}') {
        out[n++] = *lx->p++;
    } else {
        while (lx->p < lx->end && (unsigned char)*lx->p > ' ' && *lx->p != '{' && *lx->p != '}') {
            if (n + 1 < RTT_Q3_NAME_MAX) out[n++] = *lx->p;
            lx->p++;
        }
    }
    out[n] = '\0';
    return true;
}

static bool is_image_keyword(const char *token)
{
    return strcasecmp(token, "map") == 0 || strcasecmp(token, "clampmap") == 0 || strcasecmp(token, "animmap") == 0;
}

bool rtt_q3_shader_parse(const char *text, size_t size, rtt_q3_shader_fn fn, void *context, char *why,
                         size_t why_size)
{
    lexer lx = {text, text + size, 1};
    char token[RTT_Q3_NAME_MAX], name[RTT_Q3_NAME_MAX], image[RTT_Q3_NAME_MAX];
    bool newline;
    while (next_token(&lx, name, &newline)) {
        if (name[0] == '{' || name[0] == '}') {
            snprintf(why, why_size, "line %u: \"%s\" where a shader name was expected", lx.line, name);
            return false;
        }
        if (!next_token(&lx, token, &newline) || strcmp(token, "{") != 0) {
            snprintf(why, why_size, "line %u: shader \"%s\" has no block", lx.line, name);
            return false;
        }
        int depth = 1;
        bool found = false;
        const char *keyword_wanted = NULL; /* set after an image keyword inside a stage */
        image[0] = '\0';
        while (depth > 0) {
            if (!next_token(&lx, token, &newline)) {
                snprintf(why, why_size, "line %u: shader \"%s\" is not closed", lx.line, name);
                return false;
            }
            if (strcmp(token, "{") == 0) {
                if (++depth > 2) {
                    snprintf(why, why_size, "line %u: shader \"%s\": a block inside a stage", lx.line, name);
                    return false;
                }
                keyword_wanted = NULL;
            } else if (strcmp(token, "}") == 0) {
                depth--;
                keyword_wanted = NULL;
            } else if (keyword_wanted && !newline) {
                bool is_number = strcasecmp(keyword_wanted, "animmap") == 0 && image[0] == '\0' && !found &&
                                 ((token[0] >= '0' && token[0] <= '9') || token[0] == '.');
                if (!is_number) { /* animMap's first argument is its frequency */
                    if (!found && token[0] != '$') {
                        snprintf(image, sizeof image, "%s", token);
                        found = true;
                    }
                    keyword_wanted = NULL;
                }
            } else {
                keyword_wanted = depth == 2 && is_image_keyword(token) ? (strcasecmp(token, "animmap") == 0 ? "animmap" : "map") : NULL;
            }
        }
        fn(context, name, found ? image : NULL);
    }
    return true;
}
