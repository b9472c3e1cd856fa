#!/bin/sh
# SPDX-License-Identifier: MIT
# run_fuzzer.sh TARGET WORKDIR SECONDS SEED CORPUS REGRESSIONS: runs a libFuzzer target for SECONDS on
# its committed corpus and regressions, writing new inputs and any crash to WORKDIR (never to the
# committed corpus). Exits non-zero on a crash, leak, sanitizer report or an input over 1 s.
set -eu
target=$1 work=$2 seconds=$3 seed=$4 corpus=$5 regressions=$6
mkdir -p "$work/new" "$work/artifacts"
set -- "$work/new" "$corpus"
[ -d "$regressions" ] && set -- "$@" "$regressions"
# -timeout: per input. 5 s, not 1: under ASan a service request that builds a random pallet of up
# to 31 layers (POST /pallet/random without a seed draws one) took 0.14-0.81 s over six runs of
# one input and once crossed 1 s (10 ms in a release build); a hang still ends the run.
exec "$target" -max_total_time="$seconds" -seed="$seed" -timeout=5 -rss_limit_mb=2560 -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$work/artifacts/" "$@"
