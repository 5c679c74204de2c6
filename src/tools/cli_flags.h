/* cli_flags.h — the model flags of firmness_model: one table maps each flag
 * to a field of af_model_params, its unit and its help text, so parsing,
 * validation messages, sweeps and --help all read the same entries. */
#ifndef AF_CLI_FLAGS_H
#define AF_CLI_FLAGS_H

#include <stdbool.h>
#include <stddef.h>

#include "model.h"

/* Exit code for bad input, as rig scripts expect. */
#define AF_CLI_EXIT_USAGE 2

typedef enum {
  AF_FLAG_DOUBLE,
  AF_FLAG_LOBE,
  AF_FLAG_DAMPING,
  AF_FLAG_BAND,
  AF_FLAG_SHEAR
} af_flag_kind;

typedef struct {
  const char *name;  /* without the leading "--" */
  const char *field; /* af_model_params field, as af_param_error names it */
  af_flag_kind kind;
  size_t offset; /* of the double field in af_model_params (AF_FLAG_DOUBLE only) */
  const char *help;
} af_cli_flag;

/* Finds a flag by name, with or without the leading "--"; NULL if unknown. */
const af_cli_flag *af_cli_flag_find(const char *name);

/* Sets the flag's field from text. false, with a one-line message on stderr
 * naming the flag, when the text is not a value of the flag's kind. */
bool af_cli_flag_set(const af_cli_flag *f, const char *text, af_model_params *p);

/* Reads the flag's field as a number (enumerations as their index). */
double af_cli_flag_get(const af_cli_flag *f, const af_model_params *p);

/* Applies the model flags of argv[first..argc) to p, starting from the
 * profile (--profile default|paper, wherever it stands). Arguments not of the
 * model are left to the caller when *rest is not NULL: their indices are
 * stored in rest[] and counted in *n_rest; otherwise they are errors. Then
 * validates p. A model flag or --profile given twice is refused (which one
 * would win is a silent choice). false after printing a one-line error on stderr. */
bool af_cli_parse_model(int argc, char **argv, int first, af_model_params *p, int *rest,
                        int *n_rest);

/* v as the fewest digits that read back exactly (1000000001, not 1e+09),
 * for a message that prints a value beside its range. */
void af_cli_number_text(double v, char *buf, size_t len);

/* Checks p (af_model_params_check); false after one line on stderr, "TOOL:
 * --FLAG VALUE is outside the accepted range RANGE". */
bool af_cli_validate(const af_model_params *p, const char *tool);

/* "the model flags --E2, --nu2, ..., --profile" into buf (truncated to
 * len), for the line naming what a tool accepts. */
void af_cli_flag_names(char *buf, size_t len);

/* Prints the model flags (every entry of the table, then --profile) with
 * units and defaults for --help, on stdout. */
void af_cli_print_flags(void);

#endif
