/* options.h — the flags of a command-line tool as one table.
 *
 * Each tool (firmness_model and its subcommands, firmness_report,
 * strike_bag, capture_to_bag) lists its flags in a table of af_option, each
 * with how its value is read and its accepted range: the one parser
 * (af_options_parse) reads every tool's arguments from it, and --help is
 * printed from the same table, range included. A flag therefore cannot be accepted without
 * being documented, and the default --help shows is read from the very
 * struct the parser starts from (the tool's *_default() arguments), or from
 * the parameter table row (settings.h) the flag sets — never typed twice.
 *
 * The tools' convention for files: every file written is told by one line
 * "wrote PATH" on stderr (af_options_wrote), so that stdout keeps only the
 * tool's data (JSON, CSV, text) and can be piped. No allocation. */
#ifndef AF_OPTIONS_H
#define AF_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "settings.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How a flag's value is read and held in the tool's arguments struct. The
 * parser (af_options_parse) stores SWITCH to UINT itself; SETTING and NONE
 * are handed back to the tool, which applies them when it is ready. */
typedef enum {
  AF_OPTION_SWITCH,  /* no value; a bool field, shown "off" or "on" */
  AF_OPTION_TEXT,    /* a const char * field (the argument, borrowed); NULL shown as `absent` */
  AF_OPTION_NUMBER,  /* a double field, shown %g; 0 or NaN = not given (`absent`, or required) */
  AF_OPTION_RANGE,   /* "A:B", two doubles (lo, hi) from the field on, A <= B, each in range */
  AF_OPTION_LONG,    /* a long field, a whole number; 0 = not given, as NUMBER */
  AF_OPTION_U64,     /* a uint64_t field, a whole number (digits only: read exactly) */
  AF_OPTION_UINT,    /* an unsigned field, a whole number; 0 = not given, as LONG */
  AF_OPTION_SETTING, /* a row of the parameter table, handed back: default, unit and range
                        from the af_settings given to the help */
  AF_OPTION_NONE     /* handed back (repeatable flags, choices the tool reads); `absent`
                        says what not giving it means */
} af_option_kind;

typedef struct {
  const char *name;    /* with its leading "--" */
  const char *value;   /* placeholder of the value ("FILE", "HZ"); NULL: a switch */
  af_option_kind kind; /* */
  size_t offset;       /* of the field in the tool's arguments struct */
  int setting;         /* SETTING: the row (af_setting_id); NUMBER, RANGE, LONG, UINT: the
                          row whose range applies when `range` is NULL; else -1 */
  const char *range;   /* accepted values and their unit, as the parameter table writes
                          them (settings.h): "(0, 600] s", "[1, 256]", "0 or [1e5, 1e12] Pa";
                          NULL: the row's (setting), else any finite number */
  const char *help;    /* one line (SETTING: NULL = the row's help); the unit in [] when
                          there is no range to carry it */
  const char *absent;  /* what no value means ("stdout", "no plot"); NULL = required when
                          the default is NULL or 0 */
  bool repeat;         /* accepted more than once (--set), handed back each time */
} af_option;

/* The entry of name (exact, with its "--"); NULL when the table has none. */
const af_option *af_option_find(const af_option *table, size_t n, const char *name);

/* ---- the parser ------------------------------------------------------------ */

/* A flag the parser does not store (SETTING, NONE), with its value (NULL for
 * a switch), or a positional argument (o NULL). false after the tool's own
 * one line on stderr: the parse stops, the tool exits 2. */
typedef bool af_option_hand_fn(void *user, const af_option *o, const char *value);

/* One table and where its values go. */
typedef struct {
  const af_option *table;
  size_t n;
  void *args;              /* the stored kinds are written here, at their offsets; NULL:
                              nothing stored (a later pass that only hands back) */
  af_option_hand_fn *hand; /* SETTING and NONE entries, in argv's order; NULL: dropped */
  void *user;              /* hand's */
} af_option_set;

#define AF_OPTIONS_SETS_MAX 2     /* a tool's own flags and the model flags */
#define AF_OPTIONS_ENTRIES_MAX 96 /* entries of the sets together (the "given twice" marks) */

typedef struct {
  const char *tool; /* first word of every message: "firmness_model analyze" */
  af_option_set sets[AF_OPTIONS_SETS_MAX];
  size_t n_sets;
  const char *more; /* named after the flags in the unknown-flag line ("BAG..."); or NULL */
  bool positional;  /* an argument not starting "--" goes to sets[0].hand with o NULL;
                       false: it is an unknown flag */
} af_options_parser;

/* Reads argv[first..argc) against the parser's tables, in order. Refuses,
 * with one line on stderr and false (the tool exits 2): a flag no table holds
 * ("TOOL: unknown flag 'F'; accepted: --a, --b ..."), a flag without its value
 * (the next argument missing or empty), a flag not `repeat` given twice, and
 * a value outside its kind or range. Stores SWITCH..UINT into the set's args;
 * hands SETTING and NONE entries and positional arguments back in order. */
bool af_options_parse(const af_options_parser *p, int argc, char **argv, int first);

/* text as a number: the whole text, finite ("12abc", "", "nan", "inf" and
 * "1e999" are not). The one number reader of the tools' flags. */
bool af_options_read_number(const char *text, double *out);

/* o's accepted interval into r and its text with unit into *text (may be
 * NULL); false when o accepts any finite number. */
bool af_option_range(const af_option *o, af_setting_range *r, const char **text);

/* text as o's number (NUMBER, LONG, U64, UINT, and each end of a RANGE):
 * read, whole for the integer kinds, within o's range; else one line on
 * stderr naming the tool, the flag, the value and the range, and false. */
bool af_option_number(const char *tool, const af_option *o, const char *text, double *out);

/* The one range message, on stderr: "TOOL: FLAG VALUE is outside the
 * accepted range RANGE" and why when not NULL (" with --ode"). VALUE is
 * written as af_options_number_text writes it. */
void af_options_outside(const char *tool, const char *flag, double v, const char *range,
                        const char *why);

/* v as the fewest digits that read back exactly (1000000001, not %g's
 * 1e+09, which would look inside a range that ends at 1e9). */
void af_options_number_text(double v, char *buf, size_t len);

/* The longest argument a tool accepts [bytes]: a path (PATH_MAX) or a
 * value is shorter; a longer one is refused before anything quotes it. */
#define AF_OPTIONS_ARG_MAX_BYTES 4096

/* Every argument of argv[1..argc) is one a message may quote: no control
 * character (a newline in a value would split a one-line refusal) and at
 * most AF_OPTIONS_ARG_MAX_BYTES long (a 100k-character value was echoed
 * whole). Else one line on stderr naming the argument, its length or the
 * character (shown as '?') and its first 40 characters, and false: the
 * tool exits 2 before any work. */
bool af_options_args_plain(const char *tool, int argc, char **argv);

/* True when argv[first..argc) asks for help (--help or -h). */
bool af_options_want_help(int argc, char **argv, int first);

/* A number macro as text, for a help line: AF_OPTION_STR(AF_X_MAX) where
 * AF_X_MAX is a plain literal (600.0, 1e6), so that the help and the check
 * read the same number. */
#define AF_OPTION_STR_(x) #x
#define AF_OPTION_STR(x) AF_OPTION_STR_(x)

/* One line per flag, then -h/--help's: "  --name VALUE  help [unit] (default X,
 * range R)", X read from defaults (the tool's default arguments; may be NULL
 * when no entry reads a field), unit and R from the entry's range (the one
 * the parser applies); for SETTING entries from s with the row's name. */
void af_options_help(FILE *out, const af_option *table, size_t n, const void *defaults,
                     const af_settings *s);

/* The same lines without -h/--help's (a second table under the first). */
void af_options_help_rows(FILE *out, const af_option *table, size_t n, const void *defaults,
                          const af_settings *s);

/* The one line a tool prints for each file it wrote: "wrote PATH" on stderr. */
void af_options_wrote(const char *path);

#ifdef __cplusplus
}
#endif
#endif
