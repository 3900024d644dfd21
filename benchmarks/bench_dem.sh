#!/usr/bin/env bash
# Resolved-model benchmark (issue 5, "Cost"): called by scripts/bench.sh (section dem).
#   benchmarks/bench_dem.sh BUILD_DIR OUT_DIR
# 1. Cost of the impact deck in microseconds per grain and step, on 1 and 2 MPI ranks, on the
#    default quasi-2-D bed (0.6 x 0.10 x 0.10 m, grains of 3-5 mm radius, about 16,000 grains),
#    against LIGGGHTS alone on the same settled bed (benchmarks/bench_dem_plain.in).
# 2. Where the impact deck's extra cost goes: both runs profiled with perf, by category.
# 3. Campaign scaling: 4 impacts on the small test bed with 1 rank, then with 2 ranks (2 LIGGGHTS
#    instances side by side); efficiency = T(1) / (2 T(2)).
# The bed is cached in OUT_DIR/dem-cache (built once, about 3 min on 2 ranks). The machine's other
# load shows in the figures: run it on an idle machine.
set -euo pipefail
BUILD=$(cd "$1" && pwd)
OUT=$2
ROOT=$(cd "$(dirname "$0")/.." && pwd)
R="$BUILD/cli/ricochet"
MPI="mpirun --oversubscribe --allow-run-as-root"
CACHE="$OUT/dem-cache"
WORK="$OUT/dem-work"
mkdir -p "$CACHE" "$WORK"
STEPS=${DEM_BENCH_STEPS:-2000}
T_IMPACT=${DEM_BENCH_T:-0.04}

# The bench's bed: set H on the 0.6 x 0.10 x 0.10 m slab (about 16,000 grains; the decks' defaults
# until the calibrated bed replaced them), pinned so that the ratios stay comparable across runs.
BED_SET=(--set bed.Lx_m=0.6 --set bed.Ly_m=0.10 --set bed.r2_m=0.004 --set bed.r3_m=0.005
         --set bed.E_grain_Pa=2e8 --set bed.e_gg=0.7 --set bed.mu_gg=0.8 --set bed.mur_gg=0.5
         --set bed.mu_pour=0.1 --set bed.rolling_model=epsd2)
BLOCK_SET=(--set block.mu_gb=0.5 --set block.mur_gb=0.1)  # `dem bed` takes bed.* only
echo "-- bench bed, set H (cached in $CACHE)"
$MPI -np 2 "$R" dem bed --cache "$CACHE" "${BED_SET[@]}" --json > "$OUT/dem-bed.json"
PREFIX=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['prefix'])" "$OUT/dem-bed.json")

plain() {  # ranks -> "wall_us_per_grain_step core_us_per_grain_step"
  local np=$1 log="$WORK/plain-$1.log"
  local cpu
  cpu=$( { /usr/bin/time -f "%U %S" bash -c "cd '$WORK' && $MPI -np $np liggghts -in '$ROOT/benchmarks/bench_dem_plain.in' \
      -var bed '$PREFIX' -var common '$ROOT/liggghts-inputs/common' -var steps $STEPS \
      -log '$log' -screen '$WORK/plain-$np.screen' > /dev/null" ; } 2>&1 | tail -1)
  python3 - "$log" "$cpu" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
loops = re.findall(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)
t, procs, steps, atoms = loops[-1]
user, system = (float(x) for x in sys.argv[2].split())
n = int(steps) * int(atoms)
print(f"{1e6 * float(t) / n:.4f} {1e6 * (user + system) / n:.4f}")
PY
}

impact() {  # ranks -> json file
  local np=$1
  $MPI -np "$np" "$R" dem impact --json --cache "$CACHE" --work "$WORK" --id "bench-$np" \
      "${BED_SET[@]}" "${BLOCK_SET[@]}" --set run.t_max_s="$T_IMPACT" > "$WORK/impact-$np.json"
  echo "$WORK/impact-$np.json"
}

echo "== Resolved model: cost per grain and step (impact deck vs LIGGGHTS alone on the same bed)"
P1=$(plain 1); P2=$(plain 2)
I1=$(impact 1); I2=$(impact 2)
python3 - "$P1" "$P2" "$I1" "$I2" "$OUT/dem.json" <<'PY'
import json, os, sys
p1, p2 = ([float(x) for x in a.split()] for a in sys.argv[1:3])
i1, i2 = (json.load(open(f)) for f in sys.argv[3:5])
def cost(j):
    n = j["steps"] * (j["grains"] + j["block_spheres"])
    return 1e6 * j["wall_s"] / n, 1e6 * j["cpu_s"] / n
c1, c2 = cost(i1), cost(i2)
print(f"load average during the run: {os.getloadavg()[0]:.1f} (2 cores; other load inflates wall times)")
print(f"plain LIGGGHTS, settled bed of {i1['grains']} grains, wall: "
      f"{p1[0]:.3f} us/grain/step on 1 rank, {p2[0]:.3f} on 2 ranks; CPU: {p1[1]:.3f} and "
      f"{p2[1]:.3f} core-us/grain/step")
print(f"impact deck ({i1['block_spheres']}-sphere cylinder, {i1['steps']} steps, status "
      f"{i1['status']}): wall {c1[0]:.3f} us/grain/step on 1 rank, {c2[0]:.3f} on 2 ranks "
      f"(speed-up {c1[0] / c2[0]:.2f}); CPU {c1[1]:.3f} and {c2[1]:.3f} core-us/grain/step; "
      f"ratio to plain LIGGGHTS (CPU) {c1[1] / p1[1]:.2f} (1 rank), {c2[1] / p2[1]:.2f} (2 ranks); "
      f"target <= 1 us/grain/step on one core: {'met' if c1[0] <= 1.0 else 'NOT met'}")
json.dump({"plain_wall_cpu_us_per_grain_step": [p1, p2],
           "impact_wall_cpu_us_per_grain_step": [c1, c2],
           "grains": i1["grains"], "block_spheres": i1["block_spheres"], "steps": i1["steps"]},
          open(sys.argv[5], "w"), indent=2)
PY

echo "== Resolved model: where the impact deck's extra cost goes (perf, one rank, same bed and steps)"
# Issue 13, item 3: the impact deck against LIGGGHTS alone, profiled with perf (sampling, self
# time per symbol); each symbol is put in one category by its name, and a category's cost is its
# share of the samples times the run's CPU per grain and step (part 1). Skipped without perf.
if command -v perf > /dev/null && perf record -q -o /dev/null true 2> /dev/null; then
  perf record -q -F 999 -o "$WORK/plain.perf" -- $MPI -np 1 liggghts \
      -in "$ROOT/benchmarks/bench_dem_plain.in" -var bed "$PREFIX" \
      -var common "$ROOT/liggghts-inputs/common" -var steps "$STEPS" \
      -log "$WORK/plain-perf.log" -screen none > /dev/null 2>&1
  perf record -q -F 999 -o "$WORK/impact.perf" -- $MPI -np 1 "$R" dem impact --cache "$CACHE" \
      --work "$WORK" --id bench-perf "${BED_SET[@]}" "${BLOCK_SET[@]}" \
      --set run.t_max_s="$T_IMPACT" --json > "$WORK/impact-perf.json" 2> /dev/null
  for k in plain impact; do
    perf report -q -i "$WORK/$k.perf" --no-children --sort dso,symbol --stdio 2> /dev/null \
      > "$WORK/$k.perf.txt"
  done
  python3 - "$WORK/plain.perf.txt" "$WORK/impact.perf.txt" "$OUT/dem.json" "$OUT/dem-profile.json" <<'PY'
import json, re, sys
# First match wins: LIGGGHTS 3.8 class and function names.
CATEGORIES = [
    ("block insertion (the template's volume weights, once per impact)", r"FixTemplateMultisphere|FixTemplateMultiplespheres"),
    ("multisphere body (forces, torques, integration of the block)", r"[Mm]ultisphere"),
    ("neighbour lists (rebuilds, exclusion of the block's own pairs)", r"Neigh|NPair|NBin|NStencil|bin_atoms|coord2bin"),
    ("walls (fix wall/gran)", r"FixWall|Walls::|TriMesh|FixMesh"),
    ("grain contacts (pair gran: normal, tangential, rolling)", r"PairGran|PairStyles|ContactModel|Granular"),
    ("integration of the grains (nve/sphere, gravity)", r"FixNVE|FixGravity"),
    ("computes, variables and stop checks (fix print, thermo, reduce, check/timestep)", r"Compute|Variable|Input::|Thermo|FixPrint|FixCheck|FixAve"),
    ("communication (MPI, ghosts)", r"Comm|MPI|mca_|opal_|ompi_|pmix|ucp_|btl"),
    ("memory, kernel and libc", r"\[kernel|kallsyms|memcpy|memset|malloc|free|_int_|__libc|memmove|libc"),
]
def load(path):
    shares = {}
    for line in open(path):
        m = re.match(r"\s*([0-9.]+)%\s+(\S+)\s+\[[.k]\]\s+(.*)", line)
        if not m:
            continue
        pct, dso, sym = float(m.group(1)), m.group(2), m.group(3).strip()
        cat = next((c for c, rx in CATEGORIES if re.search(rx, sym) or re.search(rx, dso)), "other")
        shares[cat] = shares.get(cat, 0.0) + pct / 100.0
    return shares
plain, impact = load(sys.argv[1]), load(sys.argv[2])
dem = json.load(open(sys.argv[3]))
cpu_plain = dem["plain_wall_cpu_us_per_grain_step"][0][1]
cpu_impact = dem["impact_wall_cpu_us_per_grain_step"][0][1]
print(f"CPU per grain and step, one rank: plain {cpu_plain:.3f} us, impact deck {cpu_impact:.3f} us "
      f"(ratio {cpu_impact / cpu_plain:.2f}); by category (us per grain and step, share of samples):")
rows = []
for cat in [c for c, _ in CATEGORIES] + ["other"]:
    a, b = plain.get(cat, 0.0) * cpu_plain, impact.get(cat, 0.0) * cpu_impact
    rows.append({"category": cat, "plain_us": a, "impact_us": b, "extra_us": b - a})
rows.sort(key=lambda r: -r["extra_us"])
for r in rows:
    print(f"  {r['category']}: plain {r['plain_us']:.3f}, impact {r['impact_us']:.3f}, "
          f"extra {r['extra_us']:+.3f} ({r['extra_us'] / (cpu_impact - cpu_plain):+.0%} of the difference)"
          if cpu_impact > cpu_plain else
          f"  {r['category']}: plain {r['plain_us']:.3f}, impact {r['impact_us']:.3f}")
json.dump({"cpu_us_per_grain_step": {"plain": cpu_plain, "impact": cpu_impact}, "categories": rows},
          open(sys.argv[4], "w"), indent=2)
PY
else
  echo "perf not available or not permitted (kernel.perf_event_paranoid): profile skipped"
fi

echo "== Resolved model: campaign scaling, 4 impacts on the small test bed, 1 vs 2 ranks"
DESIGN="$WORK/scaling.toml"
cat > "$DESIGN" <<EOF
[campaign]
name = "scaling"
cache_dir = "$CACHE"
work_dir = "$WORK/scaling"
[bed]
Lx_m = 0.6
Ly_m = 0.06
H_m = 0.06
r1_m = 0.004
r2_m = 0.005
r3_m = 0.006
[design]
incident = [[2.9, -2.3, -65.0], [2.7, -2.4, -70.0], [3.1, -2.2, -60.0], [2.9, -2.5, -65.0]]
EOF
# The bed first (not timed), then the same 4 impacts from scratch on 1 and on 2 ranks.
$MPI -np 1 "$R" dem impact --cache "$CACHE" --work "$WORK" --id warm --json \
  --set bed.Lx_m=0.6 --set bed.Ly_m=0.06 --set bed.H_m=0.06 --set bed.r1_m=0.004 \
  --set bed.r2_m=0.005 --set bed.r3_m=0.006 --set run.t_max_s=0.001 > /dev/null
for np in 1 2; do
  rm -f "$WORK/scaling-$np.h5"
  $MPI -np "$np" "$R" dem campaign "$DESIGN" --out "$WORK/scaling-$np.h5" --json > "$WORK/scaling-$np.json"
done
python3 - "$WORK/scaling-1.json" "$WORK/scaling-2.json" <<'PY'
import json, sys
a, b = (json.load(open(f)) for f in sys.argv[1:3])
t1, t2 = a["wall_s"], b["wall_s"]
import os
print(f"4 impacts: {t1:.1f} s on 1 rank, {t2:.1f} s on 2 ranks (2 instances): speed-up {t1 / t2:.2f}, "
      f"efficiency {t1 / (2 * t2):.0%}; statuses {a['status_counts']} / {b['status_counts']}; "
      f"load average {os.getloadavg()[0]:.1f}")
PY
