/* settings.h — the one table of the lane's parameters, and a values object
 * checked against it.
 *
 * Every parameter of config/station.yaml and of the cultivar's YAML
 * (config/jonagold.yaml) is one row: its name (= the YAML key = the node's
 * private ROS parameter), its kind, its default, its accepted range with its
 * unit, the file that holds it, whether it may be absent, and a line of help.
 * Nothing else in the package writes a range or a default of these: the node
 * (src/node/params.c) loads its ROS parameters through the table, the desk
 * tools read the same YAML files and `--set name=value` through it,
 * af_model_params_check (model.c) takes its ranges from it, and
 * test/core/test_settings.c checks the shipped YAML files against it.
 *
 * Conventions:
 *  - a range is text, e.g. "[0.05, 10] m/s": "(" / ")" open, "[" / "]" closed,
 *    "inf" unbounded, then the unit (none when dimensionless); "0 or [a, b]"
 *    accepts 0 too (a rigid hammer, a flat face). The numbers are parsed
 *    from that text, so the range shown is the range applied. Every range is
 *    physical, not only mathematical: what a fruit, a hammer or a transducer
 *    can be, so that no accepted value makes the model or the lane work
 *    without bound;
 *  - every error is ONE line, written into err[len] (cut, never overflowing),
 *    naming the parameter, the value and what is accepted:
 *      <name> = <value> is outside the accepted range <range>
 *      <name> = <value> is not a whole number in <range>
 *      <name> = '<text>' is not a number
 *      <name> = '<text>' is not true or false
 *      <name> = '<text>' is not one of: a, b
 *      <name> is missing (...)
 *      unknown parameter '<name>'
 *    Names carry the values object's name prefix ("~" in the node; "" by
 *    default); file errors start with "<path>:<line>: ";
 *  - no allocation anywhere; af_settings is a fixed-size value (copy it freely).
 *    The functions are reentrant (no static state).
 */
#ifndef AF_SETTINGS_H
#define AF_SETTINGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "status.h"

/* Sizes the table's rows state and the modules holding their values use. */
#define AF_SETTINGS_NAME_MAX 64 /* a name row's text (cultivar, hammer_link), with its NUL */
#define AF_SETTINGS_HEALTH_WINDOW_MAX 1000 /* strikes: the upper end of hammer_health_window */

#ifdef __cplusplus
extern "C" {
#endif

/* One id per row, in the order of the YAML files (also the printed order). */
typedef enum {
  /* --- config/station.yaml: the hammer --- */
  AF_SETTING_HAMMER_LINK,
  AF_SETTING_URDF_FILE,
  AF_SETTING_FRAME_PREFIX,
  AF_SETTING_HARDWARE_ID,
  AF_SETTING_HAMMER_MASS_KG,
  AF_SETTING_HAMMER_TIP_RADIUS_M,
  AF_SETTING_HAMMER_MODULUS_PA,
  AF_SETTING_HAMMER_POISSON,
  /* the strike */
  AF_SETTING_STRIKE_VELOCITY_M_S,
  AF_SETTING_GRAVITY_M_S2,
  AF_SETTING_DAMPING_LAW,
  AF_SETTING_LOBE,
  AF_SETTING_BAND_LEVEL,
  AF_SETTING_SHEAR_RATIO,
  /* strike advice */
  AF_SETTING_LATITUDE_TOLERANCE_DEG,
  AF_SETTING_R2_SEARCH_LOW_M,
  AF_SETTING_R2_SEARCH_HIGH_M,
  AF_SETTING_STRIKE_RADIUS_MIN_M,
  AF_SETTING_STRIKE_RADIUS_MAX_M,
  /* streams */
  AF_SETTING_FORCE_SAMPLE_RATE_HZ,
  AF_SETTING_FORCE_BUFFER_S,
  AF_SETTING_AUDIO_SAMPLE_RATE_HZ,
  AF_SETTING_AUDIO_BUFFER_S,
  AF_SETTING_AUDIO_UNIT,
  AF_SETTING_AUDIO_INPUT,
  AF_SETTING_AUDIO_CHANNEL,
  AF_SETTING_AUDIO_FULL_SCALE,
  AF_SETTING_STREAM_STALE_AFTER_S,
  AF_SETTING_STREAM_ABSENT_WARN_S,
  /* the inputs' rate and stamp checks on /diagnostics (rate_status.h) */
  AF_SETTING_FORCE_CHUNK_SAMPLES,
  AF_SETTING_AUDIO_CHUNK_SAMPLES,
  AF_SETTING_STREAM_RATE_TOLERANCE,
  AF_SETTING_STREAM_STAMP_DELAY_MIN_S,
  AF_SETTING_STREAM_STAMP_DELAY_MAX_S,
  AF_SETTING_APPLE_RATE_MIN_HZ,
  AF_SETTING_APPLE_RATE_MAX_HZ,
  AF_SETTING_APPLE_STAMP_DELAY_MIN_S,
  AF_SETTING_APPLE_STAMP_DELAY_MAX_S,
  AF_SETTING_DIAGNOSTIC_RATE_WINDOW,
  AF_SETTING_FORCE_UNIT,
  AF_SETTING_FORCE_SENSITIVITY_V_PER_N,
  /* rviz markers */
  AF_SETTING_MARKERS_ENABLED,
  AF_SETTING_MARKER_LIFETIME_S,
  AF_SETTING_MARKER_STRIKE_DISTANCE_M,
  AF_SETTING_MARKER_ARROW_LENGTH_M,
  /* the live strike picture (~strike_plot) */
  AF_SETTING_STRIKE_PLOT_WIDTH_PX,
  AF_SETTING_STRIKE_PLOT_HEIGHT_PX,
  /* measured strikes: the detector, the queue */
  AF_SETTING_STRIKE_FULL_SCALE_N,
  AF_SETTING_STRIKE_THRESHOLD_NOISE_FACTOR,
  AF_SETTING_STRIKE_THRESHOLD_MIN_N,
  AF_SETTING_STRIKE_PRE_TRIGGER_S,
  AF_SETTING_STRIKE_BASELINE_TIME_CONSTANT_S,
  AF_SETTING_STRIKE_BASELINE_WINDOW_S,
  AF_SETTING_STRIKE_DOUBLE_HIT_GAP_S,
  AF_SETTING_STRIKE_MAX_CONTACT_S,
  AF_SETTING_STRIKE_POST_S,
  AF_SETTING_STRIKE_RISE_FIT_LEVEL,
  AF_SETTING_STRIKE_FALL_FIT_LEVEL,
  AF_SETTING_STRIKE_PENDING_SIZE,
  AF_SETTING_APPLE_STALE_AFTER_S,
  AF_SETTING_APPLE_WAIT_S,
  AF_SETTING_APPLE_TRANSIT_S,
  AF_SETTING_APPLE_TRANSIT_TOLERANCE_S,
  AF_SETTING_STREAM_CLOCK_STEP_S,
  AF_SETTING_AUDIO_LAG_LEARN,
  AF_SETTING_AUDIO_LAG_MAX_S,
  /* measured strikes: the measurement */
  AF_SETTING_MEASURE_FIT_VELOCITY,
  AF_SETTING_MEASURE_AUDIO_DELAY_S,
  AF_SETTING_MEASURE_AUDIO_WINDOW_S,
  AF_SETTING_MEASURE_NOISE_WINDOW_S,
  AF_SETTING_MEASURE_NOISE_GUARD_S,
  AF_SETTING_MEASURE_RANGE_MARGIN,
  AF_SETTING_MEASURE_SNR_THRESHOLD_DB,
  AF_SETTING_MEASURE_HUM_HZ,
  AF_SETTING_MEASURE_HUM_HARMONICS,
  AF_SETTING_MEASURE_NOISE_BAND_LOW_HZ,
  AF_SETTING_MEASURE_NOISE_BAND_HIGH_HZ,
  AF_SETTING_MEASURE_FFT_PADDING,
  /* tap-only mode: strikes from the audio onset (onset.h) */
  AF_SETTING_TAP_ONLY,
  AF_SETTING_ONSET_SNR_DB,
  AF_SETTING_ONSET_HOLDOFF_S,
  AF_SETTING_ONSET_FRAME_S,
  AF_SETTING_ONSET_FLOOR_TIME_CONSTANT_S,
  AF_SETTING_ONSET_FLOOR,
  /* hammer health (hammer_health.h) */
  AF_SETTING_HAMMER_HEALTH_WINDOW,
  AF_SETTING_HAMMER_HEALTH_MIN_STRIKES,
  AF_SETTING_HAMMER_HEALTH_VELOCITY_BAND,
  AF_SETTING_HAMMER_HEALTH_BASELINE_DRIFT_N,
  AF_SETTING_HAMMER_HEALTH_CLIP_RATE,
  /* the modulus factor learned on the line (factor_learn.h) */
  AF_SETTING_MODULUS_FACTOR_LEARN_WINDOW,
  AF_SETTING_MODULUS_FACTOR_LEARN_MIN_STRIKES,
  AF_SETTING_MODULUS_FACTOR_LEARN_APPLY,
  AF_SETTING_MODULUS_FACTOR_LEARN_MIN_CHANGE,
  /* --- the cultivar's YAML (config/jonagold.yaml) --- */
  AF_SETTING_CULTIVAR,
  AF_SETTING_MODULUS_NOMINAL_PA,
  AF_SETTING_MODULUS_MIN_PA,
  AF_SETTING_MODULUS_MAX_PA,
  AF_SETTING_MASS_MIN_KG,
  AF_SETTING_MASS_MAX_KG,
  AF_SETTING_EQUATORIAL_RADIUS_MIN_M,
  AF_SETTING_EQUATORIAL_RADIUS_MAX_M,
  AF_SETTING_ASPECT_RATIO_MIN,
  AF_SETTING_ASPECT_RATIO_MAX,
  AF_SETTING_RESTITUTION,
  AF_SETTING_FRUIT_POISSON,
  AF_SETTING_DENSITY_KG_M3,
  AF_SETTING_FRUIT_Q_MIN,
  AF_SETTING_FRUIT_Q_MAX,
  AF_SETTING_FRUIT_CONFIDENCE_MIN,
  AF_SETTING_FRUIT_NEIGHBOUR_MARGIN_DB,
  AF_SETTING_YIELD_RATIO,
  AF_SETTING_YIELD_EXPONENT,
  AF_SETTING_YIELD_REFERENCE_MODULUS_PA,
  AF_SETTING_YIELD_MEASURED,
  AF_SETTING_MODULUS_FACTOR,
  /* firmness grades of measured strikes (grade.h) */
  AF_SETTING_GRADE_QUANTITY,
  AF_SETTING_GRADE_CLASSES,
  /* the second damage reading: the strike's absorbed energy (model.h) */
  AF_SETTING_BRUISE_ENERGY_J,
  AF_SETTING_COUNT
} af_setting_id;

typedef enum {
  AF_SETTING_NUMBER, /* a double within its range */
  AF_SETTING_WHOLE,  /* a whole number within its range (held as a double) */
  AF_SETTING_BOOL,   /* true or false */
  AF_SETTING_STRING, /* free text of at most max_chars characters */
  AF_SETTING_CHOICE  /* one of the words of choices */
} af_setting_kind;

/* Which file holds a row (bit masks, for af_settings_check_required and
 * af_settings_print). */
#define AF_SETTINGS_STATION 1u  /* config/station.yaml */
#define AF_SETTINGS_CULTIVAR 2u /* the cultivar's YAML, e.g. config/jonagold.yaml */
#define AF_SETTINGS_ALL 3u

#define AF_SETTINGS_TEXT_MAX 512 /* longest string value (a path), with its NUL */
/* string rows: hammer_link, urdf_file, frame_prefix, hardware_id, cultivar, yield_measured,
 * grade_classes (test_settings checks the count against the table) */
#define AF_SETTINGS_STRINGS 7
#define AF_SETTINGS_PREFIX_MAX 8 /* name prefix in messages, with its NUL */

/* One row of the table. */
typedef struct {
  const char *name;     /* YAML key = the node's private parameter */
  af_setting_kind kind; /* */
  const char *def;      /* default, written as in the YAML ("1.4", "true", "exact", "");
                           NULL = absent (optional rows) */
  const char *range;    /* number and whole rows: "(0, 10] m/s"; NULL otherwise */
  const char *choices;  /* choice rows: "paper, exact, hu-guo"; NULL otherwise */
  unsigned file;        /* AF_SETTINGS_STATION or AF_SETTINGS_CULTIVAR */
  bool optional;        /* may be absent */
  bool zero_is_absent;  /* a 0 stands for absent (optional rows) */
  const char *absent;   /* optional rows: what absence means, e.g. "from the URDF" */
  size_t max_chars;     /* string rows: longest accepted value */
  const char *help;     /* one line */
  const char *rig;      /* optional hammer rows: the shipped rig's value (config/rig.urdf,
                           which test_urdf checks against it), what a tool that reads no
                           URDF takes; NULL otherwise */
} af_setting_def;

/* A row's accepted interval, parsed from its range text. */
typedef struct {
  double lo, hi;
  bool lo_open, hi_open;
  bool zero; /* 0 is accepted too ("0 or [lo, hi]") */
} af_setting_range;

/* "(lo, hi] unit" or "0 or [lo, hi] unit" (the grammar above): the interval
 * and where the unit starts (unit may be NULL); false on a malformed text.
 * Also read by the tools' flag tables (options.h), whose ranges are written
 * the same way. */
bool af_setting_parse_range(const char *text, af_setting_range *r, const char **unit);

/* The row of id; NULL when id is not a row. */
const af_setting_def *af_setting_def_of(af_setting_id id);
/* AF_OK and *id for a row name; AF_EINVAL when name is no row. */
af_status af_setting_find(const char *name, af_setting_id *id);
/* AF_OK and *out for number and whole rows; AF_EINVAL for other rows or a
 * malformed range text (the test checks there is none). */
af_status af_setting_range_of(af_setting_id id, af_setting_range *out);
/* v finite and inside r. */
bool af_setting_range_contains(const af_setting_range *r, double v);
/* The shipped rig's value of an optional hammer row (af_setting_def.rig),
 * e.g. 0.010 for hammer_mass_kg [kg]; NAN for every other row. */
double af_setting_rig_value(af_setting_id id);
/* The unit of a row: the end of its range text ("m/s"), "" when none. */
const char *af_setting_unit(af_setting_id id);
/* Word k of a choice row into buf (k = 0, 1, ...); AF_EINVAL past the last
 * word or for other rows. */
af_status af_setting_choice_word(af_setting_id id, size_t k, char *buf, size_t len);

/* The values of every row: defaults, then what files, flags or parameters set. */
typedef struct {
  double value[AF_SETTING_COUNT]; /* number, whole, bool (0 or 1), choice (word index); NAN
                                     while an optional row is absent */
  bool given[AF_SETTING_COUNT];   /* set by a file, a flag or a parameter (not the default) */
  bool present[AF_SETTING_COUNT]; /* holds a value (default or given); false = absent */
  char text[AF_SETTINGS_STRINGS][AF_SETTINGS_TEXT_MAX]; /* the string rows, in row order */
  char name_prefix[AF_SETTINGS_PREFIX_MAX];             /* before every name in messages */
} af_settings;

/* Every row at its default (optional rows absent), nothing given, prefix "". */
void af_settings_reset(af_settings *s);
/* Names in messages become prefix + name, e.g. "~" for ROS private
 * parameters. Cut to AF_SETTINGS_PREFIX_MAX - 1 characters. */
void af_settings_set_name_prefix(af_settings *s, const char *prefix);

/* Typed values (the node's ROS parameters), checked against the row of id.
 * set_number on a number or whole row; set_bool on a bool row; set_string on
 * a string or choice row. A value of another type is refused with the line
 * of the row's kind ("is not a number", "is not one of: ..."; a string that
 * is a C number, such as a ROS string "8.0e6", with the YAML 1.1 hint). A
 * number 0 on a zero_is_absent row makes it absent. On AF_EINVAL s is
 * unchanged. */
af_status af_settings_set_number(af_settings *s, af_setting_id id, double v, char *err, size_t len);
af_status af_settings_set_bool(af_settings *s, af_setting_id id, bool v, char *err, size_t len);
af_status af_settings_set_string(af_settings *s, af_setting_id id, const char *v, char *err,
                                 size_t len);

/* One value as a YAML 1.1 scalar, as rosparam would type it: 'single' or
 * "double" quoted = a string; bare true/false/yes/no/on/off = a bool; a bare
 * integer (12, 0x1f, 010 octal, 1_000) or float (1.4, .5, 8.0e+6, .inf) = a
 * number; any other bare word = a string. So 8.0e6 (no exponent sign) and
 * 1e+6 (no dot) are strings, refused for a number row with a hint: the node
 * would be given a string for them too. AF_EINVAL for an unknown name or a
 * refused value. */
af_status af_settings_set_text(af_settings *s, const char *name, const char *text, char *err,
                               size_t len);
/* A command-line "name=value": as set_text, except that a numeric row also
 * takes any complete C number (8e6). AF_EINVAL without '=' too. */
af_status af_settings_set_arg(af_settings *s, const char *arg, char *err, size_t len);

/* Reads a flat YAML file of `key: value  # comment` lines (blank lines and
 * comment lines skipped; values as in set_text; a comment needs a blank
 * before its '#'). Every key must be a row; a key given twice, an unknown
 * key, a line that is not `key: value` (indentation, lists, flow values,
 * tags, anchors, block scalars, a line over 1023 characters) and a refused
 * value give AF_EINVAL with "<path>:<line>: <reason>"; a file that cannot be
 * opened or read gives AF_EIO with "<path>: <reason>". All or nothing: on
 * failure s is unchanged. Keys of the other file are accepted (the node
 * loads both files into one namespace). */
af_status af_settings_load_yaml(af_settings *s, const char *path, char *err, size_t len);

/* AF_OK when every required (not optional) row of files has been given;
 * else AF_EINVAL with "<name> is missing (...)" for the first one. */
af_status af_settings_check_required(const af_settings *s, unsigned files, char *err, size_t len);

bool af_settings_given(const af_settings *s, af_setting_id id);
/* For tools that read no URDF (analyze, firmness_report): each hammer row
 * still absent takes the shipped rig's value (af_setting_rig_value), as if
 * given. AF_OK; an error (into err) only if a rig value left its range. */
af_status af_settings_use_rig_hammer(af_settings *s, char *err, size_t len);
/* Absent optional rows read as not present. */
bool af_settings_present(const af_settings *s, af_setting_id id);
/* Number, whole, bool (0/1) or choice (word index); NAN when absent or no row. */
double af_settings_number(const af_settings *s, af_setting_id id);
bool af_settings_bool(const af_settings *s, af_setting_id id);
/* A string row's text (the values object's own storage); NULL for other rows. */
const char *af_settings_string(const af_settings *s, af_setting_id id);
/* A choice row's word into buf; AF_EINVAL for other rows. */
af_status af_settings_choice(const af_settings *s, af_setting_id id, char *buf, size_t len);
/* The value as it would be written in the YAML ("1.4", "true", "exact",
 * "\"\"" for an empty string, "absent"). */
void af_settings_value_text(const af_settings *s, af_setting_id id, char *buf, size_t len);

typedef enum {
  AF_SETTINGS_PRINT_TEXT,    /* aligned columns: name, kind, default, range + unit, file, help */
  AF_SETTINGS_PRINT_MARKDOWN /* doc/parameters.md's form: "- **name** (kind, default, range, unit):
                                help" */
} af_settings_print_format;

/* Prints the rows of files (defaults from the table). */
void af_settings_print(FILE *out, unsigned files, af_settings_print_format format);

#ifdef __cplusplus
}
#endif
#endif
