#!/usr/bin/env bash
# At a session's end, lanes running: ships every campaign that scripts/stiffness-plateau.sh has
# run in this work tree (it writes RESULTS/running, "DESIGN-NAME FILE", when it starts one): the
# campaign file so far into data/resolved/ (scripts/ship-campaign.sh, which prints the counts that
# tests/cli/shipped_data_test.cpp and data/resolved/README.md quote) and what its impacts still to
# run need on a new machine, built or in flight (scripts/ship-beds.sh: beds, a bed build's latest
# checkpoint, an impact's), the beds keyed by the campaign's pinned program and decks (the file's
# counts by the tree's program, which finds its decks where a pinned copy does not); a campaign
# whose impacts are as shipped keeps its file, and one with nothing left to build gets no beds
# folder (both scripts see to that). Then commit
# data/resolved/ and update the counts where the file gained impacts.
#
#   scripts/ship-session.sh
#
# Exit 0 when every campaign shipped, 1 when one failed (the others are still shipped).
set -uo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
cd "$ROOT" || exit 1
rc=0
for marker in results/*/running; do
  [ -f "$marker" ] || continue
  dir=$(dirname "$marker")
  read -r name file < "$marker"
  design=$dir/pinned/$name.toml
  if [ ! -f "$dir/$file.h5" ] || [ ! -f "$design" ]; then
    echo "== $dir: no campaign file $file.h5 or pinned design $name yet: nothing to ship"
    continue
  fi
  echo "== $dir ($name into $file.h5)"
  scripts/ship-campaign.sh "$design" "$dir/$file.h5" || rc=1
  scripts/ship-beds.sh "$design" "$dir/$file.h5" "$dir/pinned/ricochet" || rc=1
done
exit "$rc"
