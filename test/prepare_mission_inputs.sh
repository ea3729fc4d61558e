#!/usr/bin/env bash
# Test fixture: draws the sketches of the small generated cave and pre-processes the deformed one
# into a prior bundle (OUT/prior.prior), does the same for the
# small garage's precise sketch (OUT/wrong_place.prior: a sketch of another place), records a
# short simulated flight in the cave (OUT/flight.bag) and draws the cave's precise sketch with its
# true placement for the replay (OUT/replay.prior, OUT/replay.prior.truth.yaml), for the
# closed-loop and bag-replay rostests.
#   prepare_mission_inputs.sh BIN_DIR OUT_DIR
set -euo pipefail
bin=$1
out=$2
rm -rf "$out"
mkdir -p "$out"

# prior WORLD VARIANT OUT_FILE: the world's sketch of that variant, pre-processed at the scale
# its sidecar states (the user's guess in these tests).
prior() {
  local world=$1 variant=$2 file=$3
  "$bin/world_view" --world "$world" --size small --seed 1 --out "$out/$world" >/dev/null
  local guess
  guess=$(sed -n 's/^metres_per_pixel: *//p' "$out/$world/${world}_${variant}.yaml")
  "$bin/prior_map_build" --sketch "$out/$world/${world}_${variant}.png" --scale-guess "$guess" \
    --mapping-range 5 --out "$file" >/dev/null
}
prior simple_cave deformed "$out/prior.prior"
prior garage precise "$out/wrong_place.prior"
"$bin/record_flight" --bag "$out/flight.bag" --world simple_cave --size small --seed 1 \
  --variant precise --duration 60 >/dev/null
"$bin/sim_prior" --world simple_cave --size small --seed 1 --variant precise \
  --out "$out/replay.prior" >/dev/null 2>&1
for f in prior.prior wrong_place.prior flight.bag replay.prior replay.prior.truth.yaml; do test -s "$out/$f"; done
