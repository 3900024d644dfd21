#!/usr/bin/env bash
# The verdict of the active zone's paired check at a campaign's own settings (docs/resolved-model.md,
# "Active zone", the rule fixed there on 2026-12-05 before any run): the design of
# `scripts/verification-campaign.py --zone-check R` (each lab state twice on one bed, `whole-ID` and
# `zoneR-ID`), run into FILE.h5. The zone passes when
#   - every state ended with the same status on the whole bed and in the zone (rebound and rebound,
#     or the same censoring), and at least 3 states rebounded in both, and
#   - for each V_out component, the mean over those states of |zone - whole bed| is below 0.25 lab
#     sd (`ricochet paired`'s differences, in the lab cylinders' sd: 0.25 sd is the plateau rule's
#     margin, the same as every numerical setting of docs/resolved-model.md must meet).
#
#   scripts/active-zone-verdict.sh DIR NAME FILE.h5 R [RICOCHET]
#
# DIR: the campaign's folder (its pinned/ program, decks and design NAME.toml, as
# scripts/stiffness-plateau.sh leaves them); RICOCHET: the program that reads the file (default
# build/cli/ricochet). Prints one JSON document: `active_zone_m` (R when it passed, else 0: what
# the campaigns after it use), `passed`, `pairs`, `mean_abs_lab_sd` per component, `statuses`.
# Exit 2 when the campaign still has impacts to run (no verdict yet), 0 otherwise.
#
# The triangles' check (amended on 2026-12-06, docs/resolved-model.md "Active zone") takes its
# whole-bed arm from the blind design itself, whose ids carry no prefix of their own; four
# variables (environment, optional) say so, and the rule is the same:
#   ZONE_BASE=T                            the whole-bed arm's id prefix (default whole-)
#   ZONE_BASE_NAME=sand-blind-triangles-1.5e9   the pinned design of that arm (default NAME)
#   ZONE_BASE_ONLY=T01,T02,T03             its impacts in the check (`dem campaign --only`)
#   ZONE_ONLY=zone0.3-T01,...              the zone arm's impacts in NAME (`--only`)
# A state's key is its whole-bed id without ZONE_BASE; its zone id is zoneR- followed by that id
# for the triangles (ZONE_BASE not whole-), zoneR- followed by the key otherwise.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
[ $# -ge 4 ] || { echo "usage: $0 DIR NAME FILE.h5 R [RICOCHET]" >&2; exit 2; }
DIR=$1 NAME=$2 FILE=$3 R=$4
BIN=${5:-$ROOT/build/cli/ricochet}
BASE=${ZONE_BASE:-whole-}
# The dry run of pinned design $1 on FILE (its impacts in --only $2 when given).
dry_run() {
  local only=()
  if [ -n "$2" ]; then only=(--only "$2"); fi
  (cd "$DIR" && pinned/ricochet dem campaign "pinned/$1.toml" --decks pinned/liggghts-inputs \
    "${only[@]}" --out "$FILE" --dry-run --json)
}
plan=$(dry_run "$NAME" "${ZONE_ONLY:-}")
base_plan=$plan
if [ -n "${ZONE_BASE_NAME:-}" ]; then base_plan=$(dry_run "$ZONE_BASE_NAME" "${ZONE_BASE_ONLY:-}"); fi
for p in "$plan" "$base_plan"; do
  if [ "$(jq .to_run <<< "$p")" != 0 ]; then
    echo "active-zone-verdict: $FILE: $(jq .to_run <<< "$p") impacts of $(jq -r .name <<< "$p")" \
      "still to run" >&2
    exit 2
  fi
done
prefix="zone$(awk -v r="$R" 'BEGIN { printf "%g", r }')-"
against=$prefix
if [ "$BASE" != whole- ]; then against=$prefix$BASE; fi
paired=$("$BIN" paired "$FILE" --base "$BASE" --against "$against" --json)
jq -n --argjson plan "$plan" --argjson base_plan "$base_plan" --argjson paired "$paired" \
  --argjson r "$R" --arg zone "$against" --arg base "$BASE" '
  (($plan.impacts + $base_plan.impacts) | map({(.id): .status}) | add) as $st
  | [$st | keys[] | select(startswith($base) and (startswith($zone) | not)) | ltrimstr($base)]
    as $keys
  | ($keys | map(select($st[$base + .] != $st[$zone + .])) | length) as $changed
  | $paired.pairs as $p
  | ([0, 1, 2] | map(. as $c | if ($p | length) > 0
                                 then ($p | map(.difference[$c] | fabs) | add / length) else null end)) as $m
  | (($changed == 0) and (($p | length) >= 3) and ($m | all(. != null and . < 0.25))) as $ok
  | {active_zone_m: (if $ok then $r else 0 end), passed: $ok, zone_m: $r, pairs: ($p | length),
     states: ($keys | length), status_changed: $changed,
     mean_abs_lab_sd: {vout_x: $m[0], vout_y: $m[1], wout: $m[2]},
     rule: "same status in every state, >= 3 rebounds in both, mean |zone - whole| < 0.25 lab sd per component",
     statuses: $st}'
