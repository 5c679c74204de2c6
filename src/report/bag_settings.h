/* bag_settings.h — the settings a bag was recorded with: the node's
 * snapshot on /NS/settings (std_msgs/String, latched; src/node/snapshot.h),
 * which launch/record.launch records. firmness_report judges a bag with it
 * when it is there and no file is given, so that a bag is judged again as
 * the node judged it live, not with today's files. */
#ifndef AF_REPORT_BAG_SETTINGS_H
#define AF_REPORT_BAG_SETTINGS_H

#include <stdbool.h>
#include <stddef.h>

#include "settings.h"

typedef enum {
  AF_BAG_SETTINGS_NONE,   /* no bag holds a snapshot */
  AF_BAG_SETTINGS_READ,   /* every bag holds the same one: read into s */
  AF_BAG_SETTINGS_REFUSED /* unreadable, or the bags disagree: err says which and why */
} af_bag_settings_result;

/* The snapshot on topic (e.g. "/lane1/settings") of every bag: none, the
 * same in every bag (read into s, which is reset first), or refused: some
 * bags hold one and others not, two differ, one is not a snapshot of this
 * version's rows. */
af_bag_settings_result af_bag_settings_read(char *const *bags, size_t n, const char *topic,
                                            af_settings *s, char *err, size_t len);

#endif
