# shellcheck shell=bash
# The sand-only recalibration's calibrate-grains arguments, as the plan fixes them
# (docs/resolved-model.md, "Recalibration with what sand has"): the calibration half of the lab
# cylinders (split seed 3201) as the target, OpenTURNS seed 4, the six sampled grain parameters
# (block.mur_gb is tied to bed.mur_gg, a copy, not an input), the solid-fraction band of sand, and
# the packing of the beds that the file does not record from their grain count (amended on
# 2026-12-02). One place for them: scripts/dem-lanes.sh runs the calibration with them, and
# scripts/main-job.sh repeats it on the shipped file. Sourced; needs ROOT (the checkout) and sets
# SAND_CALIBRATION_ARGS, sand_half and SAND_BLIND_WHERE.
# The --where filter of one half of the lab cylinders' split (calibration or held-out), e.g.
# for the verification's checks against the lab.
sand_half() {
  "$ROOT/scripts/lab-split.py" "$ROOT/data/lab/cylinders.csv" 3201 --where "$1"
}
# The blind triangles' file (data/resolved/sand-blind-triangles-1.5e9.h5) also holds the zone arm
# of their active-zone check (docs/resolved-model.md, "The check on the triangles"), T01-T06
# again in a 0.30 m zone under the prefix zone0.3-: this --where keeps the ids that start with T
# and so leaves those out, so that each lab state is counted once, by its whole-bed or (from T07)
# its zone run. (Until 2026-12-07, before the filters had '^=', it named the six ids with !=.)
# shellcheck disable=SC2034
SAND_BLIND_WHERE="id^=T"
# SC2034: used by the scripts that source it; SC2054: 0.56,0.62 is one argument, LO,HI.
# shellcheck disable=SC2034,SC2054
SAND_CALIBRATION_ARGS=(
  --lab "$ROOT/data/lab/cylinders.csv" --seed 4
  --lab-where "$(sand_half calibration)"
  --parameters bed.mu_gg bed.mur_gg block.mu_gb bed.e_gg block.e_gb bed.mu_pour
  --packing-from-grain-count --solid-fraction 0.56,0.62
)
