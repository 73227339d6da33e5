#!/usr/bin/env bash
# The environment pictures of the documentation site (docs/assets/envs/), made by `carl-spec render`.
# Committed; run this again when a renderer or a default context changes, and commit the result:
#   scripts/docs/render_envs.sh            # uses CARL_SPEC_BIN, default target/release/carl-spec
# Environments without a renderer (the classic-control five, rna_design) get no picture; Mario's
# levels are Nintendo-derived data that the repository never holds, so no picture of it is shipped.
set -euo pipefail
cd "$(dirname "$0")/../.."
bin="${CARL_SPEC_BIN:-target/release/carl-spec}"
out=docs/assets/envs
mkdir -p "$out"
# Episodes of the built-in heuristic controllers, as animated GIFs (every 4th frame).
for env in lunar_lander bipedal_walker; do
  "$bin" render "$env" --seed 0 --policy heuristic --steps 200 --every 4 --out "$out/$env.gif" --force
done
# The reset state at the default context.
for env in vehicle_racing ant half_cheetah humanoid ur5e fetch grasp; do
  "$bin" render "$env" --seed 0 --out "$out/$env.png" --force
done
# The figure of the Landing-in-Space guide and the LunarLander picture of the rendering guide.
"$bin" plot lunar_lander/landing_in_space_train --mark lunar_lander/landing_in_space_test_planets \
  --out docs/assets/images/landing_in_space.png --force
"$bin" plot lunar_lander/landing_in_space_train --mark lunar_lander/landing_in_space_test_planets \
  --out docs/assets/images/landing_in_space.svg --force
"$bin" render lunar_lander --seed 0 --policy heuristic --steps 120 --out docs/assets/images/lunar_lander.png --force
