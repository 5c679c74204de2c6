/* fuzz_yaml.c — libFuzzer harness: the parameter table's flat YAML reader
 * (af_settings_load_yaml, as the desk tools read config/station.yaml and the
 * cultivar's file) on arbitrary file contents, then, when the file is read,
 * af_lane_config_derive with the shipped hammer: every cross-check, the
 * memory estimate before any allocation, the trial creates. Any refusal is
 * one line; no input may crash, hang, allocate without bound or trip a
 * sanitizer. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_scratch.h"
#include "lane_config.h"
#include "settings.h"

static void one_line(const char *err)
{
  if (err[0] == '\0' || strchr(err, '\n') != NULL)
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
  const char *path = af_fuzz_scratch(0, "yaml", "yaml"); /* fuzz_scratch.h */
  FILE *f = fopen(path, "wb");
  if (f == NULL)
    return 0;
  fwrite(data, 1, size, f);
  fclose(f);
  af_settings s;
  char err[512] = "";
  af_settings_reset(&s);
  af_status st = af_settings_load_yaml(&s, path, err, sizeof err);
  if (st != AF_OK) {
    one_line(err);
    return 0;
  }
  if (!af_settings_present(&s, AF_SETTING_HAMMER_MASS_KG))
    (void)af_settings_set_arg(&s, "hammer_mass_kg=0.01", err, sizeof err);
  if (!af_settings_present(&s, AF_SETTING_HAMMER_TIP_RADIUS_M))
    (void)af_settings_set_arg(&s, "hammer_tip_radius_m=0", err, sizeof err);
  af_lane_config c;
  err[0] = '\0';
  if (af_lane_config_derive(&s, &c, err, sizeof err) != AF_OK)
    one_line(err);
  return 0;
}
