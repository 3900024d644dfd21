#!/usr/bin/env bash
# Puts back on a new machine what scripts/ship-beds.sh shipped for a campaign, so that it resumes
# where the last machine left it instead of building and running again:
#   - each complete bed (bed-KEY.restart.xz and .params) into the cache, decompressed under a
#     temporary name, its parameters file last (what marks a bed complete: src-ext/bed.hpp);
#   - a bed build's latest checkpoint (bed-KEY.building.ckpt-PHASE-CHUNK-SETTLED.restart.xz) into
#     the cache, unless that bed or that checkpoint is there already (ensure_bed resumes the
#     build from the latest checkpoint it finds);
#   - an impact's work folder in flight (impact-ID.gen-G.tar.xz: checkpoint.json, its restart and
#     the track so far, with their paths from the results folder) into the results folder, unless
#     that work folder holds a checkpoint already (the archive ends with checkpoint.json, which is
#     what makes a checkpoint current: src-ext/impact_checkpoint.hpp).
# Nothing lands under its final name incomplete; a file that cannot be read is left out (the bed
# is then built, the impact run, from the start).
#
#   scripts/seed-shipped.sh SHIPPED_DIR RESULTS_DIR CACHE_DIR
#   e.g. scripts/seed-shipped.sh data/resolved/beds/wall-stiffness-1.5e10 \
#          results/wall-stiffness-1.5e10 results/wall-stiffness-1.5e10/dem-cache
#
# scripts/stiffness-plateau.sh calls it before every campaign it starts. Prints a line per file
# seeded; exit 0 (also when SHIPPED_DIR does not exist), 2 on a wrong call.
set -uo pipefail
if [ $# -ne 3 ]; then
  echo "usage: $0 SHIPPED_DIR RESULTS_DIR CACHE_DIR" >&2
  exit 2
fi
SHIPPED=$1
OUT=$2
CACHE=$3
for params in "$SHIPPED"/bed-*.params; do
  [ -f "$params" ] || continue
  bed=$CACHE/$(basename "$params" .params)
  [ -f "$bed.params" ] && continue
  mkdir -p "$CACHE"
  if xz -dc "${params%.params}.restart.xz" > "$bed.restart.seeding"; then
    mv "$bed.restart.seeding" "$bed.restart" && cp "$params" "$bed.params"
    echo "seeded the bed $(basename "$bed") from the shipped copy"
  else
    rm -f "$bed.restart.seeding"
    echo "could not seed $(basename "$bed") from the shipped copy: it will be built"
  fi
done
for ckpt in "$SHIPPED"/bed-*.building.ckpt-*.restart.xz; do
  [ -f "$ckpt" ] || continue
  name=$(basename "$ckpt" .xz)
  if [ -f "$CACHE/${name%%.building.*}.params" ] || [ -f "$CACHE/$name" ]; then continue; fi
  mkdir -p "$CACHE"
  if xz -dc "$ckpt" > "$CACHE/$name.seeding"; then
    mv "$CACHE/$name.seeding" "$CACHE/$name"
    echo "seeded the bed build's checkpoint $name from the shipped copy"
  else
    rm -f "$CACHE/$name.seeding"
    echo "could not seed $name from the shipped copy: the build starts afresh"
  fi
done
for work in "$SHIPPED"/impact-*.tar.xz; do
  [ -f "$work" ] || continue
  json=$(tar -tJf "$work" 2> /dev/null | grep '/checkpoint\.json$')
  if [ -z "$json" ] || [ -f "$OUT/$json" ]; then continue; fi
  mkdir -p "$OUT"
  if tar -xJf "$work" -C "$OUT"; then
    echo "seeded the impact in flight $(dirname "$json") from $(basename "$work")"
  else
    rm -f "$OUT/$json"
    echo "could not seed $(basename "$work"): the impact starts afresh"
  fi
done
exit 0
