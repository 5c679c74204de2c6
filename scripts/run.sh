#!/usr/bin/env bash
# The main job: builds if needed, then runs the impact model on the paper's
# optimal strike (extra arguments go to firmness_model, e.g. --json).
set -euo pipefail
source "$(dirname "$0")/env.sh"
[ -x "$AF_BUILD/devel/lib/acoustic_firmness/firmness_model" ] || {
  bash "$AF_ROOT/scripts/setup.sh"
  bash "$AF_ROOT/scripts/build.sh"
}
af_source_devel
exec rosrun acoustic_firmness firmness_model "$@"
