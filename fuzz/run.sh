#!/usr/bin/env bash
# Run the scene_parser fuzz target for a bounded time and print libFuzzer's stats.
#   fuzz/run.sh [SECONDS]      (default 60)
# By default the run keeps going past crashes/OOMs/timeouts (libFuzzer fork mode) so that it
# always lasts SECONDS and collects every artifact under fuzz/artifacts/scene_parser/.
# Env: STOP_ON_CRASH=1 (plain mode: stop at the first finding), SANITIZER (default none;
# "address" also builds), NICE (default 15).
set -euo pipefail
SECONDS_TO_RUN="${1:-60}"
cd "$(dirname "$0")"
FUZZ_DIR="$PWD"
# Only stable Rust is installed: let it accept the nightly-only flags cargo-fuzz passes.
export RUSTC_BOOTSTRAP=1
CORPUS="$FUZZ_DIR/corpus/scene_parser"
ARTIFACTS="$FUZZ_DIR/artifacts/scene_parser"
mkdir -p "$CORPUS" "$ARTIFACTS"
# Seed corpus: the shipped scenes.
for f in "$FUZZ_DIR"/../assets/scenes/*.ron; do
    cp -f "$f" "$CORPUS/seed_$(basename "$f")"
done
if [ "${STOP_ON_CRASH:-0}" = 1 ]; then
    MODE=()
else
    MODE=(-fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1)
fi
LOG="$FUZZ_DIR/fuzz-$(date +%Y%m%d-%H%M%S).log"
BEFORE=$(ls "$ARTIFACTS" | sort)
echo "corpus before: $(ls "$CORPUS" | wc -l) files; log: $LOG"
set +e
nice -n "${NICE:-15}" cargo fuzz run \
    --fuzz-dir "$FUZZ_DIR" --target-dir "$FUZZ_DIR/target" -s "${SANITIZER:-none}" \
    scene_parser "$CORPUS" -- \
    -max_total_time="$SECONDS_TO_RUN" -timeout=10 -rss_limit_mb=2048 -max_len=8192 \
    -dict="$FUZZ_DIR/scene.dict" -artifact_prefix="$ARTIFACTS/" -print_final_stats=1 \
    "${MODE[@]}" 2>&1 | tee "$LOG"
rc=${PIPESTATUS[0]}
set -e
echo "---- summary ----"
# Last status line: plain mode "#N ... cov: ft: corp: exec/s:", fork mode "#N: cov: ... oom/timeout/crash:".
grep -E '^#[0-9]+:? ' "$LOG" | grep -E 'cov:' | tail -1 || true
grep -E '^stat::|^INFO: exiting' "$LOG" || true
echo "corpus after: $(ls "$CORPUS" | wc -l) files, $(du -sh "$CORPUS" | cut -f1)"
comm -13 <(echo "$BEFORE") <(ls "$ARTIFACTS" | sort) | sed 's/^/new artifact: /'
echo "exit status: $rc"
exit "$rc"
