# shellcheck shell=bash
# Sourced by the long background campaigns (scripts/stiffness-plateau.sh, plateau-drop.sh).
# pin_program ROOT PIN: on the first start, copies ROOT/build/cli/ricochet (under the shared build
# lock, so that it never copies a binary being linked) and ROOT/liggghts-inputs/ into PIN, with
# the source state (commit and uncommitted changes of src-ext, liggghts-inputs, cli), so that a
# campaign of days runs one program on one set of decks (an edited deck would change the bed
# cache key and rebuild beds); later starts keep the pinned copy. Delete PIN to take the tree's
# current ones on the next start.
# The decks are the tree's, unless beds were shipped for this results folder (a folder of
# ROOT/data/resolved/beds/ whose pinned-in names it, scripts/ship-beds.sh) with the decks that
# key them (pinned-decks.tar.xz, scripts/pack-decks.py): a new machine then pins those, and finds
# the shipped beds under their keys.
pin_program() {
  local root=$1 pin=$2
  if [ ! -x "$pin/ricochet" ] || [ ! -d "$pin/liggghts-inputs" ]; then
    rm -rf "$pin.tmp" && mkdir -p "$pin.tmp"
    flock /tmp/ricochet-build.lock cp "$root/build/cli/ricochet" "$pin.tmp/ricochet"
    local folder shipped="" other
    folder=$(basename "$(dirname "$pin")")
    for other in "$root"/data/resolved/beds/*/pinned-decks.tar.xz; do
      [ -f "$other" ] || continue
      [ "$(cat "$(dirname "$other")/pinned-in" 2> /dev/null)" = "$folder" ] || continue
      if [ -z "$shipped" ]; then
        shipped=$other
      elif ! cmp -s "$shipped" "$other"; then
        echo "warning: $shipped and $other, both shipped for $folder, hold different decks;" \
          "pinning the first"
      fi
    done
    (cd "$root" && git rev-parse HEAD && git status --short -- src-ext liggghts-inputs cli) \
      > "$pin.tmp/source-state.txt" 2>&1
    if [ -n "$shipped" ]; then
      tar -xJf "$shipped" -C "$pin.tmp"
      echo "decks: $shipped (the decks that key its beds), not the tree's" >> "$pin.tmp/source-state.txt"
    else
      cp -r "$root/liggghts-inputs" "$pin.tmp/liggghts-inputs"
    fi
    rm -rf "$pin" && mv "$pin.tmp" "$pin"
    echo "pinned the program and the decks in $pin${shipped:+ (the decks shipped in $(dirname "$shipped"))}"
  fi
}
