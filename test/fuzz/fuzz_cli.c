/* fuzz_cli.c — libFuzzer harness: firmness_model's model flags
 * (src/tools/cli_flags.c: af_cli_parse_model, which validates through
 * af_model_params_check and the parameter table's physical ranges), then,
 * for what is accepted, one full model evaluation and the R2_min search, and
 * every argument as a `--set name=value` of the table. The input is the
 * argument list, NUL-separated. Accepted flags must evaluate within the
 * budgets (a status, never a hang); refused ones are refused with one line;
 * no input may crash or trip a sanitizer. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_flags.h"
#include "settings.h"

#define AF_FUZZ_ARGS 24
#define AF_FUZZ_TEXT 4096

static af_model *model;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  static char text[AF_FUZZ_TEXT + 1];
  char *argv[AF_FUZZ_ARGS + 2];
  if (model == NULL && af_model_create(&model) != AF_OK)
    abort();
  size_t n = size < AF_FUZZ_TEXT ? size : AF_FUZZ_TEXT;
  memcpy(text, data, n);
  text[n] = '\0';
  int argc = 0;
  argv[argc++] = "firmness_model";
  for (char *p = text; argc < AF_FUZZ_ARGS + 1 && p < text + n; p += strlen(p) + 1)
    argv[argc++] = p;
  argv[argc] = NULL;

  af_settings s;
  char err[512];
  af_settings_reset(&s);
  for (int k = 1; k < argc; k++) {
    err[0] = '\0';
    if (af_settings_set_arg(&s, argv[k], err, sizeof err) != AF_OK &&
        (err[0] == '\0' || strchr(err, '\n') != NULL))
      abort(); /* a refusal is one line */
  }

  af_model_params p;
  if (!af_cli_parse_model("firmness_model", NULL, NULL, argc, argv, 1, &p))
    return 0;
  af_model_result r;
  af_status st = af_model_execute(model, &p, &r);
  if (st == AF_EINVAL)
    abort(); /* the parser accepted what the model refuses */
  if (st == AF_OK && (data[0] & 1)) {
    double r_min;
    (void)af_model_min_strike_radius(model, &p, 0.002, 0.5, &r_min);
  }
  return 0;
}
