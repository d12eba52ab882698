#!/usr/bin/env bash
# Fuzzes fairfit's readers with libFuzzer (cargo-fuzz targets, nightly toolchain).
#   fuzz/run.sh [SECONDS_PER_TARGET] [TARGET...]      (default: 60 s, every target)
#   FUZZ_BUILD_ONLY=1 fuzz/run.sh                      (build the targets and the corpus, run nothing)
#   FUZZ_PARALLEL=1 fuzz/run.sh 3600                   (every target at once, each logging to
#                                                      fuzz/logs/TARGET.log; for a long unattended run)
# Each target starts from a seed corpus made from the repository's data (fuzz/corpus/TARGET, not
# committed: rebuilt here, kept between runs so a long run grows it). A crash, a panic, an allocation
# over 256 MB, an RSS over 2 GB or an input taking over 10 s stops the target and leaves the input in
# fuzz/artifacts/TARGET/. With `cargo fuzz` installed it is used; without it the targets are built with
# `cargo build` and libfuzzer-sys's own flags (the same instrumentation cargo-fuzz passes, no sanitizer),
# on the nightly toolchain when there is one and otherwise on the default (stable) one: the flags need
# no nightly feature. Exit status: 0 when every target ran its time without a finding.
set -euo pipefail
cd "$(dirname "$0")"
secs=${1:-60}
shift || true
all=(points_csv sections_xyz json mesh_ply mesh_stl mesh_obj step iges)
if [ $# -gt 0 ]; then targets=("$@"); else targets=("${all[@]}"); fi

seed() { # seed TARGET DIR EXT...: copy the repository's files with those extensions into the corpus
  local t=$1 d=$2
  shift 2
  mkdir -p "corpus/$t"
  for e in "$@"; do
    find "../$d" -type f -iname "*.$e" -size -1024k -exec cp -n {} "corpus/$t/" \;
  done
}
seed points_csv examples/data csv dat txt
seed sections_xyz examples/data csv xyz
seed json crates/fairfit/tests/data json
seed json examples json
cp -n seeds/*.json corpus/json/
seed step crates/fairfit/tests/data step stp
seed iges crates/fairfit/tests/data igs iges
for m in ply stl obj; do
  mkdir -p "corpus/mesh_$m"
  cp -n seeds/*."$m" "corpus/mesh_$m/"
done

flags=(-max_total_time="$secs" -malloc_limit_mb=256 -rss_limit_mb=2048 -timeout=10 -max_len=1048576
       -print_final_stats=1)
if cargo +nightly fuzz --version >/dev/null 2>&1; then
  if [ "${FUZZ_BUILD_ONLY:-0}" = 1 ]; then exec cargo +nightly fuzz build --release; fi
  for t in "${targets[@]}"; do
    mkdir -p "artifacts/$t"
    cargo +nightly fuzz run --release "$t" "corpus/$t" -- -artifact_prefix="artifacts/$t/" "${flags[@]}"
  done
else
  export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing -Cdebug-assertions -Coverflow-checks"
  toolchain=()
  if cargo +nightly --version >/dev/null 2>&1; then toolchain=(+nightly); fi
  cargo "${toolchain[@]}" build --release --bins --target x86_64-unknown-linux-gnu
  if [ "${FUZZ_BUILD_ONLY:-0}" = 1 ]; then exit 0; fi
  if [ "${FUZZ_PARALLEL:-0}" = 1 ]; then
    mkdir -p logs
    for t in "${targets[@]}"; do
      mkdir -p "artifacts/$t"
      "target/x86_64-unknown-linux-gnu/release/$t" "corpus/$t" -artifact_prefix="artifacts/$t/" \
        "${flags[@]}" >"logs/$t.log" 2>&1 &
    done
    status=0
    for t in "${targets[@]}"; do wait -n || status=1; done
    exit $status
  fi
  for t in "${targets[@]}"; do
    mkdir -p "artifacts/$t"
    "target/x86_64-unknown-linux-gnu/release/$t" "corpus/$t" -artifact_prefix="artifacts/$t/" "${flags[@]}"
  done
fi
