#!/usr/bin/env bash
# Test fixture: draws the sketches of the small generated cave, pre-processes the deformed one
# into a prior bundle (OUT/prior.prior) and records a short simulated flight (OUT/flight.bag), for
# the closed-loop and bag-replay rostests.
#   prepare_mission_inputs.sh BIN_DIR OUT_DIR
set -euo pipefail
bin=$1
out=$2
rm -rf "$out"
mkdir -p "$out"
"$bin/world_view" --world simple_cave --size small --seed 1 --out "$out" >/dev/null
guess=$(sed -n 's/^metres_per_pixel: *//p' "$out/simple_cave_deformed.yaml")
"$bin/prior_map_build" --sketch "$out/simple_cave_deformed.png" --scale-guess "$guess" \
  --mapping-range 5 --out "$out/prior.prior" >/dev/null
"$bin/record_flight" --bag "$out/flight.bag" --world simple_cave --size small --seed 1 \
  --variant deformed --duration 30 >/dev/null
test -s "$out/prior.prior" && test -s "$out/flight.bag"
