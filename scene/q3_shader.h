/* Quake III shader scripts (scripts/NAME.shader in pk3 archives), reduced to
 * what rtt draws: each shader's first image stage (q3_shader.c).  Internal
 * to scene/. */
#ifndef RTT_SCENE_Q3_SHADER_H
#define RTT_SCENE_Q3_SHADER_H

#include <stdbool.h>
#include <stddef.h>

#define RTT_Q3_NAME_MAX 64u /* Quake's MAX_QPATH: longer names are cut to this many bytes minus one */

/* Called once per shader with its name and the image of its first stage
 * that names one ("map", "clampMap", or the first frame of "animMap"; not
 * "$lightmap", "$whiteimage" or another "$" image); image is NULL when no
 * stage names an image. */
typedef void (*rtt_q3_shader_fn)(void *context, const char *shader, const char *image);

/* Parses one script.  Tokens are separated by white space; "//" and
 * "/ * ... * /" comments are skipped; a shader is a name followed by a
 * braced block, stages are the blocks inside it.  On a syntax error
 * (unbalanced braces, a name without a block, nesting deeper than stages)
 * returns false with a reason naming the line: the shaders before it have
 * been reported. */
bool rtt_q3_shader_parse(const char *text, size_t size, rtt_q3_shader_fn fn, void *context, char *why,
                         size_t why_size);

#endif
