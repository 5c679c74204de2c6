/* settings_private.h — what the files of the parameter table share and
 * nothing else includes: the rows (settings_table.c), the one-line message
 * writer and the name as messages write it (settings.c), the typed value
 * and its check against a row (settings.c), the YAML 1.1 scalar parser and
 * the settings file's bounds (settings_yaml.c). The public API is settings.h
 * and lane_config.h.
 *
 *   settings_table.c  the rows and their accessors (also built alone into the
 *                     generators of Station.cfg and af_defaults.h)
 *   settings.c        the values object: init, set, get, print
 *   settings_yaml.c   YAML 1.1 scalars; the settings file's bounds
 *   settings_libyaml.c  the settings file, parsed by libyaml
 *   lane_config.c     af_lane_config_derive and the lane's memory bound */
#ifndef AF_SETTINGS_PRIVATE_H
#define AF_SETTINGS_PRIVATE_H

#include <stdbool.h>
#include <stddef.h>

#include "settings.h"
#include "text.h" /* af_text_line: the one-line messages */

/* The table, indexed by af_setting_id (settings_table.c). */
extern const af_setting_def af_setting_rows[AF_SETTING_COUNT];

static inline bool setting_valid_id(af_setting_id id)
{
  return (int)id >= 0 && id < AF_SETTING_COUNT;
}

/* The name as messages write it: prefix + name (settings.c). */
typedef struct {
  char text[AF_SETTINGS_PREFIX_MAX + 64];
} af_name;
af_name af_settings_name_of(const af_settings *s, af_setting_id id);

/* A typed value: what YAML, a flag or a ROS parameter gave. */
typedef enum { AF_V_NULL, AF_V_BOOL, AF_V_NUMBER, AF_V_STRING } af_vtype;

typedef struct {
  af_vtype type;
  double number;
  bool boolean;
  const char *text; /* AF_V_STRING */
  bool quoted;      /* AF_V_STRING from a quoted scalar */
  bool lenient;     /* a bare string that is a whole C number counts as one (CLI) */
} af_value;

/* Checks v against row id and stores it into s, or says why not
 * (settings.c). */
af_status af_settings_apply(af_settings *s, af_setting_id id, const af_value *v, char *err,
                            size_t len);

/* Parses the YAML scalar at p into buf[size] (unquoted text) and *v; *rest
 * is where it ended (after a closing quote, or at a comment / the end for a
 * plain one). false with *why on a malformed scalar (settings_yaml.c). */
bool af_settings_parse_scalar(const char *p, char *buf, size_t size, af_value *v, const char **rest,
                              const char **why);
/* Nothing but blanks and a comment (settings_yaml.c). */
bool af_settings_blank_or_comment(const char *p);
/* A plain (unquoted) YAML scalar t typed as PyYAML types it (settings_yaml.c). */
void af_settings_resolve_plain(const char *t, af_value *v);

/* The settings file's bounds, checked before any parser sees its bytes. */
#define AF_YAML_LINE_MAX 1024                /* bytes per line, with its NUL */
#define AF_YAML_FILE_MAX_BYTES (1024 * 1024) /* a settings file, whole [bytes] */
/* The whole of path into *data (malloc'd, *size bytes) when it is a regular
 * file of at most AF_YAML_FILE_MAX_BYTES; else one line in err. */
af_status af_settings_read_whole(const char *path, char **data, size_t *size, char *err,
                                 size_t len);
/* The line at data[*pos..size) into line[AF_YAML_LINE_MAX] without its end;
 * *pos moves past it. false with file:line:column in err on a NUL byte, a CR
 * not followed by LF or a line longer than AF_YAML_LINE_MAX - 1 bytes. */
bool af_settings_next_line(const char *data, size_t size, size_t *pos, char *line, const char *path,
                           int number, char *err, size_t len);

#endif
