/* settings_doc — prints the parameter reference of doc/parameters.md from the
 * one parameter table (src/core/settings_table.c), so that no default, range or
 * unit of the docs is typed a second time:
 *
 *   settings_doc            the generated part of doc/parameters.md, markdown
 *
 * Two lists, the rows of config/station.yaml and those of the cultivar's
 * YAML, each row as af_settings_print writes it:
 * "- **name** (kind, default, range, unit): help." test/scripts/
 * test_doc_parameters.sh checks that doc/parameters.md holds exactly this
 * between its "generated" markers; `bash scripts/docs.sh` rewrites it.
 * Installed with the package (`rosrun acoustic_firmness af_settings_doc`).
 * Exit 0, or 1 when stdout cannot be written. */
#include <stdio.h>

#include "settings.h"

int main(void)
{
  puts("### config/station.yaml (the station: rig, strike, streams, detector, measurement)\n");
  af_settings_print(stdout, AF_SETTINGS_STATION, AF_SETTINGS_PRINT_MARKDOWN);
  puts("\n### The cultivar's YAML (config/jonagold.yaml)\n");
  af_settings_print(stdout, AF_SETTINGS_CULTIVAR, AF_SETTINGS_PRINT_MARKDOWN);
  return fflush(stdout) == 0 && !ferror(stdout) ? 0 : 1;
}
