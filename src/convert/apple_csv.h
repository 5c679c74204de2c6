/* apple_csv.h — a lab's apple list: one row per apple that was struck, with
 * what the vision system would have said of it (msg/AppleEstimate.msg), for
 * capture_to_bag.
 *
 * A header row names the columns, in any order, each exactly once:
 *   apple_id, stamp_s, mass_kg, equatorial_radius_m, strike_radius_m,
 *   stem_axis_x, stem_axis_y, stem_axis_z, confidence
 * then one row per apple. Fields are plain numbers (blanks around them
 * ignored); blank lines are skipped; CRLF is accepted. Every field is
 * checked, with one line naming the file, the line, the column, the value
 * and the accepted range:
 *   apple_id             whole number in [1, 4294967295], unique
 *   stamp_s              the estimate's time from the force recording's
 *                        start [s], within [stamp_min_s, stamp_max_s], rows
 *                        in time order (equal stamps allowed)
 *   mass_kg              the range of the parameter table's mass_min_kg row
 *   equatorial_radius_m  the range of its equatorial_radius_min_m row
 *   strike_radius_m      0 (unknown) or the range of strike_radius_min_m
 *   stem_axis_x/_y/_z    any finite number (all 0 = unknown)
 *   confidence           [0, 1]
 * (A station refuses apples outside its cultivar's narrower mass and radius
 * bounds when it reads them, as it would a camera's.) */
#ifndef AF_APPLE_CSV_H
#define AF_APPLE_CSV_H

#include <stddef.h>
#include <stdint.h>

#include "status.h"

#ifdef __cplusplus
extern "C" {
#endif

#define AF_APPLE_CSV_MAX_ROWS ((size_t)100000)
#define AF_APPLE_CSV_LINE_MAX 1024 /* characters per line, with its end */

typedef struct {
  uint32_t apple_id;
  double stamp_s; /* from the force recording's start [s] */
  double mass_kg, equatorial_radius_m, strike_radius_m;
  double stem_axis[3]; /* any length; zero = unknown */
  double confidence;   /* [0, 1] */
} af_csv_apple;

/* Reads the list at path into *out (*n rows, at least one; free() it).
 * AF_EIO (cannot read), AF_EINVAL (a bad header, row or field, no row),
 * AF_ESIZE (over AF_APPLE_CSV_MAX_ROWS), AF_ENOMEM, with one line in err;
 * *out is then NULL. */
af_status af_apple_csv_read(const char *path, double stamp_min_s, double stamp_max_s,
                            af_csv_apple **out, size_t *n, char *err, size_t len);

#ifdef __cplusplus
}
#endif
#endif
