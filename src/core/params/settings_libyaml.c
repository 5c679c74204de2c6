/* settings_libyaml.c — the flat YAML settings files (config/station.yaml, the
 * cultivar's) read with libyaml's event parser, checked against the
 * parameter table (doc/layout.md, "libyaml: measured, adopted").
 *
 * The file-level bounds stay ours and come first: a regular file of at most
 * AF_YAML_FILE_MAX_BYTES, read whole; then every line through the same
 * byte checks as the line reader (a NUL, a CR not followed by LF, a line
 * over AF_YAML_LINE_MAX - 1 bytes: file:line:column). Only then does libyaml
 * see the bytes. What it parses must still be one map of `name: scalar`:
 * flow style ({a: 1}), indentation, quoted keys, every escape, and anchors
 * on scalars with their aliases are read as PyYAML (rosparam) reads them; a
 * list, a nested map, a tag, a block scalar, a second document, an unknown
 * or duplicate key are refused in one line. Scalars are typed as rosparam
 * types them (plain: af_settings_resolve_plain, quoted: a string). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

#include "settings_private.h"

#define AF_YAML_ANCHORS_MAX 16 /* anchored scalars in one file */

typedef struct {
  char name[64];
  char text[AF_YAML_LINE_MAX];
  bool quoted;
} af_anchor;

typedef struct {
  af_settings copy;
  int first_line[AF_SETTING_COUNT];
  af_anchor anchors[AF_YAML_ANCHORS_MAX];
  int n_anchors;
} af_yaml_state;

static const char *event_what(yaml_event_type_t t)
{
  switch (t) {
  case YAML_SEQUENCE_START_EVENT: return "a list";
  case YAML_MAPPING_START_EVENT: return "a map";
  case YAML_ALIAS_EVENT: return "an alias";
  case YAML_SCALAR_EVENT: return "a scalar";
  default: return "not a flat value";
  }
}

/* The scalar of event e as a typed value into v (text in buf[AF_YAML_LINE_MAX]);
 * false with *why. */
static bool scalar_value(const yaml_event_t *e, char *buf, af_value *v, const char **why)
{
  const size_t n = e->data.scalar.length;
  if (e->data.scalar.tag != NULL) {
    *why = "not a flat value (a tag)";
    return false;
  }
  if (e->data.scalar.style == YAML_LITERAL_SCALAR_STYLE ||
      e->data.scalar.style == YAML_FOLDED_SCALAR_STYLE) {
    *why = "not a flat value (a block scalar)";
    return false;
  }
  if (n >= AF_YAML_LINE_MAX) {
    *why = "a value longer than the line buffer";
    return false;
  }
  if (memchr(e->data.scalar.value, '\0', n) != NULL) { /* a "\0" escape */
    *why = "a NUL character in a quoted value";
    return false;
  }
  memcpy(buf, e->data.scalar.value, n);
  buf[n] = '\0';
  *v = (af_value){.type = AF_V_NULL};
  if (e->data.scalar.style == YAML_PLAIN_SCALAR_STYLE) {
    af_settings_resolve_plain(buf, v);
  } else {
    *v = (af_value){.type = AF_V_STRING, .text = buf, .quoted = true};
  }
  return true;
}

/* The value event e of key (row id, on line `line`) into st; false with err. */
static af_status one_value(af_yaml_state *st, af_setting_id id, const char *key,
                           const yaml_event_t *e, const char *path, int line, char *err, size_t len)
{
  char buf[AF_YAML_LINE_MAX], why_buf[AF_SETTINGS_TEXT_MAX];
  const char *why = NULL;
  af_value v = {.type = AF_V_NULL};
  const int vline = (int)e->start_mark.line + 1;
  if (e->type == YAML_ALIAS_EVENT) {
    const af_anchor *a = NULL;
    for (int k = 0; k < st->n_anchors; k++)
      if (strcmp(st->anchors[k].name, (const char *)e->data.alias.anchor) == 0)
        a = &st->anchors[k];
    if (a == NULL) {
      af_text_line(err, len, "%s:%d: %s: an alias to '%.40s', which is not an anchored scalar",
                   path, vline, key, (const char *)e->data.alias.anchor);
      return AF_EINVAL;
    }
    memcpy(buf, a->text, sizeof buf);
    if (a->quoted)
      v = (af_value){.type = AF_V_STRING, .text = buf, .quoted = true};
    else
      af_settings_resolve_plain(buf, &v);
  } else if (e->type != YAML_SCALAR_EVENT) {
    af_text_line(err, len, "%s:%d: %s: not a flat value (%s)", path, vline, key,
                 event_what(e->type));
    return AF_EINVAL;
  } else if (!scalar_value(e, buf, &v, &why)) {
    af_text_line(err, len, "%s:%d: %s: %s", path, vline, key, why);
    return AF_EINVAL;
  } else if (e->data.scalar.anchor != NULL) {
    if (st->n_anchors >= AF_YAML_ANCHORS_MAX) {
      af_text_line(err, len, "%s:%d: more than %d anchors", path, vline, AF_YAML_ANCHORS_MAX);
      return AF_EINVAL;
    }
    af_anchor *a = &st->anchors[st->n_anchors++];
    snprintf(a->name, sizeof a->name, "%s", (const char *)e->data.scalar.anchor);
    memcpy(a->text, buf, sizeof a->text);
    a->quoted = v.quoted;
  }
  if (af_settings_apply(&st->copy, id, &v, why_buf, sizeof why_buf) != AF_OK) {
    af_text_line(err, len, "%s:%d: %s", path, line, why_buf);
    return AF_EINVAL;
  }
  return AF_OK;
}

/* The key event e into *id (checked: a plain known name, not given before). */
static af_status one_key(af_yaml_state *st, const yaml_event_t *e, af_setting_id *id, char *key,
                         size_t key_len, const char *path, char *err, size_t len)
{
  const int line = (int)e->start_mark.line + 1;
  if (e->type != YAML_SCALAR_EVENT || e->data.scalar.tag != NULL || e->data.scalar.anchor != NULL ||
      e->data.scalar.style == YAML_LITERAL_SCALAR_STYLE ||
      e->data.scalar.style == YAML_FOLDED_SCALAR_STYLE) {
    af_text_line(err, len, "%s:%d: not a flat `key: value` entry: its key is %s", path, line,
                 e->type == YAML_SCALAR_EVENT ? "tagged, anchored or a block scalar"
                                              : event_what(e->type));
    return AF_EINVAL;
  }
  snprintf(key, key_len, "%.*s", (int)(e->data.scalar.length < 79 ? e->data.scalar.length : 79),
           (const char *)e->data.scalar.value);
  if (strlen(key) != e->data.scalar.length || af_setting_find(key, id) != AF_OK) {
    af_text_line(err, len, "%s:%d: unknown parameter '%s'", path, line, key);
    return AF_EINVAL;
  }
  if (st->first_line[*id] != 0) {
    af_text_line(err, len, "%s:%d: duplicate key '%s': given on line %d and again on line %d", path,
                 line, key, st->first_line[*id], line);
    return AF_EINVAL;
  }
  st->first_line[*id] = line;
  return AF_OK;
}

/* The events of the parser into st; false with err. */
static af_status parse_events(yaml_parser_t *p, af_yaml_state *st, const char *path, char *err,
                              size_t len)
{
  int docs = 0, depth = 0; /* depth 1: inside the top map */
  bool want_key = true, done = false;
  af_setting_id id = AF_SETTING_COUNT;
  char key[80] = "";
  int key_line = 0;
  af_status status = AF_OK;
  while (status == AF_OK && !done) {
    yaml_event_t e;
    if (!yaml_parser_parse(p, &e)) {
      af_text_line(err, len, "%s:%d:%d: %s%s%s", path, (int)p->problem_mark.line + 1,
                   (int)p->problem_mark.column + 1, p->problem ? p->problem : "a YAML error",
                   p->context ? " " : "", p->context ? p->context : "");
      return AF_EINVAL;
    }
    const int line = (int)e.start_mark.line + 1;
    switch (e.type) {
    case YAML_STREAM_START_EVENT:
    case YAML_DOCUMENT_END_EVENT: break;
    case YAML_STREAM_END_EVENT: done = true; break;
    case YAML_DOCUMENT_START_EVENT:
      if (++docs > 1) {
        af_text_line(err, len, "%s:%d: a second YAML document; a settings file holds one", path,
                     line);
        status = AF_EINVAL;
      }
      break;
    default:
      if (depth == 0 && e.type == YAML_MAPPING_START_EVENT) {
        depth = 1;
      } else if (depth == 0 && e.type == YAML_SCALAR_EVENT && e.data.scalar.length == 0 &&
                 e.data.scalar.style == YAML_PLAIN_SCALAR_STYLE) {
        /* an empty document ("---" alone): no settings */
      } else if (depth == 0) {
        af_text_line(err, len, "%s:%d: not a flat `key: value` file: the document is %s", path,
                     line, event_what(e.type));
        status = AF_EINVAL;
      } else if (e.type == YAML_MAPPING_END_EVENT && want_key) {
        depth = 0;
      } else if (want_key) {
        status = one_key(st, &e, &id, key, sizeof key, path, err, len);
        key_line = line;
        want_key = false;
      } else {
        status = one_value(st, id, key, &e, path, key_line, err, len);
        want_key = true;
      }
    }
    yaml_event_delete(&e);
  }
  return status;
}

af_status af_settings_load_yaml(af_settings *s, const char *path, char *err, size_t len)
{
  if (s == NULL || path == NULL) {
    af_text_line(err, len, "settings: a NULL argument");
    return AF_EINVAL;
  }
  char *data = NULL;
  size_t size = 0, pos = 0;
  af_status status = af_settings_read_whole(path, &data, &size, err, len);
  if (status != AF_OK)
    return status;
  /* The bytes first: the same checks as the line reader's, before libyaml. */
  char line[AF_YAML_LINE_MAX];
  for (int number = 1; status == AF_OK && pos < size; number++)
    if (!af_settings_next_line(data, size, &pos, line, path, number, err, len))
      status = AF_EINVAL;
  af_yaml_state *st = status == AF_OK ? calloc(1, sizeof *st) : NULL;
  if (status == AF_OK && st == NULL) {
    af_text_line(err, len, "%s: no memory to read it", path);
    status = AF_ENOMEM;
  }
  yaml_parser_t parser;
  if (status == AF_OK && !yaml_parser_initialize(&parser)) {
    af_text_line(err, len, "%s: no memory for the YAML parser", path);
    status = AF_ENOMEM;
  } else if (status == AF_OK) {
    st->copy = *s;
    yaml_parser_set_input_string(&parser, (const unsigned char *)data, size);
    status = parse_events(&parser, st, path, err, len);
    yaml_parser_delete(&parser);
  }
  if (status == AF_OK)
    *s = st->copy;
  free(st);
  free(data);
  return status;
}
