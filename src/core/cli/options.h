/* options.h — the flags of a command-line tool as one table.
 *
 * Each tool (firmness_model and its subcommands, firmness_report,
 * strike_bag) lists its flags in a table of af_option: the parser asks the
 * table whether a flag exists and whether it takes a value, and --help is
 * printed from the same table. A flag therefore cannot be accepted without
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

/* How a flag's value is held in the tool's arguments struct (for the
 * default --help shows) — the parsing itself stays with the tool. */
typedef enum {
  AF_OPTION_SWITCH,  /* no value; a bool field, shown "off" or "on" */
  AF_OPTION_TEXT,    /* a const char * field; NULL shown as the row's `absent` */
  AF_OPTION_NUMBER,  /* a double field, shown %g; 0 = not given (`absent`, or required) */
  AF_OPTION_RANGE,   /* two doubles (lo, hi) from the field on, shown A:B */
  AF_OPTION_LONG,    /* a long field, as NUMBER */
  AF_OPTION_U64,     /* a uint64_t field */
  AF_OPTION_SETTING, /* a row of the parameter table: default, unit and range
                        from the af_settings given to the help */
  AF_OPTION_NONE     /* no default to show (repeatable flags, choices the tool
                        handles); `absent` says what not giving it means */
} af_option_kind;

typedef struct {
  const char *name;    /* with its leading "--" */
  const char *value;   /* placeholder of the value ("FILE", "HZ"); NULL: a switch */
  af_option_kind kind; /* */
  size_t offset;       /* of the field in the tool's arguments struct */
  int setting;         /* AF_OPTION_SETTING: the row (af_setting_id); else -1 */
  const char *help;    /* one line, the unit in [] (SETTING: NULL = the row's help) */
  const char *absent;  /* what no value means ("stdout", "no plot"); NULL = required when
                          the default is NULL or 0 */
} af_option;

/* The entry of name (exact, with its "--"); NULL when the table has none. */
const af_option *af_option_find(const af_option *table, size_t n, const char *name);

/* Stores a SWITCH (true) or TEXT (value, borrowed) entry into the tool's
 * arguments struct args; false for other kinds, which the tool parses. */
bool af_option_store(const af_option *o, const char *value, void *args);

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

/* One line per flag, then -h/--help's: "  --name VALUE  help [unit] (default X)", X read from
 * defaults (the tool's default arguments; may be NULL when no entry reads a
 * field) or, for SETTING entries, from s with the row's name, unit and range. */
void af_options_help(FILE *out, const af_option *table, size_t n, const void *defaults,
                     const af_settings *s);

/* The one line (stderr) for a flag the table does not hold: "TOOL: unknown
 * flag 'FLAG'; accepted: --a, --b, ... [and MORE] (TOOL --help: units and
 * defaults)". more may be NULL (e.g. "the model flags"). */
void af_options_unknown(const char *tool, const af_option *table, size_t n, const char *flag,
                        const char *more);

/* The one line (stderr) for a flag given without its value: "TOOL: FLAG
 * needs a value: VALUE, help". */
void af_options_missing(const char *tool, const af_option *o);

/* argv[k] is o's name: true when argv[first..k) does not hold it already;
 * else one line (stderr) "TOOL: FLAG is given twice ...; it is accepted
 * once" and false. A single-valued flag given twice is refused rather than
 * the last silently winning; repeatable flags (--set) are not passed here. */
bool af_options_once(const char *tool, const af_option *o, char **argv, int first, int k);

/* The one line a tool prints for each file it wrote: "wrote PATH" on stderr. */
void af_options_wrote(const char *path);

#ifdef __cplusplus
}
#endif
#endif
