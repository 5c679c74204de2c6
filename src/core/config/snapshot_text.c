/* snapshot_text.c — the settings as text and back (see snapshot_text.h). */
#include "snapshot_text.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

af_status af_settings_snapshot(const af_settings *s, char *buf, size_t len)
{
  if (s == NULL || buf == NULL || len == 0)
    return AF_EINVAL;
  size_t at = 0;
  buf[0] = '\0';
  for (int id = 0; id < AF_SETTING_COUNT; id++) {
    if (!af_settings_present(s, (af_setting_id)id) &&
        af_setting_def_of((af_setting_id)id)->kind != AF_SETTING_STRING)
      continue; /* absent: the row's default meaning, as in a YAML file without it */
    char value[2 * AF_SETTINGS_TEXT_MAX + 8];
    af_settings_value_text(s, (af_setting_id)id, value, sizeof value);
    int n =
        snprintf(buf + at, len - at, "%s: %s\n", af_setting_def_of((af_setting_id)id)->name, value);
    if (n < 0 || (size_t)n >= len - at) {
      buf[at] = '\0';
      return AF_ESIZE;
    }
    at += (size_t)n;
  }
  return AF_OK;
}

/* One line "name: value" (NUL-terminated, no newline) into t. */
static af_status snapshot_line(af_settings *t, char *line, bool *seen, char *err, size_t len)
{
  char *colon = strstr(line, ": ");
  if (colon == NULL) {
    snprintf(err, len, "not `name: value`");
    return AF_EINVAL;
  }
  *colon = '\0';
  af_setting_id id;
  if (af_setting_find(line, &id) != AF_OK) {
    snprintf(err, len, "'%.64s' is not a parameter of this version", line);
    return AF_EINVAL;
  }
  if (seen[id]) {
    snprintf(err, len, "%s is given twice", line);
    return AF_EINVAL;
  }
  seen[id] = true;
  return af_settings_set_text(t, line, colon + 2, err, len);
}

af_status af_settings_from_snapshot(af_settings *s, const char *text, char *err, size_t len)
{
  static _Thread_local af_settings t; /* large: not on the stack */
  bool seen[AF_SETTING_COUNT] = {false};
  char line[2 * AF_SETTINGS_TEXT_MAX + 80], why[sizeof line + 64];
  if (s == NULL || text == NULL)
    return AF_EINVAL;
  af_settings_reset(&t);
  size_t no = 0;
  for (const char *p = text; *p != '\0';) {
    const char *end = strchr(p, '\n');
    size_t n = end ? (size_t)(end - p) : strlen(p);
    no++;
    if (n >= sizeof line) {
      snprintf(err, len, "line %zu: longer than %zu characters", no, sizeof line - 1);
      return AF_EINVAL;
    }
    memcpy(line, p, n);
    line[n] = '\0';
    p += n + (end != NULL);
    if (n > 0 && snapshot_line(&t, line, seen, why, sizeof why) != AF_OK) {
      snprintf(err, len, "line %zu: %s", no, why);
      return AF_EINVAL;
    }
  }
  *s = t;
  return AF_OK;
}
