/* snapshot_text.h — the settings a lane runs with, as text: what the node
 * publishes latched on NS/settings (std_msgs/String) so that a recording
 * holds them, and what firmness_report reads back from a bag.
 *
 * The text is flat YAML, one `name: value` line per row that holds a value
 * (an absent optional row is left out), in the table's order, each value as
 * af_settings_value_text writes it: a number in the fewest digits that read
 * back as the same double, so a snapshot read back gives the very settings
 * it was made from. */
#ifndef AF_SNAPSHOT_TEXT_H
#define AF_SNAPSHOT_TEXT_H

#include <stddef.h>

#include "settings.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The longest snapshot [bytes, with its NUL]: every row's name, ": ", its
 * longest value (a string row's, quoted and escaped) and a newline. */
#define AF_SNAPSHOT_MAX_BYTES ((size_t)AF_SETTING_COUNT * (2 * AF_SETTINGS_TEXT_MAX + 80))

/* The snapshot of s into buf (len bytes). AF_OK; AF_ESIZE when it does not
 * fit (buf then holds the lines that did, whole). */
af_status af_settings_snapshot(const af_settings *s, char *buf, size_t len);

/* Reads a snapshot into s, after af_settings_reset: every line must be
 * `name: value` of a row (values as af_settings_set_text reads them), no row
 * twice. AF_OK; AF_EINVAL with "line N: cause" in err, s then unchanged. */
af_status af_settings_from_snapshot(af_settings *s, const char *text, char *err, size_t len);

#ifdef __cplusplus
}
#endif
#endif
