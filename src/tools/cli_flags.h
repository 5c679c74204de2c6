/* cli_flags.h — the model flags of firmness_model: one af_option table
 * (options.h) maps each flag to a field of af_model_params and to the row of
 * the parameter table whose range af_model_params_check applies, so the one
 * parser reads them, checks their range and --help prints them from the same
 * entries. */
#ifndef AF_CLI_FLAGS_H
#define AF_CLI_FLAGS_H

#include <stdbool.h>
#include <stddef.h>

#include "model.h"
#include "options.h"

/* Exit code for bad input, as rig scripts expect. */
#define AF_CLI_EXIT_USAGE 2

/* The model flags: the numbers (NUMBER; lobe UINT) stored into
 * af_model_params, the choices (SETTING) and --profile (NONE) handed back. */
const af_option *af_cli_model_options(size_t *n);

/* The number flag NAME (without its "--") of the model: a NUMBER or UINT
 * entry; NULL for another name or a choice. */
const af_option *af_cli_model_number(const char *name);

/* Sets the number flag o of p to v (checked already). */
void af_cli_model_set(const af_option *o, double v, af_model_params *p);

/* The number flag o of p. */
double af_cli_model_get(const af_option *o, const af_model_params *p);

/* Parses argv[first..argc): the tool's own flags (own, may be NULL; first in
 * the unknown-flag line, `more` after all) and the model flags into *p, from
 * the parameter table's defaults; --profile (wherever it stands) then the
 * choice flags applied after the numbers, then p validated. false after one
 * line on stderr starting "TOOL: ". */
bool af_cli_parse_model(const char *tool, const af_option_set *own, const char *more, int argc,
                        char **argv, int first, af_model_params *p);

/* Checks p (af_model_params_check); false after one line on stderr, "TOOL:
 * --FLAG VALUE is outside the accepted range RANGE". */
bool af_cli_validate(const af_model_params *p, const char *tool);

/* Prints the model flags with units, defaults and ranges for --help, on
 * stdout (no -h line). */
void af_cli_print_flags(void);

#endif
