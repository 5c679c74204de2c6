#!/usr/bin/env bash
# The main job: the station's replay demo (scripts/demo.sh). Builds if needed,
# synthesizes a bag of strikes (force 50 kHz, audio 48 kHz, an AppleEstimate
# before each), replays it through the station node with replay.launch, and
# prints one line per measured strike against the truth it was made from.
# Arguments go to demo.sh (--strikes N --seed S --rate R --keep DIR).
# The model alone: source devel/setup.bash (the file scripts/build.sh prints);
# rosrun acoustic_firmness firmness_model
set -euo pipefail
exec bash "$(dirname "$0")/demo.sh" "$@"
