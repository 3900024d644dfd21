# shellcheck shell=bash
# Sourced, not run. The tests' grains and grain-block law (tests/dem/dem_support.hpp, kTestBed:
# 4-6 mm, E_grain 2e8 Pa) on a bed as long as the sand campaigns' end-wall reruns, 1.5 x 0.10 x
# 0.10 m (19,322 grains, bed ce736ecc63716c37): the bed of benchmarks/active-zone/run.sh and
# scripts/body-id-check.sh, `dem bed` and `dem impact` arguments.
# shellcheck disable=SC2034  # the sourcing script's
LONG_TEST_BED=(--set bed.Lx_m=1.5 --set bed.Ly_m=0.1 --set bed.H_m=0.1 --set bed.r1_m=0.004
  --set bed.r2_m=0.005 --set bed.r3_m=0.006 --set bed.E_grain_Pa=2e8 --set bed.e_gg=0.7
  --set bed.mu_gg=0.8 --set bed.mur_gg=0.5 --set bed.mu_pour=0.1 --set bed.rolling_model=epsd2)
# shellcheck disable=SC2034
LONG_TEST_BLOCK=(--set block.mu_gb=0.5 --set block.mur_gb=0.1)
