#!/usr/bin/env bash
# The environment pictures of the documentation site (docs/assets/envs/), made by `carl-spec render`.
# Committed; run this again when a renderer or a default context changes, or an environment is
# added, and commit the result:
#   scripts/docs/render_envs.sh            # uses CARL_SPEC_BIN, default target/release/carl-spec
# Which environments get a picture, and how, is in the front matter of each environment's page
# (crates/carl-envs-<family>/docs/<id>.md: `picture: gif --seed 0 --policy heuristic --steps 200
# --every 4` for an episode of the heuristic controller, `picture: png --seed 0` for the reset
# state), listed by `gen_pages.py --pictures`. Environments without a renderer (the classic-control
# five, rna_design) have none; Mario's levels are Nintendo-derived data that the repository never
# holds, so no picture of it is shipped.
set -euo pipefail
cd "$(dirname "$0")/../.."
bin="${CARL_SPEC_BIN:-target/release/carl-spec}"
export CARL_SPEC_BIN="$bin"
python="${PYTHON:-python3}"
out=docs/assets/envs
mkdir -p "$out"
"$python" scripts/docs/gen_pages.py --pictures | while read -r env fmt args; do
  # shellcheck disable=SC2086  # the page's render arguments, split on spaces
  "$bin" render "$env" $args --out "$out/$env.$fmt" --force
done
# The figure of the Landing-in-Space guide and the LunarLander picture of the rendering guide.
"$bin" plot lunar_lander/landing_in_space_train --mark lunar_lander/landing_in_space_test_planets \
  --out docs/assets/images/landing_in_space.png --force
"$bin" plot lunar_lander/landing_in_space_train --mark lunar_lander/landing_in_space_test_planets \
  --out docs/assets/images/landing_in_space.svg --force
"$bin" render lunar_lander --seed 0 --policy heuristic --steps 120 --out docs/assets/images/lunar_lander.png --force
