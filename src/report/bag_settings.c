/* bag_settings.c — a bag's settings snapshot (see bag_settings.h). */
#include "bag_settings.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "af_bag.h"
#include "snapshot_text.h"

/* bag's snapshot into text: false when the bag cannot be read (the
 * session then reports it, as a bag not read, with the reader's line). */
static bool read_one(const char *bag, const char *topic, char *text, bool *found)
{
  return af_bag_read_text(bag, topic, text, AF_SNAPSHOT_MAX_BYTES, found) == AF_OK;
}

/* The first line where a and b differ, for the message. */
static void first_difference(const char *a, const char *b, char *out, size_t len)
{
  while (*a && *a == *b) {
    const char *ea = strchr(a, '\n'), *eb = strchr(b, '\n');
    if (!ea || !eb || ea - a != eb - b || strncmp(a, b, (size_t)(ea - a)) != 0)
      break;
    a = ea + 1;
    b = eb + 1;
  }
  snprintf(out, len, "'%.*s' against '%.*s'", (int)strcspn(a, "\n"), a, (int)strcspn(b, "\n"), b);
}

/* Every readable bag's snapshot against the first readable one's (a bag
 * that cannot be read is left to the session, which reports it). */
static af_bag_settings_result compare_all(char *const *bags, size_t n, const char *topic,
                                          char *first, char *other, char *err, size_t len)
{
  size_t ref = n; /* the first readable bag */
  bool found0 = false, found;
  for (size_t k = 0; k < n; k++) {
    if (!read_one(bags[k], topic, ref == n ? first : other, ref == n ? &found0 : &found))
      continue;
    if (ref == n) {
      ref = k;
      continue;
    }
    if (found != found0) {
      snprintf(err, len,
               "%s holds the node's settings (%s) and %s does not: give --config and "
               "--cultivar to judge them alike, or report them apart",
               found0 ? bags[ref] : bags[k], topic, found0 ? bags[k] : bags[ref]);
      return AF_BAG_SETTINGS_REFUSED;
    }
    if (found && strcmp(first, other) != 0) {
      char diff[512];
      first_difference(other, first, diff, sizeof diff);
      snprintf(err, len,
               "%s was recorded with other settings than %s (%s): report them apart, "
               "or give --config and --cultivar",
               bags[k], bags[ref], diff);
      return AF_BAG_SETTINGS_REFUSED;
    }
  }
  return found0 ? AF_BAG_SETTINGS_READ : AF_BAG_SETTINGS_NONE;
}

af_bag_settings_result af_bag_settings_read(char *const *bags, size_t n, const char *topic,
                                            af_settings *s, char *err, size_t len)
{
  char *first = malloc(AF_SNAPSHOT_MAX_BYTES), *other = malloc(AF_SNAPSHOT_MAX_BYTES);
  af_bag_settings_result r = AF_BAG_SETTINGS_REFUSED;
  if (!first || !other)
    snprintf(err, len, "out of memory for the settings snapshots");
  else if (n > 0)
    r = compare_all(bags, n, topic, first, other, err, len);
  else
    r = AF_BAG_SETTINGS_NONE;
  if (r == AF_BAG_SETTINGS_READ) {
    char why[512];
    if (af_settings_from_snapshot(s, first, why, sizeof why) != AF_OK) {
      snprintf(err, len, "%s is not a settings snapshot of this version: %s", topic, why);
      r = AF_BAG_SETTINGS_REFUSED;
    }
  }
  free(first);
  free(other);
  return r;
}
