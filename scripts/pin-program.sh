# shellcheck shell=bash
# Sourced by the long background campaigns (scripts/stiffness-plateau.sh, plateau-drop.sh).
# pin_program ROOT PIN: on the first start, copies ROOT/build/cli/ricochet (under the shared build
# lock, so that it never copies a binary being linked) and ROOT/liggghts-inputs/ into PIN, with
# the source state (commit and uncommitted changes of src-ext, liggghts-inputs, cli), so that a
# campaign of days runs one program on one set of decks (an edited deck would change the bed
# cache key and rebuild beds); later starts keep the pinned copy. Delete PIN to take the tree's
# current ones on the next start.
pin_program() {
  local root=$1 pin=$2
  if [ ! -x "$pin/ricochet" ] || [ ! -d "$pin/liggghts-inputs" ]; then
    rm -rf "$pin.tmp" && mkdir -p "$pin.tmp"
    flock /tmp/ricochet-build.lock cp "$root/build/cli/ricochet" "$pin.tmp/ricochet"
    cp -r "$root/liggghts-inputs" "$pin.tmp/liggghts-inputs"
    (cd "$root" && git rev-parse HEAD && git status --short -- src-ext liggghts-inputs cli) \
      > "$pin.tmp/source-state.txt" 2>&1
    rm -rf "$pin" && mv "$pin.tmp" "$pin"
    echo "pinned the program and the decks in $pin"
  fi
}
