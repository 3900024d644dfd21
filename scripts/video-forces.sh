#!/usr/bin/env bash
# Issue 33, item 1: forces from video. A LIGGGHTS campaign's impacts (their recorded tracks are
# the truth) are filmed as a lab camera would (tests/detection/film_tracks: a frame rate,
# Gaussian pointing noise on the centre and an eccentric mark, a random phase), `ricochet
# reconstruct --track-forces` turns each film back into a contact force with standard errors,
# film_tracks --compare measures that force against the recorded one, and `ricochet diagnose`
# discovers the force law from the films as it does from the recorded tracks.
#
#   [SEEDS="3301 ..."] scripts/video-forces.sh BUILD_DIR OUT_DIR [SOURCE.h5]
#
# SOURCE defaults to data/resolved/lab-cylinders.h5 (the 28 lab cylinder states on the first
# resolved bed, tracks every 0.2 ms). The grid (frame rate x pointing noise x half window) and
# the seeds (3301-3305: the films' noise and phase) are fixed here before the first run. Writes
# OUT_DIR/summary.tsv (one line per seed and setting; the first the recorded tracks themselves),
# OUT_DIR/by-setting.tsv (medians over the seeds, and in how many seeds the discovered normal law
# has each term of the recorded tracks' law) and the per-setting files. About 4 s per setting
# and seed on 2 cores (16 settings x 5 seeds: 5 min).
set -euo pipefail
BUILD=$(cd "$1" && pwd)
OUT=$2
HERE=$(cd "$(dirname "$0")/.." && pwd)
SOURCE=${3:-$HERE/data/resolved/lab-cylinders.h5}
FILM=$BUILD/tests/detection/film_tracks
RICOCHET=$BUILD/cli/ricochet
for b in "$FILM" "$RICOCHET"; do
  [ -x "$b" ] || { echo "no $b: build the targets film_tracks and ricochet" >&2; exit 2; }
done
mkdir -p "$OUT"
read -r -a SEED_LIST <<< "${SEEDS:-3301 3302 3303 3304 3305}"
summary=$OUT/summary.tsv
printf "seed\tfps\tnoise_m\thalf_window\tspan_ms\treleases\tcontact_frames\trms_error_fcy_N\tmedian_se_fcy_N\trms_z\twithin_2se\tpeak_ratio\tnormal_law\tnormal_heldout_rms_N\n" > "$summary"
law_of() {  # the normal component's terms and held-out rms from a diagnose JSON
  python3 - "$1" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
law = next((l for l in d["force_law"]["laws"] if l["component"] == "normal"), None)
terms = ",".join(f"{t['name']}={t['coefficient']:.4g}{t['unit'].replace(' ', '')}" for t in law["terms"]) or "-"
print(f"{terms}\t{law['heldout_rms']:.4g}")
PY
}
"$RICOCHET" diagnose "$SOURCE" --seed "${SEED_LIST[0]}" --json > "$OUT/diagnose-recorded.json"
printf -- "-\trecorded\t0\t-\t-\t-\t-\t-\t-\t-\t-\t-\t%s\n" "$(law_of "$OUT/diagnose-recorded.json")" >> "$summary"
for SEED in "${SEED_LIST[@]}"; do
for fps in 400 1000 2000 5000; do
  for noise in 1e-3 2e-4; do
    for k in 2 4; do
      tag=seed$SEED-fps$fps-noise$noise-k$k
      rm -rf "${OUT:?}/$tag" "$OUT/$tag.h5"
      "$FILM" "$SOURCE" "$OUT/$tag" --radius 0.08 --fps "$fps" --noise-m "$noise" --seed "$SEED" > /dev/null
      "$RICOCHET" reconstruct "$OUT/$tag"/*.csv --shape cylinder --track-forces --smooth "$k" \
        --sigma-position "$noise" --out "$OUT/$tag.h5" --json > "$OUT/reconstruct-$tag.json"
      "$FILM" "$SOURCE" --compare "$OUT/$tag.h5" --json > "$OUT/compare-$tag.json"
      "$RICOCHET" diagnose "$OUT/$tag.h5" --seed "$SEED" --json > "$OUT/diagnose-$tag.json"
      python3 - "$OUT/compare-$tag.json" "$fps" "$noise" "$k" "$(law_of "$OUT/diagnose-$tag.json")" "$SEED" >> "$summary" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
fps, noise, k, law, seed = float(sys.argv[2]), sys.argv[3], int(sys.argv[4]), sys.argv[5], sys.argv[6]
print(f"{seed}\t{fps:g}\t{noise}\t{k}\t{1e3 * 2 * k / fps:.3g}\t{c['releases']}\t{c['contact_frames']}\t"
      f"{c['rms_error_fcy_N']:.4g}\t{c['median_se_fcy_N']:.4g}\t{c['rms_z']:.3g}\t"
      f"{c['within_2se']:.3g}\t{c['median_peak_ratio']:.3g}\t{law}")
PY
      rm -rf "${OUT:?}/$tag"  # the films are reproducible from the seed
      tail -n 1 "$summary"
    done
  done
done
done
python3 - "$summary" > "$OUT/by-setting.tsv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1]), delimiter="\t"))
recorded = [t.split("=")[0] for t in rows[0]["normal_law"].split(",") if t != "-"]
groups = {}
for r in rows[1:]:
    groups.setdefault((r["fps"], r["noise_m"], r["half_window"]), []).append(r)
cols = ["rms_error_fcy_N", "median_se_fcy_N", "rms_z", "within_2se", "peak_ratio", "normal_heldout_rms_N"]
print("fps\tnoise_m\thalf_window\tspan_ms\tseeds\t" + "\t".join("median_" + c for c in cols) + "\t"
      + "\t".join(f"seeds_with_{t}" for t in recorded) + "\tseeds_with_other_terms")
for (fps, noise, k), g in groups.items():
    med = [statistics.median(float(r[c]) for r in g) for c in cols]
    names = [[t.split("=")[0] for t in r["normal_law"].split(",") if t != "-"] for r in g]
    found = [sum(t in n for n in names) for t in recorded]
    other = sum(any(t not in recorded for t in n) for n in names)
    print(f"{fps}\t{noise}\t{k}\t{g[0]['span_ms']}\t{len(g)}\t" + "\t".join(f"{v:.3g}" for v in med)
          + "\t" + "\t".join(str(f) for f in found) + f"\t{other}")
PY
cat "$OUT/by-setting.tsv"
